// prepare_mesh() on small hand-made soups whose topology is known exactly.
#include "mesh/mesh_check.hpp"

#include <gtest/gtest.h>

namespace ism {
namespace {

// A tetrahedron, outward oriented.
PolygonSoup tetrahedron() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return s;
}

TEST(MeshCheck, TetrahedronIsClosedGenusZero) {
  const MeshCheck c = prepare_mesh(tetrahedron()).check;
  EXPECT_EQ(c.vertices, 4u);
  EXPECT_EQ(c.edges, 6u);
  EXPECT_EQ(c.faces, 4u);
  EXPECT_EQ(c.euler_characteristic, 2);
  EXPECT_EQ(c.genus, 0);
  EXPECT_TRUE(c.closed());
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.repairs().empty());
  EXPECT_NEAR(c.area, 1.5 + std::sqrt(3.0) / 2, 1e-12);
}

TEST(MeshCheck, InwardTetrahedronIsTurnedOutward) {
  PolygonSoup s = tetrahedron();
  for (auto& f : s.faces) std::swap(f[1], f[2]);
  const PreparedMesh p = prepare_mesh(s);
  EXPECT_TRUE(p.check.flipped_inward);
  EXPECT_GT(signed_volume(p.mesh), 0.0);
}

TEST(MeshCheck, OneFlippedFaceIsReoriented) {
  PolygonSoup s = tetrahedron();
  std::swap(s.faces[3][1], s.faces[3][2]);
  const PreparedMesh p = prepare_mesh(s);
  EXPECT_TRUE(p.check.orientable);
  EXPECT_EQ(p.check.reoriented_faces, 1u);
  EXPECT_FALSE(p.check.flipped_inward);
  EXPECT_NEAR(signed_volume(p.mesh), 1.0 / 6.0, 1e-15);
}

TEST(MeshCheck, QuadIsTriangulatedAndHasOneBoundaryLoop) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.faces = {{0, 1, 2, 3}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.faces, 2u);
  EXPECT_EQ(c.triangulated_polygons, 1u);
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.genus, 0);  // a disc
}

TEST(MeshCheck, CoincidentPositionsAreWelded) {
  PolygonSoup s;  // two triangles sharing an edge through duplicated points
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  s.faces = {{0, 1, 2}, {3, 5, 4}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.welded_vertices, 2u);
  EXPECT_EQ(c.vertices, 4u);
  EXPECT_EQ(c.edges, 5u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.boundary_loops, 1u);
}

TEST(MeshCheck, EdgeSharedByThreeFacesIsNonManifold) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  s.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.nonmanifold_edges, 1u);
  ASSERT_TRUE(c.example_nonmanifold_edge);
  EXPECT_EQ(c.example_nonmanifold_edge->first, 0);
  EXPECT_EQ(c.example_nonmanifold_edge->second, 1);
  EXPECT_FALSE(c.valid_surface());
  EXPECT_FALSE(c.genus);
}

TEST(MeshCheck, TwoFansAtOneVertexAreNonManifold) {
  PolygonSoup s;  // two triangles touching only at vertex 0 (a bow tie)
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.faces = {{0, 1, 2}, {0, 3, 4}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.nonmanifold_vertices, 1u);
  EXPECT_EQ(c.example_nonmanifold_vertex, 0);
  EXPECT_EQ(c.components, 1u);
  const auto unmet = unmet_requirement(c, {.tool = "x"});
  ASSERT_TRUE(unmet);
  EXPECT_EQ(*unmet,
            "1 non-manifold vertex (e.g. vertex 0), x needs one connected, orientable 2-manifold");
}

TEST(MeshCheck, SeparateTrianglesAreTwoComponents) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  s.faces = {{0, 1, 2}, {3, 4, 5}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.components, 2u);
  EXPECT_FALSE(c.valid_surface());
}

TEST(MeshCheck, NonFiniteCoordinateIsADefect) {
  PolygonSoup s = tetrahedron();
  s.positions[3] = {0, std::numeric_limits<double>::quiet_NaN(), 1};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.nonfinite_coordinates, 1u);
  EXPECT_FALSE(c.valid_surface());
}

TEST(MeshCheck, ZeroAreaFaceIsCountedAndKept) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  s.faces = {{0, 1, 3}, {0, 2, 1}};  // second face is collinear
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(c.degenerate_faces, 1u);
  EXPECT_EQ(c.faces, 2u);
  EXPECT_FALSE(c.zero_area);  // one of two: a warning, not a defect
  EXPECT_TRUE(c.defects().empty());
}

