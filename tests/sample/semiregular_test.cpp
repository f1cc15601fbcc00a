// semiregular_mesh(): vertex numbering, watertightness, genus and exact
// subdivision connectivity (undone level by level with unsubdivide()).
#include "sample/semiregular.hpp"

#include "domain/domain.hpp"
#include "mesh/mesh_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>

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

}  // namespace
}  // namespace ism
