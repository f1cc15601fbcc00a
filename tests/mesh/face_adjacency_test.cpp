// The faces across each edge (faces_across): on a closed surface every edge
// has its twin, across and back is the identity, the shared edge's corners
// match; on an open one exactly the boundary edges have none.
#include "mesh/face_adjacency.hpp"

#include "mesh/boundary.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <cstddef>

namespace ism {
namespace {

TEST(FacesAcross, TwinsOnAClosedSurfaceAndNoneOnlyOnTheBoundary) {
  const TriangleMesh sphere = shapes::sphere(500);
  const auto across = faces_across(sphere.triangles);
  ASSERT_EQ(across.size(), sphere.n_faces());
  for (std::size_t f = 0; f < sphere.n_faces(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto [g, j] = across[f][k];
      ASSERT_GE(g, 0) << f << " " << k;
      ASSERT_NE(std::size_t(g), f);
      const Triangle& t = sphere.triangles[f];
      const Triangle& u = sphere.triangles[std::size_t(g)];
      EXPECT_EQ(u[std::size_t(j)], t[(k + 1) % 3]);
      EXPECT_EQ(u[std::size_t(j + 1) % 3], t[k]);
      const auto back = across[std::size_t(g)][std::size_t(j)];
      EXPECT_EQ(back.face, int(f));
      EXPECT_EQ(back.corner, int(k));
    }

  // Half of the sphere's faces: the edges without a face across are the
  // boundary loops' edges.
  TriangleMesh half = sphere;
  half.triangles.clear();
  for (const Triangle& t : sphere.triangles)
    if (sphere.positions[t[0]].z() > 0) half.triangles.push_back(t);
  std::size_t open = 0;
  for (const auto& face : faces_across(half.triangles))
    for (const auto& a : face) open += a.face < 0;
  std::size_t loop_edges = 0;
  for (const auto& loop : boundary_loops(half)) loop_edges += loop.size();
  EXPECT_GT(open, 0u);
  EXPECT_EQ(open, loop_edges);
}

}  // namespace
}  // namespace ism
