// Boundary loops and the fan caps that close them (paper §4).
#include "mesh/boundary.hpp"

#include "mesh/mesh_check.hpp"
#include "shapes/shapes.hpp"

#include "closed_surface_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace ism {
namespace {

using test::check_of;

// A sphere with the faces around two far apart vertices removed: two holes,
// each with as many vertices as the removed vertex had neighbours
// (`valence`, the same for both: the icosphere is symmetric).
TriangleMesh sphere_with_two_holes(std::size_t& valence) {
  TriangleMesh sphere = shapes::sphere(1280);
  int top = 0, bottom = 0;
  for (std::size_t v = 0; v < sphere.n_vertices(); ++v) {
    if (sphere.positions[v].z() > sphere.positions[top].z()) top = int(v);
    if (sphere.positions[v].z() < sphere.positions[bottom].z()) bottom = int(v);
  }
  std::vector<Triangle> kept;
  valence = 0;
  for (const Triangle& t : sphere.triangles) {
    valence += std::find(t.begin(), t.end(), top) != t.end();
    if (std::find(t.begin(), t.end(), top) == t.end() &&
        std::find(t.begin(), t.end(), bottom) == t.end())
      kept.push_back(t);
  }
  sphere.triangles = kept;
  return sphere;
}

TEST(BoundaryLoops, LoopsRunWithTheSurfaceOnTheirLeft) {
  std::size_t valence = 0;
  const TriangleMesh holed = sphere_with_two_holes(valence);
  const auto loops = boundary_loops(holed);
  ASSERT_EQ(loops.size(), 2u);
  std::set<std::pair<int, int>> directed;
  for (const Triangle& t : holed.triangles)
    for (int k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
  for (const auto& loop : loops) {
    EXPECT_EQ(loop.size(), valence);
    EXPECT_EQ(*std::min_element(loop.begin(), loop.end()), loop.front());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      EXPECT_FALSE(directed.count({a, b}));  // a boundary half-edge
      EXPECT_TRUE(directed.count({b, a}));   // its face holds the other way
    }
    // The ring around a vertex of the unit sphere: a closed polygon shorter
    // than the circle through its vertices, longer than its longest chord.
    double sides = 0, chord = 0, radius = 0;
    Vec3 centre = Vec3::Zero();
    for (int v : loop) centre += holed.positions[v] / double(loop.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      sides += (holed.positions[loop[(k + 1) % loop.size()]] - holed.positions[loop[k]]).norm();
      radius = std::max(radius, (holed.positions[loop[k]] - centre).norm());
      for (int w : loop)
        chord = std::max(chord, (holed.positions[w] - holed.positions[loop[k]]).norm());
    }
    EXPECT_DOUBLE_EQ(loop_length(holed, loop), sides);
    EXPECT_GT(sides, 2 * chord);
    EXPECT_LT(sides, 2 * M_PI * radius);
  }
  EXPECT_TRUE(boundary_loops(shapes::sphere(1280)).empty());
}

TEST(BoundaryLoops, VertexOnTheBoundaryTwiceIsRefused) {
  // Two triangles sharing only a vertex: a bow tie.
  const TriangleMesh bow_tie{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                             {{0, 1, 2}, {0, 3, 4}}};
  EXPECT_THROW(boundary_loops(bow_tie), std::invalid_argument);
}

TEST(CappedMesh, FansCloseEveryLoopIntoAClosedSurfaceOfTheSameGenus) {
  std::size_t valence = 0;
  const TriangleMesh holed = sphere_with_two_holes(valence);
  const auto loops = boundary_loops(holed);
  const CappedMesh capped = cap_boundary_loops(holed, loops);
  EXPECT_EQ(capped.input_vertices, holed.n_vertices());
  EXPECT_EQ(capped.input_faces, holed.n_faces());
  EXPECT_EQ(capped.mesh.n_vertices(), holed.n_vertices() + 2);
  EXPECT_EQ(capped.mesh.n_faces(), holed.n_faces() + 2 * valence);
  for (std::size_t f = 0; f < capped.mesh.n_faces(); ++f) {
    const Triangle& t = capped.mesh.triangles[f];
    const bool has_centre =
        capped.is_centre(t[0]) || capped.is_centre(t[1]) || capped.is_centre(t[2]);
    EXPECT_EQ(capped.is_cap_face(f), has_centre) << f;
  }
  for (std::size_t l = 0; l < loops.size(); ++l) {
    Vec3 centroid = Vec3::Zero();
    for (int v : loops[l]) centroid += holed.positions[v];
    EXPECT_TRUE(
        capped.mesh.positions[capped.centre(l)].isApprox(centroid / double(valence), 1e-12));
  }
  // Input vertices and faces unchanged, in place.
  for (std::size_t v = 0; v < holed.n_vertices(); ++v)
    EXPECT_EQ(capped.mesh.positions[v], holed.positions[v]);
  const MeshCheck c = check_of(capped.mesh);
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.reoriented_faces, 0u);  // the fans follow the surface's orientation
}

TEST(MeshCheck, ListsEachBoundaryLoopWithItsVerticesAndLength) {
  std::size_t valence = 0;
  const TriangleMesh holed = sphere_with_two_holes(valence);
  const MeshCheck c = check_of(holed);
  ASSERT_EQ(c.boundary_loops, 2u);
  ASSERT_EQ(c.loops.size(), 2u);
  const auto loops = boundary_loops(holed);
  for (std::size_t l = 0; l < 2; ++l) {
    EXPECT_EQ(c.loops[l].vertices, valence);
    EXPECT_NEAR(c.loops[l].length, loop_length(holed, loops[l]), 1e-12);
  }
  EXPECT_TRUE(check_of(shapes::sphere(1280)).loops.empty());
}

}  // namespace
}  // namespace ism
