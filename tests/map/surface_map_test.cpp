// The map core on generated surfaces: valid after every operation, energy
// never raised by an accepted optimisation, and the quality the paper's
// method should reach.
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "refine/disc_relaxation.hpp"
#include "refine/refine.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

namespace ism {
namespace {

struct OctahedralSetup {
  TriangleMesh octahedron = domain::octahedron();
  DomainGeometry geometry;
  PathNetwork network;
  ProgressiveMesh pm;
  OctahedralSetup(const TriangleMesh& surface, DomainMetric metric)
      : geometry(octahedron, octahedron_lengths(octahedron, metric)),
        network(trace_octahedral_network(surface)),
        pm(simplify_constrained(network, octahedron)) {}
};

TEST(SurfaceMap, BaseMapIsValid) {
  OctahedralSetup s(shapes::sphere(500), DomainMetric::right_isosceles);
  SurfaceMap map(s.geometry, s.pm);
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_EQ(map.n_vertices(), 6u);
}

TEST(SurfaceMap, ValidAfterEverySplitAndOptimisation) {
  // Variants: right isosceles; equilateral; features held; cones moved
  // without relaxation; a low inverse-stretch weight; curvature-weighted.
  for (int variant = 0; variant < 6; ++variant) {
    SCOPED_TRACE(variant);
    const DomainMetric metric =
        variant == 1 ? DomainMetric::equilateral : DomainMetric::right_isosceles;
    OctahedralSetup s(shapes::blob(600, 4, 0.4), metric);
    SurfaceMap map(s.geometry, s.pm,
                   {.release_features = variant != 2,
                    .inverse_stretch_weight = variant == 4 ? 0.1 : 1.0,
                    .cone_relaxation_rings = variant == 3 ? 0 : 2,
                    .curvature_weight = variant == 5 ? 2.0 : 0.0});
    for (int vs; (vs = map.split_next()) >= 0;) {
      ASSERT_EQ(map.validate(), std::nullopt) << "after split " << map.splits_applied();
      const double before = map.energy();
      double gain = 0;
      for (int w : map.neighbours(vs)) {
        const double before_w = map.energy();
        const double g = map.optimize_vertex(w);
        ASSERT_EQ(map.validate(), std::nullopt) << "after optimising neighbour " << w;
        EXPECT_LE(map.energy(), before_w * (1 + 1e-12));
        gain += g;
      }
      gain += map.optimize_vertex(vs);
      ASSERT_EQ(map.validate(), std::nullopt) << "after optimising " << vs;
      for (int x = 0; x < 6; ++x) {
        const int v = map.vertex_at_domain_vertex(x);
        if (v < 0) continue;
        const double before_c = map.energy();
        const double g = map.relocate_cone(v);
        ASSERT_EQ(map.validate(), std::nullopt) << "after moving cone " << x << " from " << v;
        if (g > 0) {
          EXPECT_NEAR(before_c - map.energy(), g, 1e-6 * before_c);
        }
        gain += g;
      }
      const double after = map.energy();
      // An accepted step lowers the symmetric energy by what it reports.
      EXPECT_LE(after, before * (1 + 1e-12));
      if (gain > 0) {
        EXPECT_LT(after, before);
        EXPECT_NEAR(before - after, gain, 1e-6 * before);
      }
    }
    EXPECT_EQ(map.n_vertices(), s.network.surface.n_vertices());
  }
}

TEST(SurfaceMap, RefinedSphereBeatsTheAreaRatioMap) {
  OctahedralSetup s(shapes::sphere(5000), DomainMetric::right_isosceles);
  SurfaceMap map(s.geometry, s.pm);
  const RefineStats stats = refine(map);
  EXPECT_EQ(map.validate(), std::nullopt);
  const MapMeasures m = map.measures();
  std::printf(
      "sphere: symmetric %.4f, domain->surface %.4f, surface->domain %.4f; %zu opts, %.1f%% "
      "single-face\n",
      m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency, stats.optimizations,
      100.0 * stats.single_face_rings / std::max<std::size_t>(1, stats.optimizations));
  EXPECT_GE(m.forward_efficiency, 0.83);
}

TEST(SurfaceMap, CurvatureWeightGivesCurvedRegionsMoreOfTheDomain) {
  // An ellipsoid 3:1:1 bends most at its tips: the curvature-weighted map
  // gives the surface there a larger share of the octahedron (denser samples).
  const TriangleMesh ellipsoid = shapes::ellipsoid(3000, Vec3(3, 1, 1));
  std::array<double, 2> tip_share{};
  for (int weighted = 0; weighted < 2; ++weighted) {
    OctahedralSetup s(ellipsoid, DomainMetric::right_isosceles);
    SurfaceMap map(s.geometry, s.pm, {.curvature_weight = weighted ? 2.0 : 0.0});
    refine(map);
    ASSERT_EQ(map.validate(), std::nullopt);
    double tips = 0, total = 0;
    for (std::size_t t = 0; t < map.n_faces(); ++t) {
      SurfaceMap::FaceChart chart;
      ASSERT_TRUE(map.face_chart(int(t), chart));
      const Vec2 u = chart.corner[1] - chart.corner[0], w = chart.corner[2] - chart.corner[0];
      const double area = 0.5 * (u.x() * w.y() - u.y() * w.x());
      const Triangle& f = map.faces()[t];
      const auto& p = map.positions();
      total += area;
      if (std::abs((p[f[0]] + p[f[1]] + p[f[2]]).x() / 3) > 2.2) tips += area;
    }
    tip_share[weighted] = tips / total;
  }
  std::printf("domain share of the tips |x| > 2.2: plain %.4f, curvature-weighted %.4f\n",
              tip_share[0], tip_share[1]);
  EXPECT_GT(tip_share[1], 1.1 * tip_share[0]);
}

// A kernel a millionth of a unit across and ten thousand times thinner,
// a hundredth of a unit from the origin, as vertex splits meet in the
// squeezed corners of a map: its centroid is inside it (every triangle
// with the ring positive). Summed in absolute coordinates, the centroid's
// error (~1e-6) exceeded the kernel's thickness.
TEST(KernelCentroid, ThinKernelFarFromTheOrigin) {
  const Vec2 o(0.0096924177745443697, 0.0095036769543857657);
  for (const double thickness : {1e-10, 1e-12}) {
    const std::vector<Vec2> ring{o, o + Vec2(1e-6, 2e-7), o + Vec2(0.4e-6, 0.8e-7 + thickness)};
    const std::optional<Vec2> c = kernel_centroid(ring);
    ASSERT_TRUE(c.has_value()) << thickness;
    for (std::size_t i = 0; i < ring.size(); ++i)
      EXPECT_GT(orient(*c, ring[i], ring[(i + 1) % ring.size()]), 0.0) << thickness << " " << i;
  }
  // An empty kernel (a clockwise ring) has no centroid.
  EXPECT_FALSE(kernel_centroid({Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)}).has_value());
}

// The ring (a square around the origin) and the bowl of these tests:
// anisotropic, its minimum 1 at kBowlTarget, counting its evaluations.
const std::vector<Vec2> kBowlRing{Vec2(1, 0), Vec2(0, 1), Vec2(-1, 0), Vec2(0, -1)};
const Vec2 kBowlTarget(0.21, -0.13);
auto counting_bowl(std::size_t& calls) {
  return [&calls](const Vec2& q) {
    ++calls;
    const Vec2 d = q - kBowlTarget;
    return 1 + 3 * d.x() * d.x() + d.y() * d.y() + d.x() * d.y();
  };
}

// Both line-search rules find the minimum of a smooth energy inside the
// kernel of a ring (an anisotropic bowl whose minimum is off the axes of the
// start), never return an invalid place (HUGE_VAL beyond a line through the
// ring), and the parabolic rule needs fewer evaluations.
TEST(MinimizeInKernel, ParabolicRuleFindsTheMinimumWithFewerEvaluations) {
  const std::vector<Vec2>& ring = kBowlRing;
  const Vec2 target = kBowlTarget;
  std::size_t calls = 0;
  const auto bowl = counting_bowl(calls);
  std::array<std::size_t, 2> used{};
  std::array<Vec2, 2> found;
  for (const LineSearch rule : {LineSearch::golden, LineSearch::parabolic}) {
    calls = 0;
    Vec2 p(-0.3, 0.2);  // energy 1.3
    const double e = minimize_in_kernel(ring, p, bowl, rule);
    used[rule == LineSearch::parabolic] = calls;
    found[rule == LineSearch::parabolic] = p;
    // Two rounds of two line searches: near the minimum, not on it.
    EXPECT_LT(e, 1 + 1e-3) << int(rule);
    EXPECT_LT((p - target).norm(), 0.02) << int(rule);
  }
  // The same point whichever rule (each line minimum to 1e-6 of the ring).
  EXPECT_LT((found[0] - found[1]).norm(), 1e-5);
  std::printf("evaluations: golden %zu, parabolic %zu\n", used[0], used[1]);
  EXPECT_LT(2 * used[1], used[0] + 10);
  // Invalid beyond x + y = 0.2: the minimum found is on the valid side.
  for (const LineSearch rule : {LineSearch::golden, LineSearch::parabolic}) {
    Vec2 p(-0.3, 0.2);
    const double e = minimize_in_kernel(
        ring, p, [&](const Vec2& q) { return q.x() + q.y() > 0.2 ? HUGE_VAL : bowl(q); }, rule);
    EXPECT_LT(e, HUGE_VAL) << int(rule);
    EXPECT_LE(p.x() + p.y(), 0.2) << int(rule);
    EXPECT_LT(e, bowl(Vec2(-0.3, 0.2))) << int(rule);
  }
}

// KernelSearch::model_seed: each line search starts from the step a
// quadratic model of the energy predicts (from the gradient's differences
// and one evaluation more). On the quadratic bowl the model is exact: the
// seeded line searches end where the unseeded ones do, at least as low,
// with about half the evaluations; on a bowl with a quartic term the
// model is not exact and a seeded round still gets within 1e-4 of an
// unseeded one, with no more evaluations.
TEST(MinimizeInKernel, ModelSeededLineSearchesNeedFewerEvaluations) {
  std::size_t calls = 0;
  const auto bowl = counting_bowl(calls);
  auto quartic = [&](const Vec2& q) {
    const Vec2 d = q - kBowlTarget;
    return bowl(q) + 40 * d.squaredNorm() * d.squaredNorm();
  };
  for (const bool quadratic : {true, false}) {
    std::array<std::size_t, 2> used{};
    std::array<double, 2> reached{};
    std::array<Vec2, 2> found;
    for (const bool seed : {false, true}) {
      calls = 0;
      Vec2 p(-0.3, 0.2);
      KernelSearch search{1e-3, 1};
      search.model_seed = seed;
      const auto energy = [&](const Vec2& q) { return quadratic ? bowl(q) : quartic(q); };
      reached[seed] =
          minimize_in_kernel(kBowlRing, p, energy, LineSearch::parabolic, HUGE_VAL, search);
      used[seed] = calls;
      found[seed] = p;
    }
    std::printf("%s bowl: evaluations %zu unseeded, %zu seeded; energy %.9f, %.9f\n",
                quadratic ? "quadratic" : "quartic", used[0], used[1], reached[0], reached[1]);
    EXPECT_LE(used[1], used[0]) << quadratic;
    EXPECT_LT(reached[1], 1.3) << quadratic;  // (the start's energy)
    if (quadratic) {
      EXPECT_LT(2 * used[1], used[0] + 2);
      EXPECT_LE(reached[1], reached[0] + 1e-12);
      EXPECT_LT((found[1] - found[0]).norm(), 1e-3);
    } else {
      EXPECT_NEAR(reached[1], reached[0], 1e-4);
    }
  }
}

// newton_in_kernel: on a smooth energy with exact derivatives it reaches
// the minimum (to rounding) in a few steps, where two rounds of line
// searches get near it; a minimum beyond the kernel is not crossed to.
TEST(NewtonInKernel, ReachesTheMinimumInAFewSteps) {
  std::size_t calls = 0;
  const auto bowl = counting_bowl(calls);
  auto with_derivatives = [&](const Vec2& q, Vec2* g, Eigen::Matrix2d* h) {
    const Vec2 d = q - kBowlTarget;
    if (g) {
      *g = Vec2(6 * d.x() + d.y(), 2 * d.y() + d.x());
      *h << 6, 1, 1, 2;
    }
    return bowl(q);
  };
  Vec2 p(-0.3, 0.2);
  const double e = newton_in_kernel(kBowlRing, p, with_derivatives);
  EXPECT_NEAR(e, 1, 1e-15);
  EXPECT_LT((p - kBowlTarget).norm(), 1e-9);
  EXPECT_LE(calls, 6u);
  // The same bowl centred outside the ring (at (1.5, 0)): p stays inside.
  auto outside = [&](const Vec2& q, Vec2* g, Eigen::Matrix2d* h) {
    const Vec2 d = q - Vec2(1.5, 0);
    if (g) *g = 2 * d, *h = 2 * Eigen::Matrix2d::Identity();
    return d.squaredNorm();
  };
  Vec2 r(0, 0);
  const double f = newton_in_kernel(kBowlRing, r, outside);
  EXPECT_LT(f, 2.25);
  EXPECT_LT(std::abs(r.x()) + std::abs(r.y()), 1.0);
  EXPECT_GT(r.x(), 0.5);
}

// give_up_above: a bound the first round gets below changes nothing; one it
// does not get below ends the search after that round (fewer evaluations,
// short of what the second round would have gained).
TEST(MinimizeInKernel, GivesUpAfterARoundThatStaysAboveTheBound) {
  std::size_t calls = 0;
  const auto bowl = counting_bowl(calls);
  auto run = [&](double bound, Vec2& p) {
    calls = 0;
    p = Vec2(-0.3, 0.2);
    const double e = minimize_in_kernel(kBowlRing, p, bowl, LineSearch::parabolic, bound);
    return std::pair{e, calls};
  };
  Vec2 p_free, p_loose, p_tight;
  const auto [e_free, n_free] = run(HUGE_VAL, p_free);
  const auto [e_loose, n_loose] = run(1.3, p_loose);  // the start's energy: round 1 gets below
  EXPECT_EQ(e_loose, e_free);
  EXPECT_EQ(p_loose, p_free);
  EXPECT_EQ(n_loose, n_free);
  const auto [e_tight, n_tight] = run(0.5, p_tight);  // below the minimum: one round
  EXPECT_LT(n_tight, n_free);
  EXPECT_GT(e_tight, e_free);  // the second round still gained
  EXPECT_LT(e_tight, 1.3);
}

}  // namespace
}  // namespace ism

