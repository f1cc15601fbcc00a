// Free connectivity: the dual of the sites' Voronoi regions is a closed
// manifold base of the surface's genus, on exactly the sites, oriented like
// the surface; too few sites for the shape are refused with a reason.
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"

#include "closed_surface_checks.hpp"

#include <gtest/gtest.h>

namespace ism {
namespace {

using test::check_of;

void expect_dual_base(const TriangleMesh& surface, std::size_t sites, int genus) {
  const std::vector<int> vertices = simplify_to(surface, sites).base_vertices;
  const TriangleMesh base = delaunay_base(surface, vertices);
  ASSERT_EQ(base.n_vertices(), sites);
  for (std::size_t i = 0; i < sites; ++i)
    EXPECT_EQ(base.positions[i], surface.positions[vertices[i]]);
  const MeshCheck c = check_of(base);
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.genus, genus);
  EXPECT_EQ(c.reoriented_faces, 0u);
  EXPECT_FALSE(c.flipped_inward);  // oriented like the (outward) surface
  // And it is a domain the path network can realise.
  const PathNetwork network = trace_path_network(surface, base, vertices);
  EXPECT_EQ(validate_network(network, base), std::nullopt);
}

TEST(DelaunayBase, GenusZeroAndOne) {
  expect_dual_base(shapes::blob(4000, 5, 0.4), 60, 0);
  expect_dual_base(shapes::torus(4000, 2.0, 1.0), 60, 1);
}

TEST(DelaunayBase, RefusesTooFewSitesAndBadOnes) {
  const TriangleMesh torus = shapes::torus(2000, 2.0, 1.0);
  // Four sites cannot triangulate a torus (it needs at least 7 vertices).
  try {
    delaunay_base(torus, {0, 250, 500, 750});
    ADD_FAILURE() << "no error";
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find("no triangulation of the 4 base vertices"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(delaunay_base(torus, {0, 1, 2, 1}), PartitionError);
  EXPECT_THROW(delaunay_base(torus, {0, 1, 2, int(torus.n_vertices())}), PartitionError);
}

}  // namespace
}  // namespace ism
