#pragma once
// Expectations on a remesh read back through the input checks.
#include "mesh/mesh_check.hpp"

#include <gtest/gtest.h>

namespace ism::test {

/// The input checks of a mesh given as a TriangleMesh (as a tool reads it).
inline MeshCheck check_of(const TriangleMesh& mesh) {
  PolygonSoup soup{mesh.positions, {}};
  for (const Triangle& t : mesh.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  return prepare_mesh(soup).check;
}

/// A closed valid surface of the given genus, V - E + F = 2 - 2g, that the
/// checks had nothing to repair and did not have to turn outward.
inline void expect_clean_closed_surface(const MeshCheck& c, int genus) {
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.genus, genus);
  EXPECT_EQ(long(c.vertices) - long(c.edges) + long(c.faces), 2 - 2 * genus);
  EXPECT_EQ(c.welded_vertices, 0u);
  EXPECT_EQ(c.reoriented_faces, 0u);
  EXPECT_FALSE(c.flipped_inward);
}

}  // namespace ism::test