namespace ism {
namespace {

// Refinement validated after every split and the optimisation that follows
// it and after every sweep, then random operations (vertex moves and cone
// relocations, disc re-embeddings) in a fixed pseudo-random order, each
// validated and each lowering the energy by what it reports.
// The map's meta-mesh validates from both sides (map/meta_mesh.hpp).
void expect_valid_meta_mesh(const SurfaceMap& map) {
  const auto meta = meta_mesh(map);
  ASSERT_TRUE(meta.has_value());
  EXPECT_EQ(validate(*meta), std::nullopt) << "at " << map.n_vertices() << " vertices";
}

void refine_and_shake(const TriangleMesh& domain_mesh, const std::vector<FaceLengths>& lengths,
                      const PathNetwork& network) {
  const DomainGeometry geometry(domain_mesh, lengths);
  const ProgressiveMesh pm = simplify_constrained(network, domain_mesh);
  SurfaceMap map(geometry, pm);
  std::size_t last_sweep = map.n_vertices();
  for (int vs; (vs = map.split_next()) >= 0;) {
    ASSERT_EQ(map.validate(), std::nullopt) << "after split " << map.splits_applied();
    for (int w : map.neighbours(vs)) map.optimize_vertex(w);
    map.optimize_vertex(vs);
    ASSERT_EQ(map.validate(), std::nullopt) << "after optimising split " << map.splits_applied();
    if (map.n_vertices() >= 3 * last_sweep / 2) {
      optimization_sweep(map);
      ASSERT_EQ(map.validate(), std::nullopt) << "after a sweep at " << map.n_vertices();
      expect_valid_meta_mesh(map);
      last_sweep = map.n_vertices();
    }
  }
  std::uint64_t state = 12345;
  auto next = [&] {
    return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 33;
  };
  for (int i = 0; i < 400; ++i) {
    const int v = int(next() % map.positions().size());
    if (!map.is_active(v)) continue;
    const double before = map.energy();
    // Every eighth operation re-embeds the 2-ring disc around v whole.
    const double gain = map.is_pinned(v) ? map.relocate_cone(v)
                        : i % 8 == 0     ? reembed_disc(map, map.rings_around(v, 2))
                                         : map.optimize_vertex(v);
    ASSERT_EQ(map.validate(), std::nullopt) << "after operation " << i << " on vertex " << v;
    EXPECT_NEAR(before - map.energy(), gain, 1e-6 * before);
    if (i % 50 == 49) expect_valid_meta_mesh(map);
  }
}

TEST(SurfaceMap, ValidThroughoutOnADecimatedBase) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh bunny =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "bunny_small.obj")).mesh;
  const ProgressiveMesh decimated = simplify_to(bunny, 50);
  const TriangleMesh base = base_mesh(decimated);
  refine_and_shake(base, equilateral_lengths(base),
                   trace_path_network(bunny, base, decimated.base_vertices));
}

