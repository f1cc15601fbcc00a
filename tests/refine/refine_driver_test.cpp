// The refinement driver: the same input and options give the same map, bit
// for bit (every vertex's location in M¹), with the disc re-embeddings and
// the local relaxation on.
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

namespace ism {
namespace {

TEST(Refine, IsDeterministicBitForBit) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh surface =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "bunny_small.obj")).mesh;
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry geometry(octahedron,
                                octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  const ProgressiveMesh pm = simplify_constrained(trace_octahedral_network(surface), octahedron);
  SurfaceMap a(geometry, pm), b(geometry, pm);
  const RefineStats sa = refine(a), sb = refine(b);
  EXPECT_GT(sa.discs_applied, 0u);  // the discs ran
  EXPECT_EQ(sa.discs, sb.discs);
  EXPECT_EQ(sa.local_moves, sb.local_moves);
  EXPECT_EQ(a.energy(), b.energy());
  for (std::size_t v = 0; v < a.positions().size(); ++v) {
    EXPECT_EQ(a.location(int(v)).face, b.location(int(v)).face) << v;
    EXPECT_EQ(a.location(int(v)).bary, b.location(int(v)).bary) << v;
    EXPECT_EQ(a.domain_vertex_at(int(v)), b.domain_vertex_at(int(v))) << v;
  }
}

}  // namespace
}  // namespace ism
