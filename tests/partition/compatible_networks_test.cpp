// Compatible networks on two surfaces and their two progressive meshes (issue
// 16): generated surfaces of genus 0, 1 and 2, open ones, refusals of bad
// input, and every pair of the acceptance list from ../shared.
#include "partition/compatible_networks.hpp"
#include "compatible_checks.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "open_surfaces.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <map>

namespace ism {
namespace {

struct Partitioned {
  CompatibleNetworks networks;
  std::array<ProgressiveMesh, 2> pms;
};

Partitioned partition_and_check(const TriangleMesh& a, const TriangleMesh& b,
                                const std::vector<std::array<int, 2>>& pairs) {
  Partitioned r;
  r.networks = trace_compatible_networks(a, b, pairs);
  r.pms = simplify_compatible(r.networks);
  test::expect_compatible(r.networks, r.pms, {&a, &b});
  // The given pairs are base vertices 0..n-1, in order.
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    EXPECT_EQ(r.networks.features[k].vertex, pairs[k]);
    EXPECT_EQ(r.networks.features[k].origin, FeatureOrigin::given);
  }
  return r;
}

std::size_t added(const CompatibleNetworks& n) {
  std::size_t count = 0;
  for (const FeaturePair& f : n.features) count += f.origin != FeatureOrigin::given;
  return count;
}

TriangleMesh cut(const TriangleMesh& mesh, const std::function<bool(const Vec3&)>& keep) {
  return test::keep_faces(mesh, keep);
}

// A vertex on the boundary, the one with the largest coordinate `axis`.
int boundary_vertex(const TriangleMesh& mesh, int axis, double sign, double above, double below) {
  std::map<std::pair<int, int>, int> uses;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  int best = -1;
  for (const auto& [e, n] : uses) {
    if (n != 1) continue;
    for (int v : {e.first, e.second}) {
      const double z = mesh.positions[v].z();
      if (z < above || z > below) continue;
      if (best < 0 || sign * mesh.positions[v][axis] > sign * mesh.positions[best][axis]) best = v;
    }
  }
  return best;
}

TEST(CompatibleNetworks, GenusZeroWithoutPairsGetsFourFeatures) {
  const TriangleMesh a = shapes::sphere(2000), b = shapes::ellipsoid(3000, {2.0, 1.0, 0.6});
  const Partitioned r = partition_and_check(a, b, {});
  EXPECT_EQ(r.networks.base.n_vertices(), 4u);
  for (const FeaturePair& f : r.networks.features) EXPECT_EQ(f.origin, FeatureOrigin::automatic);
  EXPECT_EQ(r.networks.genus, 0);
}

TEST(CompatibleNetworks, GenusZeroWithPairs) {
  const TriangleMesh a = shapes::blob(4000, 3, 0.3), b = shapes::ellipsoid(3000, {2.0, 1.0, 0.6});
  // Extremes of each along the axes, paired axis by axis.
  std::vector<std::array<int, 2>> pairs;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      std::array<int, 2> p{0, 0};
      for (int s = 0; s < 2; ++s) {
        const TriangleMesh& m = s ? b : a;
        for (std::size_t v = 0; v < m.n_vertices(); ++v)
          if (sign * m.positions[v][axis] > sign * m.positions[p[s]][axis]) p[s] = int(v);
      }
      pairs.push_back(p);
    }
  const Partitioned r = partition_and_check(a, b, pairs);
  EXPECT_EQ(r.networks.base.n_vertices(), 6u);
  EXPECT_EQ(added(r.networks), 0u);
  EXPECT_EQ(r.networks.base.n_faces(), 8u);
}