TEST(SurfaceMap, ValidThroughoutOnTheTorus) {
  const TriangleMesh grid = domain::torus_3x3();
  const TriangleMesh generated = shapes::torus(1500, 2, 1);
  refine_and_shake(grid, torus_3x3_lengths(grid), trace_torus_network(generated));
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh cup =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "cup.obj")).mesh;
  refine_and_shake(grid, torus_3x3_lengths(grid), trace_torus_network(cup));
}

}  // namespace
}  // namespace ism

namespace ism {
namespace {

// Bases with vertices of valence 7 and more put cones of more than 2π on the
// surface; a split that hands most of such a cone to the new vertex must
// move the cone with it (these two used to fail with "invalid ring").
TEST(SurfaceMap, ConesWiderThanAFullTurnFollowTheirSplit) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const auto& [file, size] :
       {std::pair<const char*, std::size_t>{"eight_loop2.obj", 50}, {"double_torus.obj", 100}}) {
    SCOPED_TRACE(file);
    const TriangleMesh s =
        prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file)).mesh;
    const ProgressiveMesh decimated = simplify_to(s, size);
    const TriangleMesh base = base_mesh(decimated);
    const DomainGeometry geometry(base, equilateral_lengths(base));
    bool wide_cone = false;
    for (std::size_t x = 0; x < base.n_vertices(); ++x)
      wide_cone |= geometry.total_angle(int(x)) > 2 * M_PI + 1e-9;
    EXPECT_TRUE(wide_cone);
    const PathNetwork network = trace_path_network(s, base, decimated.base_vertices);
    const ProgressiveMesh pm = simplify_constrained(network, base);
    SurfaceMap map(geometry, pm);
    refine(map);
    EXPECT_EQ(map.validate(), std::nullopt);
    EXPECT_EQ(map.n_vertices(), network.surface.n_vertices());
  }
}

}  // namespace
}  // namespace ism

