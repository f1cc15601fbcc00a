// Re-embedding discs whole: the chart of a disc agrees with its faces'
// charts and refuses a disc wrapped around a cone; every re-embedding keeps
// the map valid and lowers its energy by what it reports; a squeezed patch
// that vertex-at-a-time moves hardly open is opened by disc relaxation.
#include "refine/disc_relaxation.hpp"
#include "domain/domain.hpp"
#include "map/map.hpp"
#include "octahedral_map_fixture.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "shapes/shapes.hpp"
#include "torus_map_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ism {
namespace {

// The octahedral map of a 2000-face sphere, refined to `vertices`.
struct SphereMap : test::OctahedralMap {
  explicit SphereMap(std::size_t vertices) : OctahedralMap(shapes::sphere(2000)) {
    RefineOptions options;
    options.stop_at_vertices = vertices;
    refine(map, options);
  }
};

double edge(const std::array<Vec2, 3>& t, int k) {
  return (t[(k + 1) % 3] - t[k]).norm();
}

TEST(DiscLayout, AgreesWithTheFaceChartsAndRefusesACone) {
  SphereMap s(600);
  const SurfaceMap& map = s.map;
  int far = -1, cone = -1;
  for (std::size_t x = 0; x < map.domain().n_vertices() && cone < 0; ++x)
    if (map.domain().is_cone(int(x))) cone = map.vertex_at_domain_vertex(int(x));
  ASSERT_GE(cone, 0);
  // A vertex at least 4 edges from every vertex on an M¹ vertex.
  for (std::size_t v = 0; v < map.positions().size() && far < 0; ++v) {
    if (!map.is_active(int(v))) continue;
    bool clear = true;
    for (int u : map.rings_around(int(v), 4)) clear = clear && map.domain_vertex_at(u) < 0;
    if (clear) far = int(v);
  }
  ASSERT_GE(far, 0);

  const std::optional<DiscLayout> disc = map.disc_layout(map.rings_around(far, 2));
  ASSERT_TRUE(disc);
  EXPECT_EQ(std::count(disc->free.begin(), disc->free.end(), 1),
            std::ptrdiff_t(map.rings_around(far, 2).size()));
  // Each face of the disc is its own chart moved rigidly: same edge lengths,
  // counter-clockwise.
  for (std::size_t i = 0; i < disc->face.size(); ++i) {
    SurfaceMap::FaceChart chart;
    ASSERT_TRUE(map.face_chart(disc->face[i], chart));
    const Triangle& t = disc->local[i];
    const std::array<Vec2, 3> placed{disc->position[t[0]], disc->position[t[1]],
                                     disc->position[t[2]]};
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(edge(placed, k), edge(chart.corner, k), 1e-12);
    EXPECT_GT(orient(placed[0], placed[1], placed[2]), 0);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(disc->vertex[t[k]], map.faces()[disc->face[i]][k]);
  }
  // The neighbours of a cone: their faces go all the way round it, which no
  // flat chart holds.
  EXPECT_FALSE(map.disc_layout(map.neighbours(cone)));
  // Pinned and cone vertices never move: nothing free, no layout.
  EXPECT_FALSE(map.disc_layout({cone}));
}

TEST(DiscLayout, InstallingTheSamePositionsChangesNothing) {
  SphereMap s(600);
  SurfaceMap& map = s.map;
  const double before = map.energy();
  int v = 0;
  while (!map.is_active(v) || map.domain_vertex_at(v) >= 0) ++v;
  const std::optional<DiscLayout> disc = map.disc_layout(map.rings_around(v, 2));
  ASSERT_TRUE(disc);
  EXPECT_EQ(map.set_disc_layout(*disc), 0.0);  // no energy drop: not kept
  EXPECT_EQ(map.energy(), before);
  EXPECT_EQ(map.validate(), std::nullopt);
}

// Each disc around each of many vertices: valid after every re-embedding,
// and the energy drops by exactly what was reported.
TEST(DiscRelaxation, EveryReembeddingIsValidAndLowersTheEnergyByItsGain) {
  SphereMap s(400);
  SurfaceMap& map = s.map;
  int kept = 0;
  for (std::size_t v = 0; v < map.positions().size(); v += 7) {
    if (!map.is_active(int(v))) continue;
    for (int rings : {1, 3}) {
      const double before = map.energy();
      const double gain = reembed_disc(map, map.rings_around(int(v), rings));
      ASSERT_EQ(map.validate(), std::nullopt) << "disc of " << rings << " rings around " << v;
      EXPECT_GE(gain, 0.0);
      EXPECT_NEAR(before - map.energy(), gain, 1e-10 * before);
      kept += gain > 0;
    }
  }
  // The map was only swept level by level: whole discs still find gains.
  EXPECT_GT(kept, 0);
}

// A patch of the torus map squeezed to a thousandth of its size around a
// vertex (the ring outside it stretched to match): inside, every vertex is
// confined by its squeezed neighbours. Returns the optimised energy.
double squeeze_a_patch(SurfaceMap& map) {
  refine(map);
  const double optimised = map.energy();
  FlatTorusLayout layout = *map.flat_layout();
  int centre = 0;
  while (!map.is_active(centre)) ++centre;
  const Vec2 p0 = layout.position[centre];
  const double inner = 0.08, outer = 0.2, scale = 1e-3;
  for (std::size_t v = 0; v < layout.position.size(); ++v) {
    if (!map.is_active(int(v))) continue;
    Vec2 d = layout.position[v] - p0;
    d -= d.array().round().matrix();  // nearest copy on the torus
    const double r = d.norm();
    if (!(r > 0) || r >= outer) continue;
    // r -> scale·r inside, then linear up to the identity at `outer`.
    const double to = r < inner
                          ? scale * r
                          : scale * inner + (r - inner) * (outer - scale * inner) / (outer - inner);
    layout.position[v] += d * (to / r - 1);
  }
  EXPECT_TRUE(map.set_flat_layout(layout));
  return optimised;
}

// Vertices move by golden line searches in these tests (MapOptions::
// vertex_step), which stay confined by a squeeze; Newton steps open this
// one vertex by vertex (5 sweeps: 3.28; the discs below: 3.57).
MapOptions line_search_options() {
  MapOptions options;
  options.vertex_step = MapOptions::VertexStep::line_search;
  return options;
}

TEST(DiscRelaxation, OpensASqueezedPatch) {
  test::TorusMap s(shapes::torus(1500, 2, 1), line_search_options());
  SurfaceMap& map = s.map;
  const double optimised = squeeze_a_patch(map);
  const double squeezed = map.energy();
  ASSERT_GT(squeezed, 100 * optimised);

  std::size_t tried = 0, applied = 0;
  const double gain = disc_relaxation(map, 10, 64, tried, applied, true);
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_NEAR(squeezed - map.energy(), gain, 1e-9 * squeezed);
  EXPECT_GT(applied, 0u);
  EXPECT_LT(map.energy(), 1.5 * optimised);

  // Vertex-at-a-time sweeps from the same squeezed map stay far above.
  test::TorusMap t(shapes::torus(1500, 2, 1), line_search_options());
  squeeze_a_patch(t.map);
  for (int i = 0; i < 5; ++i) optimization_sweep(t.map);
  EXPECT_GT(t.map.energy(), 5 * map.energy());
  std::printf("  optimised %.4f, squeezed %.4f; %zu of %zu discs -> %.4f; 5 sweeps -> %.4f\n",
              optimised, squeezed, applied, tried, map.energy(), t.map.energy());
}

// Local relaxation that re-embeds the disc around a vertex still gaining
// after every 10 moves opens the same squeeze further.
TEST(DiscRelaxation, LocalRelaxationWithDiscsGoesFurther) {
  test::TorusMap with(shapes::torus(1500, 2, 1), line_search_options()),
      without(shapes::torus(1500, 2, 1), line_search_options());
  const double optimised = squeeze_a_patch(with.map);
  squeeze_a_patch(without.map);
  const double squeezed = with.map.energy();
  const LocalRelaxationStats a = local_relaxation(with.map, 1e-4, 100, 10, 3, true);
  const LocalRelaxationStats b = local_relaxation(without.map, 1e-4, 100, 0, 3);
  EXPECT_EQ(with.map.validate(), std::nullopt);
  EXPECT_NEAR(squeezed - with.map.energy(), a.gain, 1e-9 * squeezed);
  EXPECT_GT(a.discs_applied, 0u);
  EXPECT_EQ(b.discs, 0u);
  EXPECT_LT(with.map.energy(), without.map.energy());
  EXPECT_LT(with.map.energy(), 1.5 * optimised);
  std::printf(
      "  squeezed %.4f: with discs %.4f (%zu moves, %zu of %zu discs), without %.4f (%zu moves)\n",
      squeezed, with.map.energy(), a.moves, a.discs_applied, a.discs, without.map.energy(),
      b.moves);
}

}  // namespace
}  // namespace ism
