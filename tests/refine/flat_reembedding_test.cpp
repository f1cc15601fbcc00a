// The global flat-torus re-embedding: its energy is the map's, its solver
// gives back a layout from that layout's own weights (the lattice offsets
// carry the map's class), symmetric positive weights embed the torus, and
// the re-embedding repairs a distorted map and frees one that the
// vertex-at-a-time optimisation left stuck (the mug).
#include "refine/flat_reembedding.hpp"
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "refine/refine_surfaces.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"
#include "torus_map_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace ism {
namespace {

using test::TorusMap;

int first_active(const SurfaceMap& map) {
  int v = 0;
  while (!map.is_active(v)) ++v;
  return v;
}

// Energy and gradient of FlatLayoutEnergy against the map's own energy and
// central differences.
void check_energy_and_gradient(const MapOptions& map_options) {
  TorusMap s(shapes::torus(1500, 2, 1), map_options);
  RefineOptions options;
  options.stop_at_vertices = 400;
  refine(s.map, options);
  const FlatTorusLayout layout = *s.map.flat_layout();
  const FlatLayoutEnergy energy(s.map);
  std::vector<Vec2> gradient;
  const double e = energy(layout, &gradient);
  EXPECT_NEAR(e, s.map.energy(), 1e-10 * e);
  // Central differences at a spread of vertices, both coordinates.
  int checked = 0;
  for (std::size_t v = 0; v < layout.position.size(); v += 23) {
    if (!s.map.is_active(int(v))) continue;
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-7;
      FlatTorusLayout moved = layout;
      moved.position[v][k] += h;
      const double plus = energy(moved);
      moved.position[v][k] -= 2 * h;
      const double minus = energy(moved);
      const double numeric = (plus - minus) / (2 * h);
      EXPECT_NEAR(gradient[v][k], numeric, 1e-5 * (std::abs(numeric) + 1e-3 * e))
          << "vertex " << v << " coordinate " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(FlatReembedding, EnergyAndGradientAreTheMaps) {
  check_energy_and_gradient({});
  TorusMap s(shapes::torus(1500, 2, 1));
  RefineOptions options;
  options.stop_at_vertices = 400;
  refine(s.map, options);
  const FlatTorusLayout layout = *s.map.flat_layout();
  const FlatLayoutEnergy energy(s.map);
  // A face turned over (its first corner reflected through its second)
  // has no energy.
  FlatTorusLayout folded = layout;
  const auto& faces = s.map.faces();
  const Vec2 c0 = layout.corner(faces, 0, 0), c1 = layout.corner(faces, 0, 1);
  folded.position[faces[0][0]] = 2 * c1 - c0 - layout.shift[0][0].cast<double>();
  EXPECT_EQ(energy(folded), HUGE_VAL);
  EXPECT_EQ(s.map.layout_energy(folded), HUGE_VAL);
}

TEST(FlatReembedding, EnergyAndGradientWithTheAnisotropyPenalty) {
  // An onset low enough that the penalty bites on most faces.
  check_energy_and_gradient(
      {.inverse_stretch_weight = 0.1, .anisotropy_weight = 0.5, .anisotropy_threshold = 1.2});
}

TEST(FlatReembedding, LatticeOffsetsAndOwnWeightsGiveTheLayoutBack) {
  TorusMap s(shapes::torus(1500, 2, 1));
  refine(s.map);
  const FlatTorusLayout layout = *s.map.flat_layout();
  // Each vertex is the mean-value combination of its neighbours' lifted
  // corners, so solving with those weights and the extracted offsets, one
  // vertex held, must give every other position back (not only modulo 1).
  const int fixed = first_active(s.map);
  const auto solved =
      solve_flat_layout(s.map, layout, layout_mean_value_weights(s.map, layout), fixed);
  ASSERT_TRUE(solved.has_value());
  double worst = 0;
  for (std::size_t v = 0; v < layout.position.size(); ++v)
    if (s.map.is_active(int(v)))
      worst = std::max(worst, (solved->position[v] - layout.position[v]).norm());
  EXPECT_LT(worst, 1e-9);

  // With the offsets dropped (all shifts zero) the solve collapses to a
  // point: the offsets are what carries the map's class.
  FlatTorusLayout no_class = layout;
  for (auto& t : no_class.shift) t.fill(Eigen::Vector2i::Zero());
  const auto collapsed =
      solve_flat_layout(s.map, no_class, layout_mean_value_weights(s.map, layout), fixed);
  ASSERT_TRUE(collapsed.has_value());
  for (std::size_t v = 0; v < layout.position.size(); ++v) {
    if (!s.map.is_active(int(v))) continue;
    EXPECT_LT((collapsed->position[v] - layout.position[fixed]).norm(), 1e-9);
  }
}

TEST(FlatReembedding, SymmetricPositiveWeightsEmbedTheTorus) {
  TorusMap s(shapes::torus(3000, 2, 1));
  RefineOptions options;
  options.stop_at_vertices = 1000;
  refine(s.map, options);
  const FlatTorusLayout classes = *s.map.flat_layout();
  const auto& faces = s.map.faces();
  const CornerWeights weights = symmetrized(faces, surface_mean_value_weights(s.map));
  const auto harmonic = solve_flat_layout(s.map, classes, weights, first_active(s.map));
  ASSERT_TRUE(harmonic.has_value());
  test::expect_layout_tiles_the_torus(faces, *harmonic);
  // And it installs as a valid map.
  EXPECT_TRUE(s.map.set_flat_layout(*harmonic));
  EXPECT_EQ(s.map.validate(), std::nullopt);
}

// Two periodic shears of a layout: a bijection of the torus far from the
// optimum.
FlatTorusLayout sheared(FlatTorusLayout layout) {
  for (Vec2& p : layout.position) {
    p.x() += 0.15 * std::sin(2 * M_PI * p.y());
    p.y() += 0.15 * std::sin(2 * M_PI * p.x());
  }
  return layout;
}

TEST(FlatReembedding, RepairsADistortedMap) {
  TorusMap s(shapes::torus(1500, 2, 1));
  SurfaceMap& map = s.map;
  refine(map);
  const double optimised = map.energy();
  ASSERT_TRUE(map.set_flat_layout(sheared(*map.flat_layout())));
  const double distorted = map.energy();
  ASSERT_GT(distorted, 1.3 * optimised);

  const FlatReembeddingStats stats = global_flat_reembedding(map);
  EXPECT_TRUE(stats.applied);
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_EQ(stats.energy_before, distorted);
  EXPECT_EQ(stats.energy_after, map.energy());
  // Back to the optimised map's level in one step (the vertex-at-a-time
  // refinement needed the whole coarse-to-fine run for it).
  EXPECT_LT(map.energy(), 1.01 * optimised);
  std::printf("  distorted %.4f -> %.4f (vertex-at-a-time optimum %.4f), %d iterations\n",
              distorted, map.energy(), optimised, stats.iterations);
}

TEST(FlatReembedding, DoesNothingWhereItDoesNotApply) {
  // The octahedron has cones: no flat layout, the map is left alone.
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry geometry(octahedron,
                                octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  const TriangleMesh sphere = shapes::sphere(800);
  const PathNetwork network = trace_octahedral_network(sphere);
  const ProgressiveMesh pm = simplify_constrained(network, octahedron);
  SurfaceMap map(geometry, pm);
  RefineOptions options;
  options.stop_at_vertices = 200;
  refine(map, options);
  const double before = map.energy();
  EXPECT_FALSE(global_flat_reembedding(map).applied);
  EXPECT_EQ(map.energy(), before);
  // refine() with the option on behaves as without it there.
  SurfaceMap with(geometry, pm), without(geometry, pm);
  RefineOptions on;
  on.global_flat_reembedding = true;
  on.reembed_max_vertices = SIZE_MAX;
  const RefineStats stats = refine(with, on);
  refine(without);
  EXPECT_EQ(stats.reembeddings, 0u);
  EXPECT_EQ(with.energy(), without.energy());
}

TEST(FlatReembedding, RefineWithReembeddingsStaysValid) {
  TorusMap s(shapes::torus(1500, 2, 1));
  RefineOptions options;
  options.global_flat_reembedding = true;
  options.reembed_max_vertices = SIZE_MAX;
  options.validate_each_step = true;  // throws on an invalid map
  const RefineStats stats = refine(s.map, options);
  EXPECT_EQ(s.map.validate(), std::nullopt);
  EXPECT_GT(stats.reembeddings, 3u);
  EXPECT_GT(stats.reembeddings_applied, 0u);
  TorusMap plain(shapes::torus(1500, 2, 1));
  refine(plain.map);
  EXPECT_LT(s.map.energy(), plain.map.energy() * (1 + 1e-3));
}

// Vertices moved by golden line searches, which leave the mug's map stuck.
MapOptions line_search_options() {
  MapOptions options;
  options.vertex_step = MapOptions::VertexStep::line_search;
  return options;
}

TriangleMesh shared_mug() {
  return prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "mug.obj")).mesh;
}

// The mug's map, optimised a vertex at a time, squeezes strips of faces
// that single moves cannot open; the global step does. (refine() now
// re-embeds the disc around a split that squeezes a face almost flat, which
// keeps this map from getting stuck: 6.78 instead of 2e8 at 3000 vertices;
// that repair is off here to make the stuck map, and vertices move by line
// searches: Newton steps do not get stuck here, 6.24 without either.)
TEST(FlatReembedding, FreesTheMugsStuckMap) {
  ISM_REQUIRE_SHARED_MODELS();
  TorusMap s(shared_mug(), line_search_options());
  RefineOptions options;
  options.stop_at_vertices = 3000;
  options.repair_squeezed_splits = false;
  refine(s.map, options);
  // Sweeps until they gain little, then more sweeps hardly help ...
  double stuck = s.map.energy();
  for (int i = 0; i < 40; ++i) {
    const double gain = optimization_sweep(s.map);
    stuck -= gain;
    if (gain < 1e-3 * stuck) break;
  }
  stuck = s.map.energy();
  for (int i = 0; i < 3; ++i) optimization_sweep(s.map);
  const double swept = s.map.energy();
  EXPECT_GT(swept, 0.97 * stuck);
  // ... the global re-embedding lowers the energy by a third or more.
  const FlatReembeddingStats stats = global_flat_reembedding(s.map);
  EXPECT_TRUE(stats.applied);
  EXPECT_EQ(s.map.validate(), std::nullopt);
  EXPECT_LT(s.map.energy(), 0.67 * swept);
  std::printf("  mug at %zu vertices: %.3f, swept %.3f, re-embedded %.3f\n", s.map.n_vertices(),
              stuck, swept, s.map.energy());
}

// The same map with refine()'s repair of squeezed splits on: the discs
// around them re-embedded, no face stays squeezed (2e8 above; vertices
// moved by line searches, as above).
TEST(FlatReembedding, SqueezedSplitsAreRepairedOnTheMug) {
  ISM_REQUIRE_SHARED_MODELS();
  TorusMap s(shared_mug(), line_search_options());
  RefineOptions options;
  options.stop_at_vertices = 3000;
  const RefineStats stats = refine(s.map, options);
  EXPECT_GT(stats.split_repairs, 0u);
  EXPECT_EQ(s.map.validate(), std::nullopt);
  EXPECT_LT(s.map.energy(), 10.0);
  std::printf("  mug at %zu vertices: %.3f after %zu repairs\n", s.map.n_vertices(), s.map.energy(),
              stats.split_repairs);
}

// The symmetric core's map of a TorusMap: its SurfaceMap refined to
// `vertices` (all of them: 0), resumed as an InterSurfaceMap.
struct SymmetricTorus {
  TorusMap s{shapes::torus(1500, 2, 1)};
  std::unique_ptr<InterSurfaceMap> map;
  explicit SymmetricTorus(std::size_t vertices, bool distort = false) {
    RefineOptions options;
    if (vertices > 0) options.stop_at_vertices = vertices;
    refine(s.map, options);
    if (distort) {
      EXPECT_TRUE(s.map.set_flat_layout(sheared(*s.map.flat_layout())));
    }
    map = std::make_unique<InterSurfaceMap>(*meta_mesh(s.map), side_from_domain(s.geometry, s.pm),
                                            side_from_pm(s.pm),
                                            std::array<std::size_t, 2>{0, s.map.splits_applied()});
  }
  InterSurfaceMap with(const MetaMesh& overlay) const {
    return InterSurfaceMap(overlay, side_from_domain(s.geometry, s.pm), side_from_pm(s.pm),
                           {0, s.map.splits_applied()});
  }
};

// Read as a layout, the symmetric core's map is SurfaceMap's own layout;
// the overlay rebuilt from a layout is that layout's map: it validates from
// both sides and its energy over the pieces is the layout's face by face.
TEST(FlatReembedding, TheSymmetricCoresMapAsALayoutAndBack) {
  SymmetricTorus t(400);
  const auto expected = t.s.map.flat_layout();
  const auto layout = flat_layout(*t.map, t.s.geometry);
  ASSERT_TRUE(expected);
  ASSERT_TRUE(layout);
  const auto& faces = t.map->meta().side[1].faces;
  ASSERT_EQ(faces, t.s.map.faces());
  test::expect_layout_tiles_the_torus(faces, *layout);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int c = 0; c < 3; ++c) {
      // The same point modulo Z², the same displacements within the face.
      const Vec2 d = layout->position[faces[f][c]] - expected->position[faces[f][c]];
      EXPECT_LT((d - d.array().round().matrix()).norm(), 1e-9);
      const Vec2 step = layout->corner(faces, int(f), c) - layout->corner(faces, int(f), 0);
      const Vec2 expected_step =
          expected->corner(faces, int(f), c) - expected->corner(faces, int(f), 0);
      EXPECT_LT((step - expected_step).norm(), 1e-9) << "face " << f << " corner " << c;
    }
  const FlatLayoutEnergy energy(*t.map);
  const double e = t.map->energy();
  EXPECT_NEAR(energy(*layout), e, 1e-9 * e);
  // With an anisotropy penalty: per piece on the symmetric core, per face
  // of the layout, the same sum (the flat torus's map is affine per face).
  InterSurfaceOptions penalised_options;
  penalised_options.anisotropy_weight = 1;
  penalised_options.anisotropy_threshold = 1.2;
  const InterSurfaceMap penalised(t.map->meta(), side_from_domain(t.s.geometry, t.s.pm),
                                  side_from_pm(t.s.pm), {0, t.s.map.splits_applied()},
                                  penalised_options);
  const double ep = penalised.energy();
  EXPECT_GT(ep, 1.001 * e);
  EXPECT_NEAR(FlatLayoutEnergy(penalised)(*layout), ep, 1e-9 * ep);

  // Moved a little (off any vertex of the other side), rebuilt.
  FlatTorusLayout moved = *layout;
  for (std::size_t v = 0; v < moved.position.size(); ++v)
    moved.position[v] += 1e-4 * Vec2(std::sin(0.7 * double(v)), std::cos(1.3 * double(v)));
  const auto overlay = flat_torus_overlay(*t.map, t.s.geometry, moved);
  ASSERT_TRUE(overlay);
  EXPECT_EQ(validate(*overlay), std::nullopt);
  const MetaMeshSize size = meta_mesh_size(*overlay);
  EXPECT_EQ(size.kinks, 0u);
  EXPECT_EQ(size.shared_vertices, 0u);
  EXPECT_GT(size.crossings, 100u);
  const double rebuilt = t.with(*overlay).energy();
  EXPECT_NEAR(rebuilt, energy(moved), 1e-9 * rebuilt);
  // A layout with a face turned over has no overlay.
  FlatTorusLayout folded = *layout;
  const Vec2 c0 = layout->corner(faces, 0, 0), c1 = layout->corner(faces, 0, 1);
  folded.position[faces[0][0]] = 2 * c1 - c0 - layout->shift[0][0].cast<double>();
  EXPECT_FALSE(flat_torus_overlay(*t.map, t.s.geometry, folded));
  // ... until untangled: that vertex moved into its ring's kernel.
  EXPECT_TRUE(untangle_layout(faces, folded));
  test::expect_layout_tiles_the_torus(faces, folded);
  EXPECT_TRUE(flat_torus_overlay(*t.map, t.s.geometry, folded));
}

// The global re-embedding on the symmetric core: a distorted map is brought
// back to the optimised map's energy in one step, through replace_overlay,
// with the exact gain; where it does not apply nothing changes.
TEST(FlatReembedding, RepairsADistortedMapOnTheSymmetricCore) {
  TorusMap optimised(shapes::torus(1500, 2, 1));
  refine(optimised.map);
  SymmetricTorus t(0, true);
  const double distorted = t.map->energy();
  ASSERT_GT(distorted, 1.3 * optimised.map.energy());
  const FlatReembeddingStats stats = global_flat_reembedding(*t.map, t.s.geometry);
  EXPECT_TRUE(stats.applied);
  EXPECT_EQ(t.map->validate(), std::nullopt);
  EXPECT_EQ(stats.energy_before, distorted);
  EXPECT_EQ(stats.energy_after, t.map->energy());
  EXPECT_LT(t.map->energy(), 1.01 * optimised.map.energy());
  std::printf("  symmetric core: distorted %.4f -> %.4f (vertex-at-a-time optimum %.4f)\n",
              distorted, t.map->energy(), optimised.map.energy());
  // A second time: nothing lower to find, the map unchanged.
  const double once = t.map->energy();
  global_flat_reembedding(*t.map, t.s.geometry);
  EXPECT_LE(t.map->energy(), once);
  EXPECT_EQ(t.map->validate(), std::nullopt);
  // The octahedron is no flat torus: no layout, no re-embedding.
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry geometry(octahedron,
                                octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  EXPECT_FALSE(flat_layout(*t.map, geometry));
}

// refine_surfaces with the re-embedding before the final sweeps: run once
// at full resolution, the map valid from both sides after it, the gain it
// reports exactly the energy it took off.
TEST(FlatReembedding, TheSymmetricCoresRefinementRunsTheGlobalStep) {
  SymmetricTorus t(300);
  SurfaceRefineOptions options;
  std::vector<double> gains;
  options.before_final = [&](InterSurfaceMap& map) {
    EXPECT_EQ(map.splits_applied(1), map.splits_total(1));
    const double before = map.energy();
    const FlatReembeddingStats s = global_flat_reembedding(map, t.s.geometry);
    EXPECT_EQ(map.validate(), std::nullopt);
    EXPECT_EQ(s.energy_before, before);
    EXPECT_EQ(s.energy_after, map.energy());
    gains.push_back(s.energy_before - s.energy_after);
    return gains.back();
  };
  const SurfaceRefineStats stats = refine_surfaces(*t.map, options);
  EXPECT_EQ(stats.global_steps, 1u);
  ASSERT_EQ(gains.size(), 1u);
  EXPECT_GT(gains[0], 0);
  EXPECT_EQ(stats.global_steps_applied, 1u);
  EXPECT_EQ(t.map->validate(), std::nullopt);
  std::printf("  global step gained %.4g; symmetric efficiency %.4f\n", gains[0],
              t.map->measures().symmetric_efficiency);
}

}  // namespace
}  // namespace ism