TEST(CompatibleNetworks, TorusWithOnePairGetsItsFeaturesOnCycles) {
  const TriangleMesh a = shapes::torus(3000, 2.0, 1.0), b = shapes::torus(4500, 3.0, 0.6);
  const Partitioned r = partition_and_check(a, b, {{{0, 0}}});
  EXPECT_EQ(r.networks.genus, 1);
  EXPECT_GE(r.networks.base.n_vertices(), 7u);  // the smallest torus triangulation
  EXPECT_EQ(euler_characteristic(r.networks.base), 0);
  bool on_cycle = false;
  for (const FeaturePair& f : r.networks.features) on_cycle |= f.origin == FeatureOrigin::cycle;
  EXPECT_TRUE(on_cycle);
}

TEST(CompatibleNetworks, DoubleTorusWithoutPairs) {
  const TriangleMesh a = shapes::double_torus(4000), b = shapes::double_torus(6000);
  const Partitioned r = partition_and_check(a, b, {});
  EXPECT_EQ(r.networks.genus, 2);
  EXPECT_EQ(euler_characteristic(r.networks.base), -2);
}

TEST(CompatibleNetworks, DiscsAreCappedAndClipped) {
  const TriangleMesh a = cut(shapes::sphere(3000), [](const Vec3& c) { return c.z() < 0.5; });
  const TriangleMesh b =
      cut(shapes::ellipsoid(4000, {1.5, 1.0, 0.8}), [](const Vec3& c) { return c.z() < 0.3; });
  const Partitioned r = partition_and_check(a, b, {});
  EXPECT_EQ(r.networks.boundary_loops, 1u);
  EXPECT_EQ(r.networks.capped.loops, 1u);
  // The base is open like the surfaces: one boundary loop through the clip
  // features, which lie on the surfaces' boundaries.
  EXPECT_EQ(test::count_boundary_loops(r.networks.base), 1u);
  std::size_t clips = 0;
  for (const FeaturePair& f : r.networks.features) clips += f.origin == FeatureOrigin::clip;
  EXPECT_GE(clips, 3u);
  // Some splits are boundary splits with one wing.
  std::size_t one_wing = 0;
  for (const VertexSplit& s : r.pms[0].splits) one_wing += s.vl < 0 || s.vr < 0;
  EXPECT_GT(one_wing, 0u);
}

TEST(CompatibleNetworks, TwoLoopsMatchedByBoundaryPairs) {
  auto band = [](const TriangleMesh& m, double top, double bottom) {
    return cut(m, [=](const Vec3& c) { return c.z() < top && c.z() > bottom; });
  };
  const TriangleMesh a = band(shapes::sphere(3000), 0.6, -0.6);
  const TriangleMesh b = band(shapes::ellipsoid(4000, {1.5, 1.0, 1.0}), 0.6, -0.6);
  // The two loops have about the same length: which is which is ambiguous.
  EXPECT_THROW(trace_compatible_networks(a, b, {}), PartitionError);
  // A pair on each loop settles it (the top loop of A to the top one of B).
  const std::vector<std::array<int, 2>> pairs = {
      {boundary_vertex(a, 0, 1, 0.3, 1), boundary_vertex(b, 0, 1, 0.3, 1)},
      {boundary_vertex(a, 0, 1, -1, -0.3), boundary_vertex(b, 0, 1, -1, -0.3)}};
  const Partitioned r = partition_and_check(a, b, pairs);
  EXPECT_EQ(test::count_boundary_loops(r.networks.base), 2u);
}

TEST(CompatibleNetworks, IsDeterministic) {
  const TriangleMesh a = shapes::torus(2000, 2.0, 0.8), b = shapes::torus(2500, 2.5, 1.0);
  const CompatibleNetworks x = trace_compatible_networks(a, b, {});
  const CompatibleNetworks y = trace_compatible_networks(a, b, {});
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(x.networks[s].paths, y.networks[s].paths);
    EXPECT_EQ(x.networks[s].surface.triangles, y.networks[s].surface.triangles);
  }
  EXPECT_EQ(x.base.triangles, y.base.triangles);
}

