// bounded_base(): a base with boundary loops closed over the surface's
// boundary vertices (semireg on open surfaces), the decimated open bases it
// starts from (simplify_capped_to), the network traced over it with its cap
// edges given, and refusals of bases whose loops do not match.
#include "partition/bounded_base.hpp"

#include "mesh/boundary.hpp"
#include "open_surfaces.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>

namespace ism {
namespace {

// A sphere open at the top and at one side: two loops.
TriangleMesh two_holed_sphere() {
  return test::keep_faces(shapes::sphere(3000), [](const Vec3& c) {
    return c.z() < 0.6 && (c - Vec3(0.9, 0, 0)).norm() > 0.4;
  });
}

struct OpenCase {
  TriangleMesh surface;
  CappedMesh capped;
  UncappedBase base;
};

OpenCase decimated(std::size_t base_vertices) {
  OpenCase s;
  s.surface = two_holed_sphere();
  s.capped = cap_boundary_loops(s.surface, boundary_loops(s.surface));
  std::vector<int> centres;
  for (std::size_t j = 0; j < s.capped.loops.size(); ++j) centres.push_back(s.capped.centre(j));
  const ProgressiveMesh pm =
      simplify_capped_to(s.capped.mesh, s.capped.loops, centres, base_vertices + centres.size(),
                         {.priority = SimplifyPriority::isotropic});
  s.base = uncapped_base(pm, centres.size());
  return s;
}

Eigen::Vector2d layout_point(const Eigen::Vector3d& b) {
  return b[1] * Eigen::Vector2d(1, 0) + b[2] * Eigen::Vector2d(0.5, std::sqrt(3.0) / 2);
}

double area2(const std::array<Eigen::Vector3d, 3>& c) {
  const Eigen::Vector2d a = layout_point(c[0]), b = layout_point(c[1]), d = layout_point(c[2]);
  return 0.5 * ((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
}

TEST(BoundedBase, DecimatedOpenBaseKeepsTheLoops) {
  const OpenCase s = decimated(30);
  ASSERT_EQ(s.capped.loops.size(), 2u);
  EXPECT_EQ(s.base.mesh.n_vertices(), 30u);
  EXPECT_EQ(boundary_loops(s.base.mesh).size(), 2u);
  // V - E + F = 2 - 2g - b with g = 0, b = 2.
  EXPECT_EQ(euler_characteristic(s.base.mesh), 0);
  // Every base boundary vertex is a surface boundary vertex.
  std::set<int> surface_boundary;
  for (const auto& loop : s.capped.loops) surface_boundary.insert(loop.begin(), loop.end());
  for (const auto& loop : boundary_loops(s.base.mesh))
    for (int v : loop) EXPECT_TRUE(surface_boundary.count(s.base.vertices[v])) << v;
}

TEST(BoundedBase, ClosesTheBaseOverTheSurfaceBoundary) {
  const OpenCase s = decimated(30);
  const BoundedBase b = bounded_base(s.base.mesh, s.base.vertices, s.capped);
  const TriangleMesh& d = b.domain;
  // Closed, genus 0; the base's vertices first with their features.
  EXPECT_TRUE(boundary_loops(d).empty());
  EXPECT_EQ(euler_characteristic(d), 2);
  ASSERT_EQ(b.features.size(), d.n_vertices());
  for (std::size_t i = 0; i < s.base.vertices.size(); ++i)
    EXPECT_EQ(b.features[i], s.base.vertices[i]);
  EXPECT_EQ(std::set<int>(b.features.begin(), b.features.end()).size(), d.n_vertices());
  // Every surface boundary vertex and each centre is a fixed domain vertex.
  std::size_t loop_vertices = 0, fixed = 0;
  for (const auto& loop : s.capped.loops) loop_vertices += loop.size();
  for (char f : b.fixed) fixed += f != 0;
  EXPECT_EQ(fixed, loop_vertices + s.capped.loops.size());
  std::size_t base_boundary = 0;
  for (const auto& loop : boundary_loops(s.base.mesh)) base_boundary += loop.size();
  EXPECT_EQ(b.boundary_points, loop_vertices - base_boundary);
  EXPECT_GT(b.boundary_points, 0u);
  // Inner points (after the boundary points): free, at interior surface
  // vertices, each fanning to the two or more points of one base edge.
  EXPECT_GT(b.inner_points, 0u);
  const std::size_t nb = s.base.vertices.size();
  ASSERT_EQ(d.n_vertices(), nb + b.boundary_points + b.inner_points + s.capped.loops.size());
  std::set<int> loop_set;
  for (const auto& loop : s.capped.loops) loop_set.insert(loop.begin(), loop.end());
  std::vector<std::set<int>> neighbours(d.n_vertices());
  for (const Triangle& t : d.triangles)
    for (int k = 0; k < 3; ++k) neighbours[t[k]].insert(t[(k + 1) % 3]);
  for (std::size_t i = nb + b.boundary_points; i < nb + b.boundary_points + b.inner_points; ++i) {
    EXPECT_FALSE(b.fixed[i]) << i;
    EXPECT_FALSE(loop_set.count(b.features[i])) << i;
    EXPECT_LT(std::size_t(b.features[i]), s.capped.input_vertices) << i;
    std::size_t points = 0;
    for (int w : neighbours[i])
      points += std::size_t(w) >= nb && std::size_t(w) < nb + b.boundary_points;
    EXPECT_GE(points, 2u) << i;
  }

  // Lengths: real triangles. The pieces tile each base face (unit
  // equilateral) without overlap, and their lengths are their layout's.
  ASSERT_EQ(b.lengths.size(), d.n_faces());
  for (const auto& l : b.lengths)
    for (int k = 0; k < 3; ++k) EXPECT_LT(l[k], l[(k + 1) % 3] + l[(k + 2) % 3]);
  ASSERT_EQ(b.pieces.size(), s.base.mesh.n_faces());
  for (std::size_t f = 0; f < b.pieces.size(); ++f) {
    double area = 0;
    for (const auto& piece : b.pieces[f]) {
      EXPECT_GT(area2(piece.corners), 0) << f;
      area += area2(piece.corners);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(
            b.lengths[piece.face][k],
            (layout_point(piece.corners[(k + 1) % 3]) - layout_point(piece.corners[k])).norm(),
            1e-12);
    }
    EXPECT_NEAR(area, std::sqrt(3.0) / 4, 1e-12) << f;
  }
  // Caps: one fan per loop, the angles at each centre at most 2π.
  std::size_t caps = 0;
  for (std::size_t f = 0; f < d.n_faces(); ++f) caps += b.cap_face[f] != 0;
  EXPECT_EQ(caps, loop_vertices);

  // locate(): a base point comes back in one of its face's pieces.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 500; ++i) {
    const int f = int(rng() % s.base.mesh.n_faces());
    Eigen::Vector3d w(u(rng), u(rng), u(rng));
    w /= w.sum();
    const auto [face, at] = b.locate(f, w);
    const auto& pieces = b.pieces[f];
    const auto it =
        std::find_if(pieces.begin(), pieces.end(), [&](const auto& p) { return p.face == face; });
    ASSERT_NE(it, pieces.end());
    EXPECT_NEAR(at.sum(), 1.0, 1e-12);
    EXPECT_GE(at.minCoeff(), 0.0);
    const Eigen::Vector3d back =
        at[0] * it->corners[0] + at[1] * it->corners[1] + at[2] * it->corners[2];
    EXPECT_LT((back - w).norm(), 1e-9);
  }

  // The network over it: the cap edges are the surface's own edges.
  PartitionOptions options;
  options.direct_edges = b.cap_edges();
  EXPECT_EQ(options.direct_edges.size(), 2 * loop_vertices);
  const PathNetwork network = trace_path_network(s.capped.mesh, d, b.features, options);
  std::set<std::array<int, 2>> direct(options.direct_edges.begin(), options.direct_edges.end());
  for (std::size_t e = 0; e < network.domain_edges.size(); ++e)
    if (direct.count(network.domain_edges[e])) EXPECT_EQ(network.paths[e].size(), 2u) << e;
  EXPECT_FALSE(validate_network(network, d).has_value());
}

// The two-holed sphere with an ear on a loop: a boundary vertex with two
// faces loses one, so the face it keeps holds two boundary edges and its
// third edge joins two vertices of the loop (a "bridge").
struct EarCase {
  TriangleMesh surface;
  int tip = -1;
  std::array<int, 2> bridge{-1, -1};
};

EarCase two_holed_sphere_with_an_ear() {
  EarCase e;
  e.surface = two_holed_sphere();
  std::vector<std::vector<int>> faces(e.surface.n_vertices());
  for (std::size_t f = 0; f < e.surface.n_faces(); ++f)
    for (int v : e.surface.triangles[f]) faces[v].push_back(int(f));
  std::vector<char> on_loop(e.surface.n_vertices(), 0);
  for (const auto& loop : boundary_loops(e.surface))
    for (int v : loop) on_loop[v] = 1;
  for (int b = 0; b < int(e.surface.n_vertices()); ++b) {
    if (!on_loop[b] || faces[b].size() != 2) continue;
    // The vertex the two faces share besides b must be interior.
    const Triangle& f0 = e.surface.triangles[faces[b][0]];
    const Triangle& f1 = e.surface.triangles[faces[b][1]];
    int shared = -1, kept_other = -1;
    for (int v : f0)
      if (v != b && std::count(f1.begin(), f1.end(), v)) shared = v;
    for (int v : f0)
      if (v != b && v != shared) kept_other = v;
    if (shared < 0 || on_loop[shared]) continue;
    e.tip = b;
    e.bridge = {std::min(shared, kept_other), std::max(shared, kept_other)};
    e.surface.triangles.erase(e.surface.triangles.begin() + faces[b][1]);
    return e;
  }
  return e;
}

TEST(BoundedBase, AnEarsTipStaysABaseVertex) {
  const EarCase e = two_holed_sphere_with_an_ear();
  ASSERT_GE(e.tip, 0) << "no boundary vertex with two faces on the generated sphere";
  const CappedMesh capped = cap_boundary_loops(e.surface, boundary_loops(e.surface));
  ASSERT_EQ(capped.loops.size(), 2u);
  std::vector<int> centres;
  for (std::size_t j = 0; j < capped.loops.size(); ++j) centres.push_back(capped.centre(j));
  const UncappedBase base =
      uncapped_base(simplify_capped_to(capped.mesh, capped.loops, centres, 30 + centres.size(),
                                       {.priority = SimplifyPriority::isotropic}),
                    centres.size());
  // Without the tip, the base edge over it would put the ear's face on one
  // straight line of the domain.
  const auto tip = std::find(base.vertices.begin(), base.vertices.end(), e.tip);
  ASSERT_NE(tip, base.vertices.end());
  EXPECT_NO_THROW(bounded_base(base.mesh, base.vertices, capped));

  // A given base whose boundary edge spans the ear is refused: the tip's
  // base vertex moved to a loop neighbour of the tip that is no base vertex.
  std::vector<int> moved = base.vertices;
  for (int end : e.bridge)
    if (std::find(moved.begin(), moved.end(), end) == moved.end()) {
      moved[std::size_t(tip - base.vertices.begin())] = end;
      break;
    }
  ASSERT_NE(moved, base.vertices);
  std::string message = "accepted";
  try {
    bounded_base(base.mesh, moved, capped);
  } catch (const PartitionError& x) {
    message = x.what();
  }
  EXPECT_NE(message.find("spans the surface edge"), std::string::npos) << message;
}

TEST(BoundedBase, RefusesBasesWhoseLoopsDoNotMatch) {
  const OpenCase s = decimated(30);
  auto message = [&](const TriangleMesh& base, const std::vector<int>& features) {
    try {
      bounded_base(base, features, s.capped);
    } catch (const PartitionError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // The base turned inside out: its loops run the other way.
  TriangleMesh reversed = s.base.mesh;
  for (Triangle& t : reversed.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(message(reversed, s.base.vertices).find("in another order or direction"),
            std::string::npos)
      << message(reversed, s.base.vertices);
  // One loop closed by a fan: one loop fewer.
  TriangleMesh filled = s.base.mesh;
  const std::vector<int> loop = boundary_loops(filled).front();
  for (std::size_t k = 1; k + 1 < loop.size(); ++k)
    filled.triangles.push_back({loop[0], loop[k], loop[k + 1]});
  EXPECT_NE(message(filled, s.base.vertices).find("the base has 1 boundary loop, the surface 2"),
            std::string::npos)
      << message(filled, s.base.vertices);
  // A boundary vertex of the base on an interior surface vertex.
  std::vector<int> moved = s.base.vertices;
  const int b0 = boundary_loops(s.base.mesh).front().front();
  for (int v = 0; v < int(s.surface.n_vertices()); ++v)
    if (std::find(moved.begin(), moved.end(), v) == moved.end()) {
      bool on_boundary = false;
      for (const auto& l : s.capped.loops) on_boundary |= std::count(l.begin(), l.end(), v) > 0;
      if (!on_boundary) {
        moved[b0] = v;
        break;
      }
    }
  EXPECT_NE(message(s.base.mesh, moved).find("is not on the surface's boundary"), std::string::npos)
      << message(s.base.mesh, moved);
}

}  // namespace
}  // namespace ism
