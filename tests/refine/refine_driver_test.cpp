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
#include "shapes/shapes.hpp"
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

// Stopping at a level sweep and calling refine() again refines exactly as
// one call: what lets choose_network race candidates to a coarse level and
// refine the survivors on. Stopping anywhere else changes the schedule.
TEST(Refine, GoesOnFromALevelSweepAsOneCall) {
  const TriangleMesh surface = shapes::blob(3000, 5, 0.4);
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry geometry(octahedron,
                                octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  const ProgressiveMesh pm = simplify_constrained(trace_octahedral_network(surface), octahedron);
  RefineOptions to_coarse;
  to_coarse.stop_at_vertices = 600;
  SurfaceMap whole(geometry, pm), stopped(geometry, pm), off_level(geometry, pm);
  const std::size_t start = whole.n_vertices();
  refine(whole, to_coarse);

  const std::size_t level = last_level_sweep_at_most(to_coarse, start, 150);
  EXPECT_EQ(level, 108u);  // 6 -> 9 -> 14 -> 21 -> 32 -> 48 -> 72 -> 108 -> 162
  EXPECT_EQ(last_level_sweep_at_most(to_coarse, start, 8), start);
  RefineOptions first = to_coarse;
  first.stop_at_vertices = level;
  refine(stopped, first);
  EXPECT_EQ(stopped.n_vertices(), level);
  refine(stopped, to_coarse);
  first.stop_at_vertices = level + 1;
  refine(off_level, first);
  refine(off_level, to_coarse);

  ASSERT_EQ(stopped.n_vertices(), whole.n_vertices());
  EXPECT_EQ(stopped.energy(), whole.energy());
  EXPECT_NE(off_level.energy(), whole.energy());
  for (std::size_t v = 0; v < whole.positions().size(); ++v) {
    EXPECT_EQ(stopped.location(int(v)).face, whole.location(int(v)).face) << v;
    EXPECT_EQ(stopped.location(int(v)).bary, whole.location(int(v)).bary) << v;
  }
}

}  // namespace
}  // namespace ism
