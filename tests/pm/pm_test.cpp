// Progressive meshes: constrained simplification of synthetic path networks
// down to the domain, unconstrained simplification to a vertex count, and
// exact replay of the vertex splits.
#include "pm/pm.hpp"

#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh_checks.hpp"
#include "shapes/shapes.hpp"
#include "synthetic_network.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <chrono>
#include <cstring>
#include <stdexcept>

namespace ism {
namespace {

using test::Embedding;
using test::face_set;
using test::GridOptions;
using test::SyntheticNetwork;

/// Base mesh = the domain (vertex i = domain vertex i, same orientation);
/// base.triangles[f] = domain face f in features' indices.
void expect_base_is_domain(const ProgressiveMesh& pm, const SyntheticNetwork& s) {
  const TriangleMesh base = base_mesh(pm);
  EXPECT_EQ(pm.base_vertices, s.network.features);
  EXPECT_EQ(base.n_vertices(), s.domain.n_vertices());
  EXPECT_EQ(face_set(base.triangles), face_set(s.domain.triangles));
  ASSERT_EQ(pm.base.n_faces(), s.domain.n_faces());
  for (std::size_t f = 0; f < s.domain.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(pm.base.triangles[f][k], s.network.features[s.domain.triangles[f][k]]);
}

/// Replaying every split gives the input's faces and bit-identical positions.
void expect_replay_exact(const ProgressiveMesh& pm, const TriangleMesh& input) {
  const TriangleMesh full = replay(pm);
  EXPECT_EQ(face_set(full.triangles), face_set(input.triangles));
  ASSERT_EQ(full.n_vertices(), input.n_vertices());
  EXPECT_EQ(
      std::memcmp(full.positions.data(), input.positions.data(), input.n_vertices() * sizeof(Vec3)),
      0);
  EXPECT_EQ(pm.splits.size() + pm.base_vertices.size(), input.n_vertices());
}

/// Levels 0, 1/4, 1/2, 3/4 and all of the splits: closed manifolds with the
/// input's Euler characteristic and, for a network, the network intact.
void expect_levels_valid(const ProgressiveMesh& pm, const TriangleMesh& input,
                         const SyntheticNetwork* s) {
  const long euler = test::surface_topology(input).euler;
  const std::size_t n = pm.splits.size();
  for (std::size_t count : {std::size_t{0}, n / 4, n / 2, 3 * n / 4, n}) {
    SCOPED_TRACE("after " + std::to_string(count) + " of " + std::to_string(n) + " splits");
    const TriangleMesh level = replay(pm, count);
    const test::SurfaceTopology topology = test::surface_topology(level);
    EXPECT_EQ(topology.problem, std::nullopt);
    EXPECT_EQ(topology.euler, euler);
    EXPECT_EQ(topology.vertices, pm.base_vertices.size() + count);
    // Closed triangle mesh: 3F = 2E, so F = 2V - 2 chi.
    EXPECT_EQ(long(topology.faces), 2 * long(topology.vertices) - 2 * euler);
    if (s) {
      EXPECT_EQ(test::check_network_level(level, s->network, s->domain), std::nullopt);
    }
  }
}

void expect_same_splits(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  ASSERT_EQ(a.splits.size(), b.splits.size());
  for (std::size_t i = 0; i < a.splits.size(); ++i) {
    const VertexSplit &x = a.splits[i], &y = b.splits[i];
    ASSERT_TRUE(x.vs == y.vs && x.vt == y.vt && x.vl == y.vl && x.vr == y.vr &&
                x.position == y.position)
        << "split " << i;
  }
  EXPECT_EQ(a.base.triangles, b.base.triangles);
  EXPECT_EQ(a.base_vertices, b.base_vertices);
}

struct NetworkCase {
  const char* name;
  Embedding embedding;
  GridOptions grid;
};

class ConstrainedPm : public testing::TestWithParam<NetworkCase> {};

TEST_P(ConstrainedPm, EndsAtTheDomainAndReplaysExactly) {
  const NetworkCase& c = GetParam();
  const SyntheticNetwork s = test::grid_network(c.embedding, c.grid);
  // The construction itself is a valid network.
  ASSERT_EQ(test::check_network_level(s.network.surface, s.network, s.domain), std::nullopt);

  const ProgressiveMesh pm = simplify_constrained(s.network, s.domain);
  expect_base_is_domain(pm, s);
  expect_replay_exact(pm, s.network.surface);
  expect_levels_valid(pm, s.network.surface, &s);
  RecordProperty("relaxed_collapses", std::to_string(pm.relaxed_collapses));
  if (c.grid.scramble) {
    EXPECT_GT(pm.relaxed_collapses, 0u);
  }
  std::printf("  %s: %zu faces, %zu splits, %zu relaxed\n", c.name, s.network.surface.n_faces(),
              pm.splits.size(), pm.relaxed_collapses);
}

INSTANTIATE_TEST_SUITE_P(
    Networks, ConstrainedPm,
    testing::Values(
        NetworkCase{"octahedron_regular", Embedding::sphere, {.levels = 4}},
        NetworkCase{"octahedron_level1", Embedding::sphere, {.levels = 1}},
        NetworkCase{"octahedron_jittered",
                    Embedding::sphere,
                    {.levels = 4, .normal_jitter = 0.3, .seed = 3}},
        NetworkCase{"octahedron_irregular",
                    Embedding::sphere,
                    {.levels = 4, .irregularity = 0.4, .normal_jitter = 0.1}},
        NetworkCase{"octahedron_noisy",
                    Embedding::sphere,
                    {.levels = 3, .irregularity = 0.45, .normal_jitter = 3.0}},
        NetworkCase{"octahedron_scrambled", Embedding::sphere, {.levels = 3, .scramble = true}},
        NetworkCase{"torus_regular", Embedding::torus, {.levels = 3}},
        NetworkCase{"torus_level1", Embedding::torus, {.levels = 1}},
        NetworkCase{"torus_irregular",
                    Embedding::torus,
                    {.levels = 4, .irregularity = 0.4, .normal_jitter = 0.1}},
        NetworkCase{"torus_noisy",
                    Embedding::torus,
                    {.levels = 3, .irregularity = 0.45, .normal_jitter = 3.0}},
        NetworkCase{"torus_scrambled", Embedding::torus, {.levels = 3, .scramble = true}}),
    [](const testing::TestParamInfo<NetworkCase>& info) { return std::string(info.param.name); });

TEST(ConstrainedPmRuns, NetworkCheckOfTheTestsIsNotVacuous) {
  const SyntheticNetwork s = test::grid_network(Embedding::torus, {.levels = 2});
  const TriangleMesh& surface = s.network.surface;
  TriangleMesh flipped = s.domain;  // every domain face reversed
  for (Triangle& t : flipped.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(test::check_network_level(surface, s.network, flipped), std::nullopt);
  PathNetwork skipping = s.network;  // a path that jumps a vertex
  skipping.paths[3].erase(skipping.paths[3].begin() + 2);
  EXPECT_NE(test::check_network_level(surface, skipping, s.domain), std::nullopt);
  PathNetwork swapped = s.network;  // two paths exchanged
  std::swap(swapped.domain_edges[0], swapped.domain_edges[5]);
  EXPECT_NE(test::check_network_level(surface, swapped, s.domain), std::nullopt);
}

/// Number of collapses (splits read backwards) that turned a surviving face
/// by more than 90 degrees or made it degenerate, found by replaying level by
/// level: the faces around vs after split i, with vs put back onto vt.
std::size_t flipping_collapses(const ProgressiveMesh& pm) {
  std::size_t flips = 0;
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& s = pm.splits[i];
    const TriangleMesh fine = replay(pm, i + 1);
    bool flipped = false;
    for (const Triangle& t : fine.triangles) {
      const int k = t[0] == s.vs ? 0 : t[1] == s.vs ? 1 : t[2] == s.vs ? 2 : -1;
      if (k < 0 || t[0] == s.vt || t[1] == s.vt || t[2] == s.vt) continue;
      const Vec3& a = fine.positions[t[(k + 1) % 3]];
      const Vec3& b = fine.positions[t[(k + 2) % 3]];
      const Vec3& ps = fine.positions[s.vs];
      const Vec3& pt = fine.positions[s.vt];
      const Vec3 before = (a - ps).cross(b - ps), after = (a - pt).cross(b - pt);
      if (before.dot(after) < 0 || after.norm() == 0) flipped = true;
    }
    flips += flipped;
  }
  return flips;
}

TEST(ConstrainedPmRuns, FlipOnlyInRelaxedCollapses) {
  for (bool scramble : {false, true}) {
    const SyntheticNetwork s = test::grid_network(
        Embedding::sphere,
        {.levels = 3, .irregularity = 0.45, .normal_jitter = 3.0, .scramble = scramble});
    const ProgressiveMesh pm = simplify_constrained(s.network, s.domain);
    const std::size_t flips = flipping_collapses(pm);
    EXPECT_LE(flips, pm.relaxed_collapses);
    if (scramble) {
      EXPECT_GT(flips, 0u) << "the relaxed collapses should really flip";
    }
  }
}

TEST(ConstrainedPmRuns, AreDeterministic) {
  const SyntheticNetwork s = test::grid_network(
      Embedding::sphere, {.levels = 4, .irregularity = 0.3, .normal_jitter = 0.5});
  expect_same_splits(simplify_constrained(s.network, s.domain),
                     simplify_constrained(s.network, s.domain));
}

TEST(ConstrainedPmRuns, ReportProgressUpToOne) {
  const SyntheticNetwork s = test::grid_network(Embedding::torus, {.levels = 3});
  std::vector<double> reported;
  SimplifyOptions options;
  options.progress = [&](double f) { reported.push_back(f); };
  simplify_constrained(s.network, s.domain, options);
  ASSERT_FALSE(reported.empty());
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_DOUBLE_EQ(reported.back(), 1.0);
}

TEST(ConstrainedPmRuns, InputThatIsAlreadyTheBase) {
  const SyntheticNetwork s = test::grid_network(Embedding::sphere, {.levels = 0});
  const ProgressiveMesh pm = simplify_constrained(s.network, s.domain);
  EXPECT_TRUE(pm.splits.empty());
  expect_base_is_domain(pm, s);
}

TEST(ConstrainedPmRuns, RejectBrokenNetworks) {
  const SyntheticNetwork good = test::grid_network(Embedding::sphere, {.levels = 2});
  {
    SyntheticNetwork s = good;  // a feature missing
    s.network.features.pop_back();
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
  {
    SyntheticNetwork s = good;  // a path that skips a vertex
    s.network.paths[0].erase(s.network.paths[0].begin() + 1);
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
  {
    SyntheticNetwork s = good;  // a face in the wrong patch
    s.network.face_patch[0] = (s.network.face_patch[0] + 1) % 8;
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
  {
    SyntheticNetwork s = good;  // patches swapped consistently: wrong base faces
    for (int& p : s.network.face_patch) p = p == 0 ? 1 : p == 1 ? 0 : p;
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
  {
    SyntheticNetwork s = good;  // a torus domain on a sphere
    s.domain = domain::torus_3x3();
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
  {
    SyntheticNetwork s = good;  // a hole in the surface
    s.network.surface.triangles.pop_back();
    s.network.face_patch.pop_back();
    EXPECT_THROW(simplify_constrained(s.network, s.domain), std::runtime_error);
  }
}

// ---- simplify_to ---------------------------------------------------------

/// simplify_to(target): exactly target vertices, listed in increasing order,
/// same topology, exact replay, valid levels.
void expect_simplified(const TriangleMesh& mesh, std::size_t target,
                       const SimplifyOptions& options = {}) {
  const ProgressiveMesh pm = simplify_to(mesh, target, options);
  ASSERT_EQ(pm.base_vertices.size(), target);
  EXPECT_TRUE(std::is_sorted(pm.base_vertices.begin(), pm.base_vertices.end()));
  const TriangleMesh base = base_mesh(pm);
  const test::SurfaceTopology topology = test::surface_topology(base);
  EXPECT_EQ(topology.problem, std::nullopt);
  EXPECT_EQ(topology.vertices, target);
  EXPECT_EQ(topology.euler, test::surface_topology(mesh).euler);
  expect_replay_exact(pm, mesh);
  expect_levels_valid(pm, mesh, nullptr);
  std::printf("  %zu -> %zu vertices, %zu relaxed\n", mesh.n_vertices(), target,
              pm.relaxed_collapses);
}

TEST(SimplifyTo, SphereNetworkSurfaceTo20) {
  expect_simplified(test::grid_network(Embedding::sphere, {.levels = 4}).network.surface, 20);
}

TEST(SimplifyTo, TorusShapeTo50) {
  expect_simplified(shapes::torus(2000), 50);
}

TEST(SimplifyTo, DoubleTorusShapeTo30) {
  expect_simplified(shapes::double_torus(900), 30);
}

TEST(SimplifyTo, DownToATetrahedron) {
  expect_simplified(shapes::sphere(320), 4);
}

TEST(SimplifyTo, TargetAtOrAboveTheSizeChangesNothing) {
  const TriangleMesh mesh = shapes::sphere(80);
  const ProgressiveMesh pm = simplify_to(mesh, mesh.n_vertices() + 5);
  EXPECT_TRUE(pm.splits.empty());
  EXPECT_EQ(face_set(base_mesh(pm).triangles), face_set(mesh.triangles));
}

TEST(SimplifyTo, StopsAtTheTopologicalMinimum) {
  // A torus needs at least 7 vertices; asking for 4 ends where nothing is legal.
  const TriangleMesh mesh = shapes::torus(400);
  const ProgressiveMesh pm = simplify_to(mesh, 4);
  EXPECT_GE(pm.base_vertices.size(), 7u);
  EXPECT_EQ(test::surface_topology(base_mesh(pm)).euler, 0);
  expect_replay_exact(pm, mesh);
}

TEST(SimplifyTo, IsDeterministic) {
  const TriangleMesh mesh = shapes::blob(3000, 5);
  expect_same_splits(simplify_to(mesh, 50), simplify_to(mesh, 50));
}

TEST(SimplifyTo, RejectsOpenMeshes) {
  TriangleMesh mesh = shapes::sphere(80);
  mesh.triangles.pop_back();
  EXPECT_THROW(simplify_to(mesh, 20), std::runtime_error);
}

TEST(SimplifyTo, SharedModels) {
  ISM_REQUIRE_SHARED_MODELS();
  const std::pair<const char*, std::size_t> cases[] = {
      {"bunny_small.obj", 100}, {"torus.obj", 50}, {"eight.obj", 20}, {"double_torus.obj", 50}};
  for (const auto& [file, target] : cases) {
    SCOPED_TRACE(file);
    const PreparedMesh prepared =
        prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file));
    ASSERT_TRUE(prepared.check.valid_surface());
    expect_simplified(prepared.mesh, target);
    expect_simplified(prepared.mesh, target,
                      {.priority = SimplifyPriority::isotropic,
                       .valence_weight = 0.01,
                       .valence_from_curvature = true});
    EXPECT_EQ(test::surface_topology(base_mesh(simplify_to(prepared.mesh, target))).euler,
              2 - 2 * *prepared.check.genus);
  }
}

/// Mean and smallest shape quality 4√3·area/Σ|edge|² of the faces, and
/// Σ(valence − 6)² over the vertices.
struct BaseShape {
  double mean_quality = 0, worst_quality = 1, valence_deviation = 0;
};

BaseShape base_shape(const TriangleMesh& base) {
  BaseShape s;
  std::vector<int> valence(base.n_vertices(), 0);
  for (const Triangle& t : base.triangles) {
    const Vec3 &a = base.positions[t[0]], &b = base.positions[t[1]], &c = base.positions[t[2]];
    const double q = 2 * std::sqrt(3.0) * (b - a).cross(c - a).norm() /
                     ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm());
    s.mean_quality += q / double(base.n_faces());
    s.worst_quality = std::min(s.worst_quality, q);
    for (int v : t) ++valence[v];
  }
  for (int k : valence) s.valence_deviation += (k - 6) * (k - 6);
  return s;
}

// Base domains are mapped face by face onto equilateral triangles: the
// isotropic priority must give better-shaped faces than the quadric one, and
// the valence term valences closer to 6, each base still a valid level of
// an exactly replayable progressive mesh.
TEST(SimplifyTo, IsotropicPriorityGivesWellShapedBases) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const char* file : {"bunny_small.obj", "rocker_arm.obj"}) {
    SCOPED_TRACE(file);
    const TriangleMesh mesh =
        prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file)).mesh;
    const BaseShape quadric = base_shape(base_mesh(simplify_to(mesh, 100)));
    const SimplifyOptions isotropic{.priority = SimplifyPriority::isotropic};
    const BaseShape even = base_shape(base_mesh(simplify_to(mesh, 100, isotropic)));
    SimplifyOptions regular = isotropic;
    regular.valence_weight = 0.05;
    const BaseShape valences = base_shape(base_mesh(simplify_to(mesh, 100, regular)));
    std::printf(
        "  quality mean/min, valence deviation: quadric %.3f/%.3f/%.0f, isotropic "
        "%.3f/%.3f/%.0f, with valences %.3f/%.3f/%.0f\n",
        quadric.mean_quality, quadric.worst_quality, quadric.valence_deviation, even.mean_quality,
        even.worst_quality, even.valence_deviation, valences.mean_quality, valences.worst_quality,
        valences.valence_deviation);
    EXPECT_GT(even.mean_quality, quadric.mean_quality + 0.03);
    EXPECT_GT(even.mean_quality, 0.85);
    EXPECT_GT(even.worst_quality, quadric.worst_quality);
    EXPECT_LT(valences.valence_deviation, even.valence_deviation);
    expect_simplified(mesh, 100, regular);
  }
}

// ---- replay --------------------------------------------------------------

TEST(Replay, RejectsASplitThatDoesNotFit) {
  ProgressiveMesh pm = simplify_to(shapes::sphere(80), 10);
  pm.splits[0].vl = pm.splits[0].vt;  // no face (vt, vt, *)
  EXPECT_THROW(replay(pm), std::runtime_error);
}

TEST(Replay, CountBeyondTheEndReplaysAll) {
  const TriangleMesh mesh = shapes::sphere(80);
  const ProgressiveMesh pm = simplify_to(mesh, 10);
  EXPECT_EQ(face_set(replay(pm, pm.splits.size() + 100).triangles), face_set(mesh.triangles));
}

// Timing on ~131K faces; run with --gtest_also_run_disabled_tests.
TEST(Timing, DISABLED_OctahedronLevel7) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  };
  for (int levels : {6, 7}) {
    const SyntheticNetwork s = test::grid_network(
        Embedding::sphere, {.levels = levels, .irregularity = 0.3, .normal_jitter = 0.2});
    auto t0 = Clock::now();
    const ProgressiveMesh constrained = simplify_constrained(s.network, s.domain);
    const double t_constrained = seconds(t0);
    t0 = Clock::now();
    const ProgressiveMesh free = simplify_to(s.network.surface, 100);
    const double t_free = seconds(t0);
    t0 = Clock::now();
    const TriangleMesh full = replay(constrained);
    const double t_replay = seconds(t0);
    std::printf(
        "  %zu faces: simplify_constrained %.3f s (%zu relaxed), simplify_to(100) %.3f s,"
        " replay %.3f s\n",
        s.network.surface.n_faces(), t_constrained, constrained.relaxed_collapses, t_free,
        t_replay);
    EXPECT_EQ(full.n_faces(), s.network.surface.n_faces());
    EXPECT_EQ(free.base_vertices.size(), 100u);
  }
}

}  // namespace
}  // namespace ism