TEST(MeshCheck, RequirementsNameTheDefect) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.faces = {{0, 1, 2}, {0, 2, 3}};
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_EQ(unmet_requirement(c, {.tool = "gim-remesh", .closed = true}),
            "1 boundary loop, gim-remesh needs a closed surface");
  EXPECT_EQ(
      unmet_requirement(prepare_mesh(tetrahedron()).check, {.tool = "torus-remesh", .genus = 1}),
      "genus 0, torus-remesh needs genus 1");
  EXPECT_FALSE(unmet_requirement(c, {.tool = "ism-info"}));
}

// An octahedron's connectivity with every vertex on the x axis.
PolygonSoup collinear_octahedron() {
  PolygonSoup s;
  for (int i = 0; i < 6; ++i) s.positions.push_back({double(i), 0, 0});
  s.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return s;
}

TEST(MeshCheck, AllZeroAreaIsADefectNamingTheLine) {
  const MeshCheck c = prepare_mesh(collinear_octahedron()).check;
  EXPECT_TRUE(c.manifold());
  EXPECT_EQ(c.genus, 0);
  EXPECT_TRUE(c.zero_area);
  EXPECT_TRUE(c.collinear);
  EXPECT_FALSE(c.valid_surface());
  EXPECT_EQ(unmet_requirement(c, {.tool = "ism-info"}),
            "all 6 vertices lie on one line: every face has zero area, ism-info needs a surface "
            "of positive area");
}

TEST(MeshCheck, ZeroAreaOffALineIsNamedToo) {
  // Two collinear octahedra on different lines: every face has zero area,
  // the vertices are not on one line.
  PolygonSoup s = collinear_octahedron();
  const PolygonSoup other = collinear_octahedron();
  for (const Vec3& p : other.positions) s.positions.push_back({0, p.x() + 1, 1});
  for (auto face : other.faces) {
    for (int& v : face) v += 6;
    s.faces.push_back(face);
  }
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_TRUE(c.zero_area);
  EXPECT_FALSE(c.collinear);
  ASSERT_FALSE(c.defects().empty());
  EXPECT_EQ(c.defects().front(), "every face has zero area (16 faces)");
}

TEST(MeshCheck, FacesThatAllCollapseSayWhy) {
  PolygonSoup point = tetrahedron();
  for (Vec3& p : point.positions) p = Vec3(1, 2, 3);
  const MeshCheck c = prepare_mesh(point).check;
  EXPECT_EQ(c.faces, 0u);
  EXPECT_EQ(c.defects().front(), "no faces: all 4 faces collapse, every vertex is at one point");
  PolygonSoup two = tetrahedron();
  two.positions[2] = two.positions[0];
  two.positions[3] = two.positions[1];
  EXPECT_EQ(prepare_mesh(two).check.defects().front(),
            "no faces: all 4 faces collapse, their corners take only 2 distinct positions");
}

TEST(MeshCheck, TooFewVerticesForTheDomainIsNamed) {
  const MeshCheck c = prepare_mesh(tetrahedron()).check;
  EXPECT_EQ(unmet_requirement(c, {.tool = "gim-remesh",
                                  .closed = true,
                                  .genus = 0,
                                  .min_vertices = 6,
                                  .min_vertices_reason = "one per octahedron vertex"}),
            "4 vertices, gim-remesh needs at least 6 (one per octahedron vertex)");
  EXPECT_FALSE(unmet_requirement(c, {.tool = "ism-info", .min_vertices = 4}));
}

TEST(MeshCheck, ManyBoundaryPointsInOnePlaneAreWeldedInLinearTime) {
  // 80,000 separate triangles in the plane x = 0 (a 5 MB OBJ): the boundary
  // weld compared every pair with equal x and ran for minutes; ctest's
  // timeout catches a return of that. Two triangles 1e-13 apart still weld.
  PolygonSoup s;
  std::uint64_t state = 42;
  auto random = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  for (int t = 0; t < 80000; ++t) {
    for (int k = 0; k < 3; ++k) s.positions.push_back({0, random(), random()});
    s.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const int n = int(s.positions.size());
  s.positions.push_back(s.positions[0] + Vec3(0, 1e-13, 0));
  s.positions.push_back(s.positions[1]);
  s.positions.push_back({0, 2, 2});
  s.faces.push_back({n, n + 1, n + 2});
  const MeshCheck c = prepare_mesh(s).check;
  EXPECT_GE(c.welded_vertices, 2u);
  EXPECT_EQ(c.faces, 80001u);
}

}  // namespace
}  // namespace ism