void expect_refused(const TriangleMesh& a, const TriangleMesh& b,
                    const std::vector<std::array<int, 2>>& pairs, const std::string& words) {
  try {
    trace_compatible_networks(a, b, pairs);
    ADD_FAILURE() << "accepted; expected a refusal naming: " << words;
  } catch (const PartitionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(words), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
  }
}

TEST(CompatibleNetworks, RefusesBadInput) {
  const TriangleMesh sphere = shapes::sphere(1000), torus = shapes::torus(1000);
  const TriangleMesh ellipsoid = shapes::ellipsoid(1200, {2, 1, 1});
  const TriangleMesh disc = cut(sphere, [](const Vec3& c) { return c.z() < 0.5; });
  expect_refused(sphere, torus, {}, "genus");
  expect_refused(sphere, disc, {}, "boundary loop");
  expect_refused(sphere, ellipsoid, {{5, 99999}}, "out of range");
  expect_refused(sphere, ellipsoid, {{5, -1}}, "out of range");
  expect_refused(sphere, ellipsoid, {{5, 6}, {5, 7}}, "same vertex 5");
  expect_refused(sphere, ellipsoid, {{5, 6}, {8, 6}}, "same vertex 6");
  // A boundary vertex paired with an interior one.
  const int on_loop = boundary_vertex(disc, 0, 1, -1, 1);
  const TriangleMesh disc2 = cut(ellipsoid, [](const Vec3& c) { return c.z() < 0.4; });
  int interior = 0;
  while (interior == on_loop || disc.positions[interior].z() > 0) ++interior;
  expect_refused(disc, disc2, {{interior, boundary_vertex(disc2, 0, 1, -1, 1)}}, "boundary");
  // Boundary features in opposite orders along the corresponding loops.
  const std::vector<std::array<int, 2>> crossed = {
      {boundary_vertex(disc, 0, 1, -1, 1), boundary_vertex(disc2, 0, 1, -1, 1)},
      {boundary_vertex(disc, 1, 1, -1, 1), boundary_vertex(disc2, 1, -1, -1, 1)},
      {boundary_vertex(disc, 0, -1, -1, 1), boundary_vertex(disc2, 0, -1, -1, 1)}};
  expect_refused(disc, disc2, crossed, "different orders");
}

// ---- ../shared -------------------------------------------------------------

TriangleMesh read_shared(const std::filesystem::path& path) {
  return prepare_mesh(io::read_polygon_soup(path)).mesh;
}

struct SharedPair {
  const char* name;
  const char* folder;  // "pairs" or "models"
  const char* a;
  const char* b;
  bool with_pairs;  // A__B.pairs.txt beside them
};

const SharedPair kShared[] = {
    {"cat_horse", "pairs", "cat", "horse", true},
    {"rabbit", "pairs", "rabbit0", "rabbit1", true},
    {"hands", "pairs", "hand_plain", "hand_vulcan", true},
    {"plane_bird", "pairs", "plane61", "bird248", true},
    {"vase", "pairs", "vase_A", "vase_B", true},
    {"bumpy_cube", "pairs", "bumpy_cube_A", "bumpy_cube_B", true},
    {"teapot_cup", "models", "teapot", "cup", false},
    {"mug_cup", "models", "mug", "cup", false},
    {"bob_torus", "models", "bob", "torus", false},
    {"double_torus_eight", "models", "double_torus", "eight_loop2", false},
    {"eight_feline", "models", "eight_loop2", "feline", false},
    {"spot_bunny", "models", "spot", "bunny_small", false},
    {"max_planck_igea", "models", "max_planck", "igea", false},
    {"face_camelhead", "models", "face", "camelhead", false},
    {"venus_mannequin", "models", "venus_loop2", "mannequin_devil", false},
};

void PrintTo(const SharedPair& p, std::ostream* os) {
  *os << p.a << " / " << p.b;
}

class SharedPairs : public ::testing::TestWithParam<SharedPair> {};