namespace ism {
namespace {

// The teapot's thin handle makes paths that wind around it once more much
// shorter than the right ones: with the feature file's grid traced by plain
// shortest paths the map stayed twisted (one-way efficiency 0.03); paths
// held in the harmonic map's homotopy class give an untwisted map (paper
// Table 1: 0.458).
TEST(SurfaceMap, TeapotFeatureGridMapsWithoutTwists) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh teapot =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "teapot.obj")).mesh;
  const auto file = test::shared_models_dir() / "teapot_features_3x3.txt";
  const auto features = io::resolve_features(io::read_feature_file(file), teapot, 3, file.string());
  const TriangleMesh grid = domain::torus_3x3();
  const DomainGeometry geometry(grid, torus_3x3_lengths(grid));
  const PathNetwork network = trace_torus_network(teapot, features);
  const ProgressiveMesh pm = simplify_constrained(network, grid);
  SurfaceMap map(geometry, pm);
  refine(map);
  EXPECT_EQ(map.validate(), std::nullopt);
  const MapMeasures m = map.measures();
  std::printf("  teapot with its feature file: one-way efficiency %.3f (paper 0.458)\n",
              m.forward_efficiency);
  EXPECT_GT(m.forward_efficiency, 0.30);
}

}  // namespace
}  // namespace ism
