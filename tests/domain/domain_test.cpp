#include "domain/domain.hpp"
#include "mesh/mesh_check.hpp"

#include <gtest/gtest.h>

#include <set>

namespace ism {
namespace {

MeshCheck check_of(const TriangleMesh& m) {
  PolygonSoup soup{m.positions, {}};
  for (const Triangle& t : m.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  return prepare_mesh(soup).check;
}

TEST(Domain, OctahedronIsAnOutwardClosedGenusZeroMesh) {
  const TriangleMesh o = domain::octahedron();
  const MeshCheck c = check_of(o);
  EXPECT_EQ(c.vertices, 6u);
  EXPECT_EQ(c.faces, 8u);
  EXPECT_EQ(c.genus, 0);
  EXPECT_TRUE(c.repairs().empty());  // consistently oriented, outward
  EXPECT_GT(signed_volume(o), 0.0);
}

TEST(Domain, TorusGridHasValenceSixAndGenusOne) {
  const TriangleMesh t = domain::torus_3x3();
  ASSERT_EQ(t.n_vertices(), 9u);
  ASSERT_EQ(t.n_faces(), 18u);
  // Positions are parameter points: the mesh is not embedded, so check the
  // topology from the connectivity only (welding would merge nothing).
  std::vector<int> valence(9, 0);
  for (const Triangle& f : t.triangles)
    for (int v : f) ++valence[v];
  for (int v : valence) EXPECT_EQ(v, 6);
  // V - E + F = 9 - 27 + 18 = 0: genus 1.
  std::set<std::pair<int, int>> edges;
  for (const Triangle& f : t.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(f[k], f[(k + 1) % 3]));
  EXPECT_EQ(edges.size(), 27u);
  // Grid neighbours are adjacent: (row, col) to (row, col+1) and (row+1, col).
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(edges.count(std::minmax(3 * r + c, 3 * r + (c + 1) % 3)));
      EXPECT_TRUE(edges.count(std::minmax(3 * r + c, 3 * ((r + 1) % 3) + c)));
    }
}

}  // namespace
}  // namespace ism