TEST_P(SharedPairs, CompatibleNetworksAndExactReplay) {
  ISM_REQUIRE_SHARED_MODELS();
  const SharedPair& p = GetParam();
  const auto dir = test::shared_dir() / p.folder;
  const TriangleMesh a = read_shared(dir / (std::string(p.a) + ".obj"));
  const TriangleMesh b = read_shared(dir / (std::string(p.b) + ".obj"));
  std::vector<std::array<int, 2>> pairs;
  if (p.with_pairs)
    pairs =
        io::read_feature_pairs(dir / (std::string(p.a) + "__" + p.b + ".pairs.txt"), a, b).pairs;
  const Partitioned r = partition_and_check(a, b, pairs);
  std::printf("%s: base V %zu E %zu F %zu, given %zu, added %zu, Steiner %zu / %zu\n", p.name,
              r.networks.base.n_vertices(),
              r.networks.base.n_vertices() + r.networks.base.n_faces() -
                  std::size_t(euler_characteristic(r.networks.base)),
              r.networks.base.n_faces(), pairs.size(), added(r.networks),
              r.networks.networks[0].steiner_vertices(), r.networks.networks[1].steiner_vertices());
}

INSTANTIATE_TEST_SUITE_P(Acceptance, SharedPairs, ::testing::ValuesIn(kShared),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(CompatibleNetworksShared, FourCatHorseLandmarks) {
  ISM_REQUIRE_SHARED_MODELS();
  const auto dir = test::shared_dir() / "pairs";
  const TriangleMesh a = read_shared(dir / "cat.obj"), b = read_shared(dir / "horse.obj");
  auto pairs = io::read_feature_pairs(dir / "cat__horse.pairs.txt", a, b).pairs;
  pairs.resize(4);
  const Partitioned r = partition_and_check(a, b, pairs);
  EXPECT_GE(r.networks.base.n_vertices(), 4u);
}

TEST(CompatibleNetworksShared, OnePairOnGenusOneAndTwo) {
  ISM_REQUIRE_SHARED_MODELS();
  {
    const auto dir = test::shared_dir() / "pairs";
    const TriangleMesh a = read_shared(dir / "vase_A.obj"), b = read_shared(dir / "vase_B.obj");
    auto pairs = io::read_feature_pairs(dir / "vase_A__vase_B.pairs.txt", a, b).pairs;
    pairs.resize(1);
    const Partitioned r = partition_and_check(a, b, pairs);
    EXPECT_GE(added(r.networks), 6u);  // at least 7 vertices on a torus
  }
  {
    const auto dir = test::shared_models_dir();
    const TriangleMesh a = read_shared(dir / "double_torus.obj");
    const TriangleMesh b = read_shared(dir / "eight_loop2.obj");
    const Partitioned r = partition_and_check(a, b, {{{0, 0}}});
    EXPECT_EQ(r.networks.genus, 2);
    EXPECT_GE(added(r.networks), 9u);  // at least 10 vertices on a genus-2 surface
  }
}

TEST(CompatibleNetworksShared, FeatureOnTheBoundaryStaysThere) {
  ISM_REQUIRE_SHARED_MODELS();
  const auto dir = test::shared_models_dir();
  const TriangleMesh a = read_shared(dir / "face.obj"), b = read_shared(dir / "camelhead.obj");
  const std::array<int, 2> pair{boundary_vertex(a, 1, 1, -1e9, 1e9),
                                boundary_vertex(b, 1, 1, -1e9, 1e9)};
  const Partitioned r = partition_and_check(a, b, {pair});
  // Base vertex 0 is on the base's boundary: in two boundary edges.
  std::map<std::pair<int, int>, int> uses;
  for (const Triangle& t : r.networks.base.triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  int boundary_edges_at_0 = 0;
  for (const auto& [e, n] : uses) boundary_edges_at_0 += n == 1 && (e.first == 0 || e.second == 0);
  EXPECT_EQ(boundary_edges_at_0, 2);
}

}  // namespace
}  // namespace ism
