// The symmetric map core: two surfaces, both refined, validated from both
// sides after every operation.
#include "map/inter_surface_map.hpp"
#include "domain/domain.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace ism {
namespace {

/// A progressive mesh of a genus-0 surface down to the octahedron.
ProgressiveMesh octahedral_pm(const TriangleMesh& surface) {
  return simplify_constrained(trace_octahedral_network(surface), domain::octahedron());
}

/// Refines both sides in turn (the side less refined first), optimising
/// every new vertex and its neighbours; validates after every operation and
/// checks that each kept move lowers the energy by its reported gain.
void refine_both_checked(InterSurfaceMap& map, std::size_t validate_every, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::size_t operations = 0;
  auto check = [&](const char* what, int side, int v) {
    if (++operations % validate_every) return;
    const auto problem = map.validate();
    ASSERT_FALSE(problem) << what << " side " << side << " vertex " << v << ": " << *problem;
  };
  for (;;) {
    const double f0 = map.splits_total(0) ? double(map.splits_applied(0)) / map.splits_total(0) : 1;
    const double f1 = map.splits_total(1) ? double(map.splits_applied(1)) / map.splits_total(1) : 1;
    if (f0 >= 1 && f1 >= 1) break;
    const int side = f0 <= f1 ? 0 : 1;
    const int vs = map.split_next(side);
    ASSERT_GE(vs, 0);
    check("split", side, vs);
    if (::testing::Test::HasFatalFailure()) return;
    std::vector<int> todo = map.neighbours(side, vs);
    todo.push_back(vs);
    std::shuffle(todo.begin(), todo.end(), random);
    for (int v : todo) {
      const double before = map.energy();
      const double gain = map.optimize_vertex(side, v);
      const double after = map.energy();
      ASSERT_GE(gain, 0.0);
      ASSERT_NEAR(before - after, gain, 1e-9 * before) << "side " << side << " vertex " << v;
      if (gain > 0) check("optimising", side, v);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

TEST(InterSurfaceMap, TrivialMapOfTwoBasesIsValid) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(300);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  EXPECT_FALSE(map.validate());
  EXPECT_GT(map.measures().symmetric_efficiency, 0.0);
  EXPECT_EQ(map.n_vertices(0), 6u);
  EXPECT_EQ(map.n_faces(1), 8u);
}

TEST(InterSurfaceMap, SmallPairIsDeterministic) {
  const TriangleMesh a = shapes::sphere(100), b = shapes::blob(120, 5);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  std::array<double, 2> energy{};
  for (int run = 0; run < 2; ++run) {
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
    refine_both_checked(map, 10, 7);
    if (HasFatalFailure()) return;
    energy[run] = map.energy();
  }
  EXPECT_EQ(energy[0], energy[1]);
}

TEST(InterSurfaceMap, BothSidesRefineSphereAndBlob) {
  const TriangleMesh a = shapes::sphere(300), b = shapes::blob(400, 3);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  refine_both_checked(map, 1, 1);
  if (HasFatalFailure()) return;
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(0), replay(pa).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pb).n_faces());
  const MapMeasures m = map.measures();
  const auto& st = map.stats();
  std::printf(
      "sphere %zu / blob %zu faces: symmetric efficiency %.4f (%.4f, %.4f); optimisations %zu, "
      "moves %zu, fast %zu, developed %zu, general %zu, rejected %zu\n",
      a.n_faces(), b.n_faces(), m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency,
      st.optimizations, st.moves, st.fast_path, st.developed, st.general, st.rejected);
  EXPECT_GT(m.symmetric_efficiency, 0.3);
}

}  // namespace
}  // namespace ism
