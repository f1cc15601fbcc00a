// semiregular_mesh(): vertex numbering, watertightness, genus and exact
// subdivision connectivity (undone level by level with unsubdivide()).
#include "sample/semiregular.hpp"

#include "domain/domain.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ism {
namespace {

// The flat point of the base face: the base itself, finely tessellated.
Vec3 flat_point(const TriangleMesh& base, int f, const Eigen::Vector3d& b) {
  const Triangle& t = base.triangles[f];
  return b[0] * base.positions[t[0]] + b[1] * base.positions[t[1]] + b[2] * base.positions[t[2]];
}

MeshCheck check_of(const TriangleMesh& mesh) {
  PolygonSoup soup{mesh.positions, {}};
  for (const auto& t : mesh.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  return prepare_mesh(soup).check;
}

std::vector<Triangle> canonical_faces(const TriangleMesh& mesh) {
  std::vector<Triangle> faces;
  for (Triangle t : mesh.triangles) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    faces.push_back(t);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

void expect_exact_subdivision(const TriangleMesh& base, const TriangleMesh& fine, int levels) {
  TriangleMesh mesh = fine;
  for (int l = levels; l > 0; --l) {
    TriangleMesh coarse;
    ASSERT_TRUE(unsubdivide(mesh, base.n_vertices(), coarse)) << "level " << l;
    EXPECT_EQ(coarse.n_faces() * 4, mesh.n_faces());
    mesh = std::move(coarse);
  }
  EXPECT_EQ(mesh.n_vertices(), base.n_vertices());
  EXPECT_EQ(canonical_faces(mesh), canonical_faces(base));
}

TEST(Semiregular, OctahedronLevelsAreWatertightWithSubdivisionConnectivity) {
  const TriangleMesh base = domain::octahedron();
  for (int levels = 0; levels <= 4; ++levels) {
    SCOPED_TRACE(levels);
    int calls = 0;
    const TriangleMesh mesh = semiregular_mesh(base, levels, [&](int f, const Eigen::Vector3d& b) {
      ++calls;
      EXPECT_NEAR(b.sum(), 1.0, 1e-15);
      return flat_point(base, f, b);
    });
    const std::size_t n = std::size_t(1) << levels;
    EXPECT_EQ(mesh.n_faces(), base.n_faces() * n * n);
    EXPECT_EQ(std::size_t(calls), mesh.n_vertices());
    // V - E + F = 2 with E = 3F/2: V = 2 + F/2.
    EXPECT_EQ(mesh.n_vertices(), 2 + mesh.n_faces() / 2);
    for (std::size_t v = 0; v < base.n_vertices(); ++v)
      EXPECT_EQ(mesh.positions[v], base.positions[v]) << v;
    const MeshCheck c = check_of(mesh);
    EXPECT_TRUE(c.valid_surface());
    EXPECT_TRUE(c.closed());
    EXPECT_EQ(c.genus, 0);
    EXPECT_EQ(c.reoriented_faces, 0u);
    EXPECT_EQ(c.welded_vertices, 0u);
    EXPECT_FALSE(c.flipped_inward);
    // Every sample lies on the face it belongs to: the area is kept.
    EXPECT_NEAR(surface_area(mesh), surface_area(base), 1e-12);
    expect_exact_subdivision(base, mesh, levels);
  }
}

TEST(Semiregular, EdgeSamplesFollowTheEdgeFromItsLowerEndpoint) {
  const TriangleMesh base = domain::octahedron();
  const int levels = 2, n = 4;
  const TriangleMesh mesh = semiregular_mesh(
      base, levels, [&](int f, const Eigen::Vector3d& b) { return flat_point(base, f, b); });
  // Edge 0 is corner 0 -> corner 1 of face 0.
  const int a = std::min(base.triangles[0][0], base.triangles[0][1]);
  const int b = std::max(base.triangles[0][0], base.triangles[0][1]);
  for (int j = 1; j < n; ++j) {
    const Vec3 expected =
        base.positions[a] + (base.positions[b] - base.positions[a]) * double(j) / n;
    EXPECT_LT((mesh.positions[base.n_vertices() + j - 1] - expected).norm(), 1e-15);
  }
}

TEST(Semiregular, TorusBaseKeepsItsGenus) {
  const TriangleMesh base = domain::torus_3x3();
  const TriangleMesh mesh = semiregular_mesh(base, 3, [&](int f, const Eigen::Vector3d& b) {
    // Any injective-enough placement will do for the connectivity.
    return Vec3(f + 0.3 * b[1], 0.3 * b[2], 0.0);
  });
  EXPECT_EQ(mesh.n_faces(), base.n_faces() * 64);
  // V - E + F = 0 with E = 3F/2: V = F/2.
  EXPECT_EQ(mesh.n_vertices(), mesh.n_faces() / 2);
  expect_exact_subdivision(base, mesh, 3);
}

// A base with boundary: the octahedron without two faces (two loops of
// three edges, or one of four when the faces share an edge).
TEST(Semiregular, OpenBasesKeepTheirLoopsAndUnsubdivideExactly) {
  const TriangleMesh octahedron = domain::octahedron();
  auto shared = [&](int f, int g) {
    int n = 0;
    for (int v : octahedron.triangles[f])
      n += int(std::count(octahedron.triangles[g].begin(), octahedron.triangles[g].end(), v));
    return n;
  };
  // Face 0 and a face with no vertex in common; face 0 and one across an edge.
  int far = -1, near = -1;
  for (int g = 1; g < 8; ++g) {
    if (shared(0, g) == 0) far = g;
    if (shared(0, g) == 2) near = g;
  }
  ASSERT_GE(far, 0);
  ASSERT_GE(near, 0);
  for (const std::vector<int>& removed : {std::vector<int>{0, far}, std::vector<int>{0, near}}) {
    TriangleMesh base = octahedron;
    for (auto it = removed.rbegin(); it != removed.rend(); ++it)
      base.triangles.erase(base.triangles.begin() + *it);
    const MeshCheck b = check_of(base);
    ASSERT_TRUE(b.valid_surface());
    ASSERT_GT(b.boundary_loops, 0u);
    for (int levels = 1; levels <= 3; ++levels) {
      SCOPED_TRACE(levels);
      const TriangleMesh mesh = semiregular_mesh(
          base, levels, [&](int f, const Eigen::Vector3d& w) { return flat_point(base, f, w); });
      const MeshCheck c = check_of(mesh);
      EXPECT_TRUE(c.valid_surface());
      EXPECT_EQ(c.boundary_loops, b.boundary_loops);
      EXPECT_EQ(c.genus, 0);
      expect_exact_subdivision(base, mesh, levels);
    }
    // Without its last face the mesh is no subdivision any more.
    TriangleMesh mesh = semiregular_mesh(
        base, 1, [&](int f, const Eigen::Vector3d& w) { return flat_point(base, f, w); });
    mesh.triangles.pop_back();
    TriangleMesh coarse;
    EXPECT_FALSE(unsubdivide(mesh, base.n_vertices(), coarse));
  }
}

TEST(Semiregular, UnsubdivideRefusesMeshesThatAreNotSubdivisions) {
  const TriangleMesh base = domain::octahedron();
  TriangleMesh coarse;
  // The base itself (8 faces) is no 1-to-4 split of anything with vertex 0 even.
  EXPECT_FALSE(unsubdivide(base, 1, coarse));
  TriangleMesh mesh = semiregular_mesh(
      base, 2, [&](int f, const Eigen::Vector3d& b) { return flat_point(base, f, b); });
  ASSERT_TRUE(unsubdivide(mesh, base.n_vertices(), coarse));
  // One edge flip breaks the structure.
  const Triangle t0 = mesh.triangles[0];
  int other = -1, opposite = -1;
  for (std::size_t f = 1; f < mesh.n_faces() && other < 0; ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[f][k] == t0[1] && mesh.triangles[f][(k + 1) % 3] == t0[0])
        other = int(f), opposite = mesh.triangles[f][(k + 2) % 3];
  ASSERT_GE(other, 0);
  mesh.triangles[0] = {t0[2], opposite, t0[1]};
  mesh.triangles[other] = {opposite, t0[2], t0[0]};
  EXPECT_FALSE(unsubdivide(mesh, base.n_vertices(), coarse));
}

// A flat square sampled at level 3 (two faces, or four around a centre
// vertex), one vertex's sample thrown off (a point function that jumps there
// alone): its triangles fold over their neighbours. unfold_semiregular()
// re-samples that vertex nearby, and nothing else.
struct SpikedSquare {
  TriangleMesh base;
  SemiregularLayout layout;
  int spiked = -1;
  Vec3 offset;
  int levels = 3;

  // The vertex sampled at grid point (i, j) of `face`.
  SpikedSquare(bool fan, int face, int i, int j, Vec3 off) : offset(std::move(off)) {
    base.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    base.triangles = {{0, 1, 2}, {0, 2, 3}};
    if (fan) {
      base.positions.push_back(Vec3(0.5, 0.5, 0));
      base.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    }
    layout = semiregular_layout(base, levels);
    for (std::size_t v = 0; v < layout.sites.size(); ++v) {
      const SemiregularSite& s = layout.sites[v];
      if (s.face == face && s.i == i && s.j == j) spiked = int(v);
    }
  }
  Vec3 point(int f, const Eigen::Vector3d& b) const {
    const SemiregularSite& s = layout.sites[std::size_t(spiked)];
    const Vec3 p = flat_point(base, f, b);
    return f == s.face && b == layout.weights(s.i, s.j) ? Vec3(p + offset) : p;
  }
};

TEST(Semiregular, UnfoldResamplesAFoldedVertexNearby) {
  const double step = 1.0 / 8;
  struct Case {
    const char* what;
    bool fan;
    int face, i, j;
    Vec3 offset;
    int boundary_axis;  // -1, or the coordinate that must stay 0 (a boundary)
  };
  const Case cases[] = {
      {"inside face 0, thrown past its neighbour", false, 0, 3, 2, Vec3(1.5 * step, 0, 0), -1},
      {"on the boundary edge y = 0, thrown inwards", false, 0, 4, 0, Vec3(0, 1.5 * step, 0), 1},
      {"base vertex 0, a corner, thrown inside", false, 0, 0, 0, Vec3(0.4, 0.2, 0), -2},
      {"the centre base vertex, thrown", true, 0, 0, 8, Vec3(0.3, 0.05, 0), -1},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const SpikedSquare square(c.fan, c.face, c.i, c.j, c.offset);
    ASSERT_GE(square.spiked, 0);
    const auto point = [&](int f, const Eigen::Vector3d& b) { return square.point(f, b); };
    TriangleMesh mesh = semiregular_mesh(square.base, square.levels, point);
    const TriangleMesh given = mesh;
    const std::size_t folds = flipped_faces(mesh);
    ASSERT_GT(folds, 0u);

    const UnfoldReport r = unfold_semiregular(square.base, square.levels, point, mesh);
    EXPECT_EQ(r.folds_before, folds);
    EXPECT_EQ(r.folds_after, 0u);
    EXPECT_EQ(flipped_faces(mesh), 0u);
    EXPECT_EQ(r.moved_vertices, 1u);
    EXPECT_EQ(mesh.triangles, given.triangles);
    for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
      if (int(v) != square.spiked) {
        EXPECT_EQ(mesh.positions[v], given.positions[v]) << v;
      }
    // Now a plain sample of the square, within three quarters of a grid step
    // (the diagonal one: sqrt 2 steps) of its grid point; on the square's
    // boundary, still on it.
    const Vec3 grid_point = flat_point(square.base, c.face, square.layout.weights(c.i, c.j)),
               p = mesh.positions[std::size_t(square.spiked)];
    EXPECT_EQ(p.z(), 0.0);
    EXPECT_LE((p - grid_point).norm(), 0.75 * std::sqrt(2.0) * step + 1e-12);
    EXPECT_NE(p, grid_point + c.offset);
    if (c.boundary_axis >= 0) {
      EXPECT_EQ(p[c.boundary_axis], 0.0);
    }
    if (c.boundary_axis == -2) {  // the corner: along one of its two sides
      EXPECT_TRUE(p.x() == 0.0 || p.y() == 0.0) << p.transpose();
    }
  }
}

TEST(Semiregular, UnfoldLeavesFoldsWiderThanItsMoves) {
  // A disc of two grid steps' radius thrown sideways as a whole: the
  // triangles across its rim fold, and no sample moved by less than a grid
  // step leaves the disc, so they stay folded.
  const SpikedSquare square(false, 0, 0, 0, Vec3::Zero());
  const auto point = [&](int f, const Eigen::Vector3d& b) {
    const Vec3 p = flat_point(square.base, f, b);
    return (p - Vec3(0.5, 0.3, 0)).norm() < 0.25 ? Vec3(p + Vec3(0.35, 0, 0)) : p;
  };
  TriangleMesh mesh = semiregular_mesh(square.base, square.levels, point);
  const std::size_t folds = flipped_faces(mesh);
  ASSERT_GT(folds, 0u);
  const UnfoldReport r = unfold_semiregular(square.base, square.levels, point, mesh);
  EXPECT_EQ(r.folds_before, folds);
  EXPECT_EQ(r.folds_after, flipped_faces(mesh));
  EXPECT_GT(r.folds_after, 0u);
  EXPECT_LE(r.folds_after, folds);

  TriangleMesh other = semiregular_mesh(square.base, 2, point);
  EXPECT_THROW(unfold_semiregular(square.base, 3, point, other), std::invalid_argument);
}

}  // namespace
}  // namespace ism
