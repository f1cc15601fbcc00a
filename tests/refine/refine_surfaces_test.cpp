// Refinement of both sides of an InterSurfaceMap (refine_surfaces): every
// split and kept move is reported, each reported gain is the drop of the
// whole map's energy, no split leaves a near-degenerate piece behind, and
// the result is a valid map of both full-resolution surfaces.
#include "refine/refine_surfaces.hpp"
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/inter_surface_map.hpp"
#include "map/inter_surface_map_access.hpp"
#include "map/meta_mesh.hpp"
#include "map/surface_map.hpp"
#include "mesh/curvature.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/disc_relaxation.hpp"
#include "refine/refine.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace ism {
namespace {

/// Every InterSurfaceMap of this test binary rebuilds each chart that its
/// edit stamps declare unchanged since it was planned and throws if it
/// differs, and cuts each face it takes from its energy cache again.
const bool kCheckPlans = [] {
  return setenv("ISM_CHECK_PLANS", "1", 1) == 0 && setenv("ISM_CHECK_ENERGY_CACHE", "1", 1) == 0;
}();

TEST(RefineSurfaces, EveryStepIsReportedAndEachGainIsTheDropOfTheEnergy) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(240, 3);
  const TriangleMesh octahedron = domain::octahedron();
  const ProgressiveMesh pa = simplify_constrained(trace_octahedral_network(a), octahedron);
  const ProgressiveMesh pb = simplify_constrained(trace_octahedral_network(b), octahedron);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  SurfaceRefineOptions options;
  // Energy before each split, and the worst ratio of it to the one before
  // the previous split (the split and the moves after it).
  double energy = map.energy(), at_split = energy, worst_split = 0;
  std::size_t splits = 0, moves = 0;
  options.on_step = [&](const SurfaceStep& step) {
    const double after = map.energy();
    if (step.kind == SurfaceStep::split) {
      ++splits;
      EXPECT_GE(step.vertex, 0);
      worst_split = std::max(worst_split, energy / at_split);
      at_split = energy;
    } else {
      ++moves;
      EXPECT_GT(step.gain, 0.0);
      EXPECT_NEAR(energy - after, step.gain, 1e-9 * energy)
          << "move of vertex " << step.vertex << " of side " << step.side;
    }
    energy = after;
    // The refinement's thresholds read the energy from the per-face cache:
    // the very same number.
    if ((splits + moves) % 16 == 0) EXPECT_EQ(map.cached_energy(), after);
  };
  const SurfaceRefineStats stats = refine_surfaces(map, options);
  EXPECT_EQ(map.cached_energy(), map.energy());
  EXPECT_EQ(splits, pa.splits.size() + pb.splits.size());
  EXPECT_EQ(stats.splits, splits);
  EXPECT_LE(moves, map.stats().moves);  // also moves inside retried splits
  EXPECT_EQ(stats.energy, map.energy());
  EXPECT_EQ(map.n_faces(0), replay(pa).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pb).n_faces());
  EXPECT_FALSE(map.validate());
  // A split may raise the energy (two new vertices in a ring drawn for
  // one), but the moves after it leave no nearly degenerate piece (whose
  // energy is orders of magnitude above the map's).
  EXPECT_LT(worst_split, 2.0);
  EXPECT_GT(map.measures().symmetric_efficiency, 0.9);
  std::printf(
      "sphere %zu / blob %zu faces: %zu splits (worst energy ratio %.3f), %zu moves, "
      "symmetric efficiency %.4f\n",
      a.n_faces(), b.n_faces(), splits, worst_split, moves, map.measures().symmetric_efficiency);
}

/// A generated blob's progressive mesh down to the octahedron, and the
/// equilateral octahedron it maps to.
struct BlobOverOctahedron {
  ProgressiveMesh pm;
  DomainGeometry domain;
};
BlobOverOctahedron blob_over_octahedron(std::size_t faces) {
  const TriangleMesh octahedron = domain::octahedron();
  return {simplify_constrained(trace_octahedral_network(shapes::blob(faces, 2)), octahedron),
          DomainGeometry(octahedron, octahedron_lengths(octahedron, DomainMetric::equilateral))};
}

/// `surface_map` refined by SurfaceMap to `vertices` surface vertices.
void refine_to(SurfaceMap& surface_map, std::size_t vertices) {
  RefineOptions options;
  options.stop_at_vertices = vertices;
  refine(surface_map, options);
}

/// A blob's map over the octahedron refined by SurfaceMap to 150 surface
/// vertices, as a meta-mesh for InterSurfaceMap to resume (the remeshers'
/// takeover).
struct ResumedBlob {
  ProgressiveMesh pm;
  DomainGeometry domain;
  std::optional<MetaMesh> meta;
  std::array<std::size_t, 2> applied;
};
ResumedBlob resumed_blob() {
  auto [pm, domain] = blob_over_octahedron(800);
  SurfaceMap coarse(domain, pm);
  refine_to(coarse, 150);
  auto meta = meta_mesh(coarse);
  const std::array<std::size_t, 2> applied{0, coarse.splits_applied()};
  return {std::move(pm), std::move(domain), std::move(meta), applied};
}

// after_level is called after each level (both sides' vertices grown
// sweep_growth-fold); false stops the refinement there, the map valid at
// that size, and the same map as a refinement that goes on has there.
TEST(RefineSurfaces, AfterLevelSeesEachLevelAndMayStopTheRefinement) {
  ResumedBlob blob = resumed_blob();
  auto resume = [&] {
    return InterSurfaceMap(MetaMesh(*blob.meta), side_from_domain(blob.domain, blob.pm),
                           side_from_pm(blob.pm), blob.applied);
  };
  std::vector<std::size_t> sizes;
  std::vector<double> energies;
  InterSurfaceMap whole = resume();
  SurfaceRefineOptions options;
  options.after_level = [&](const InterSurfaceMap& m) {
    const std::size_t n = m.n_vertices(0) + m.n_vertices(1);
    if (!sizes.empty()) EXPECT_GE(double(n), options.sweep_growth * double(sizes.back()));
    sizes.push_back(n);
    energies.push_back(m.energy());
    return true;
  };
  const SurfaceRefineStats full = refine_surfaces(whole, options);
  EXPECT_FALSE(full.stopped);
  ASSERT_GE(sizes.size(), 2u);
  EXPECT_EQ(whole.n_faces(1), replay(blob.pm).n_faces());

  InterSurfaceMap stopped = resume();
  std::size_t calls = 0;
  options.after_level = [&](const InterSurfaceMap&) {
    ++calls;
    return false;
  };
  const SurfaceRefineStats part = refine_surfaces(stopped, options);
  EXPECT_TRUE(part.stopped);
  EXPECT_EQ(calls, 1u);
  EXPECT_EQ(stopped.n_vertices(0) + stopped.n_vertices(1), sizes[0]);
  EXPECT_EQ(stopped.energy(), energies[0]);
  EXPECT_EQ(part.energy, energies[0]);
  EXPECT_LT(part.splits, full.splits);
  EXPECT_EQ(part.final_sweeps, 0u);
  EXPECT_FALSE(stopped.validate());
}

// A level within final_level_merge of full resolution is left to the final
// sweeps: the levels before it are the same (the same sizes, the same map
// there), none follows, and the map still reaches full resolution, valid.
TEST(RefineSurfaces, ALevelCloseToFullResolutionIsLeftToTheFinalSweeps) {
  ResumedBlob blob = resumed_blob();
  auto resume = [&] {
    return InterSurfaceMap(MetaMesh(*blob.meta), side_from_domain(blob.domain, blob.pm),
                           side_from_pm(blob.pm), blob.applied);
  };
  auto levels = [&](InterSurfaceMap& map, double merge, SurfaceRefineStats& stats) {
    std::vector<std::pair<std::size_t, double>> seen;
    SurfaceRefineOptions options;
    options.final_level_merge = merge;
    options.after_level = [&](const InterSurfaceMap& m) {
      seen.push_back({m.n_vertices(0) + m.n_vertices(1), m.energy()});
      return true;
    };
    stats = refine_surfaces(map, options);
    return seen;
  };
  InterSurfaceMap every = resume();
  SurfaceRefineStats every_stats;
  const auto all = levels(every, 1, every_stats);
  ASSERT_GE(all.size(), 2u);
  const double full = double(every.n_vertices(0) + every.n_vertices(1));
  // Just enough to merge the last level, not the one before.
  const double merge = full / double(all.back().first) * (1 + 1e-9);
  ASSERT_LT(double(all[all.size() - 2].first) * merge, full);

  InterSurfaceMap merged = resume();
  SurfaceRefineStats merged_stats;
  const auto kept = levels(merged, merge, merged_stats);
  ASSERT_EQ(kept.size(), all.size() - 1);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    EXPECT_EQ(kept[k].first, all[k].first);
    EXPECT_EQ(kept[k].second, all[k].second);
  }
  EXPECT_LT(merged_stats.sweeps, every_stats.sweeps);
  EXPECT_GT(merged_stats.final_sweeps, 0u);
  EXPECT_EQ(merged.n_vertices(0) + merged.n_vertices(1), every.n_vertices(0) + every.n_vertices(1));
  EXPECT_EQ(merged.n_faces(1), replay(blob.pm).n_faces());
  EXPECT_FALSE(merged.validate());
}

// The coarse race (race_level_sweeps): each schedule's energy is that of a
// copy refined with it to the first level with race_faces faces on both
// sides, the lowest goes on, and a race of the one default schedule gives
// exactly the map of no race (a refinement stopped at a level and called
// again refines as one call).
TEST(RefineSurfaces, CoarseRaceKeepsTheLowestEnergyAndGoesOnAsOneCall) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(240, 3);
  const TriangleMesh octahedron = domain::octahedron();
  const ProgressiveMesh pa = simplify_constrained(trace_octahedral_network(a), octahedron);
  const ProgressiveMesh pb = simplify_constrained(trace_octahedral_network(b), octahedron);
  const InterSurfaceMap start(side_from_pm(pa), side_from_pm(pb));
  SurfaceRefineOptions options;
  options.threads = 1;
  options.race_faces = 60;
  options.race_fraction = 1;  // (race_faces decides)
  const std::vector<int> schedules{1, 3, 0};
  std::vector<double> alone;
  for (int k : schedules) {
    InterSurfaceMap copy = start;
    SurfaceRefineOptions o = options;
    o.max_level_sweeps = k;
    o.after_level = [&](const InterSurfaceMap& m) {
      return m.n_faces(0) < options.race_faces || m.n_faces(1) < options.race_faces;
    };
    ASSERT_TRUE(refine_surfaces(copy, o).stopped);
    EXPECT_GE(copy.n_faces(0), options.race_faces);
    EXPECT_GE(copy.n_faces(1), options.race_faces);
    alone.push_back(copy.energy());
  }
  // Different schedules give different maps (else the race decides nothing).
  EXPECT_NE(alone[0], alone[1]);

  InterSurfaceMap raced = start;
  options.race_level_sweeps = schedules;
  const SurfaceRefineStats stats = refine_surfaces(raced, options);
  ASSERT_EQ(stats.race_energies.size(), schedules.size());
  for (std::size_t k = 0; k < schedules.size(); ++k) EXPECT_EQ(stats.race_energies[k], alone[k]);
  const auto best = std::min_element(alone.begin(), alone.end()) - alone.begin();
  EXPECT_EQ(stats.race_winner, int(best));
  EXPECT_FALSE(stats.stopped);
  EXPECT_EQ(stats.splits, pa.splits.size() + pb.splits.size());
  EXPECT_EQ(raced.n_faces(0), replay(pa).n_faces());
  EXPECT_EQ(raced.n_faces(1), replay(pb).n_faces());
  EXPECT_FALSE(raced.validate());

  InterSurfaceMap plain = start, one = start;
  options.race_level_sweeps.clear();
  refine_surfaces(plain, options);
  options.race_level_sweeps = {options.max_level_sweeps};
  const SurfaceRefineStats single = refine_surfaces(one, options);
  EXPECT_EQ(single.race_winner, 0);
  EXPECT_EQ(one.energy(), plain.energy());
  EXPECT_EQ(one.measures().symmetric_efficiency, plain.measures().symmetric_efficiency);
}

/// A sphere and a blob, each simplified to the octahedron (its six
/// vertices the features), for the tests of held features.
std::array<ProgressiveMesh, 2> held_pair() {
  const TriangleMesh octahedron = domain::octahedron();
  return {simplify_constrained(trace_octahedral_network(shapes::sphere(200)), octahedron),
          simplify_constrained(trace_octahedral_network(shapes::blob(240, 3)), octahedron)};
}

// Features held, then released part of the way: the base vertices stay on
// each other through the first part of the splits and move after it (and
// never when release_features_at is negative).
TEST(RefineSurfaces, HeldFeaturesAreReleasedPartOfTheWay) {
  const auto [pa, pb] = held_pair();
  InterSurfaceOptions held;
  held.hold_features = true;
  const std::size_t total = pa.splits.size() + pb.splits.size();
  // How many base vertices of side 0 still sit on their partner's vertex.
  auto on_partners = [&](const InterSurfaceMap& map) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < pa.base_vertices.size(); ++i)
      n += map.meta().side[0].location[pa.base_vertices[i]].vertex == pb.base_vertices[i];
    return n;
  };
  for (const double at : {-1.0, 0.5}) {
    SCOPED_TRACE(at);
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb), held);
    SurfaceRefineOptions options;
    options.release_features_at = at;
    std::size_t splits = 0, moved_before = 0;
    bool released_seen = false;
    options.on_step = [&](const SurfaceStep& step) {
      if (step.kind == SurfaceStep::split) ++splits;
      const bool pinned = map.is_pinned(0, pa.base_vertices[0]);
      // Pinned until the batch that starts at half the splits (a batch is
      // at most split_batch long).
      if (double(splits) < 0.5 * double(total)) EXPECT_TRUE(pinned) << splits;
      if (!pinned) released_seen = true;
      if (double(splits) < 0.5 * double(total)) moved_before += on_partners(map) != 6;
    };
    refine_surfaces(map, options);
    EXPECT_EQ(moved_before, 0u);
    EXPECT_FALSE(map.validate());
    if (at < 0) {
      EXPECT_FALSE(released_seen);
      EXPECT_EQ(on_partners(map), 6u);
    } else {
      EXPECT_TRUE(released_seen);
      EXPECT_LT(on_partners(map), 6u);  // released, the features moved
    }
  }
}

TEST(RefineSurfaces, ASplitBlockedWhileFeaturesAreHeldReleasesThemEarly) {
  // A split that finds no place in any retry while the features are held
  // (stop 76's teapot <-> cup: a held feature's split) releases them at
  // once, before release_features_at, and is tried again; the map refines
  // to full resolution, valid. When the features are never released, or
  // already are, the split's error stops the refinement.
  const auto [pa, pb] = held_pair();
  InterSurfaceOptions held;
  held.hold_features = true;
  const std::size_t total = pa.splits.size() + pb.splits.size();
  const int every = InterSurfaceMap::kSplitRounds * (InterSurfaceMap::kSplitRetries + 1);
  for (const double at : {0.6, 0.0, -1.0}) {
    SCOPED_TRACE(at);
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb), held);
    SurfaceRefineOptions options;
    options.release_features_at = at;
    std::size_t splits = 0;
    options.on_step = [&](const SurfaceStep& step) {
      if (step.kind == SurfaceStep::split && ++splits == total / 4)
        InterSurfaceMapTestAccess::refuse_split_attempts(map, every);  // the next split fails
    };
    if (at <= 0) {  // never released, or released from the start
      EXPECT_THROW(refine_surfaces(map, options), std::runtime_error);
      EXPECT_EQ(map.splits_applied(0) + map.splits_applied(1), total / 4);
      EXPECT_EQ(map.is_pinned(0, pa.base_vertices[0]), at < 0);
      EXPECT_FALSE(map.validate());
      continue;
    }
    const SurfaceRefineStats stats = refine_surfaces(map, options);
    EXPECT_DOUBLE_EQ(stats.features_released_early_at, double(total / 4) / double(total));
    EXPECT_FALSE(map.is_pinned(0, pa.base_vertices[0]));
    EXPECT_EQ(map.splits_applied(0), pa.splits.size());
    EXPECT_EQ(map.splits_applied(1), pb.splits.size());
    EXPECT_FALSE(map.validate());
  }
}

// With the features held throughout, a split that finds no place in any
// retry is put off (defer_growth): the other side makes its next
// ceil(defer_growth x its vertices) splits, then the split is tried again.
// Put off twice, it then finds its place and the map refines to full
// resolution, valid, the features still held; failing a third time it stops
// the refinement (max_deferrals 2), the map valid at the split before.
// Features still to be released are released first.
TEST(RefineSurfaces, ASplitThatFindsNoPlaceIsPutOffWhileTheOtherSideRefines) {
  const auto [pa, pb] = held_pair();
  InterSurfaceOptions held;
  held.hold_features = true;
  const std::size_t total = pa.splits.size() + pb.splits.size();
  const int every = InterSurfaceMap::kSplitRounds * (InterSurfaceMap::kSplitRetries + 1);
  for (const int failures : {2, 3}) {
    SCOPED_TRACE(failures);
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb), held);
    SurfaceRefineOptions options;
    options.defer_growth = 0.1;
    options.max_deferrals = 2;
    std::size_t splits = 0, others = 0, expected_others = 0, all_others = 0, failed_at = 0;
    int failed_side = -1, left = failures;
    std::vector<int> sides_after;  // the sides of the splits after the first failure
    auto fail_next = [&] {
      expected_others = std::size_t(std::ceil(0.1 * double(map.n_vertices(1 - failed_side))));
      all_others += expected_others;
      others = 0;
      --left;
      InterSurfaceMapTestAccess::refuse_split_attempts(map, every);  // the next split fails
    };
    options.on_step = [&](const SurfaceStep& step) {
      if (step.kind != SurfaceStep::split) return;
      if (failed_side >= 0) {
        sides_after.push_back(step.side);
        if (step.side != failed_side && ++others == expected_others && left > 0) fail_next();
      }
      if (++splits == total / 4) {
        auto fraction = [&](int s) {
          return double(map.splits_applied(s)) / double(map.splits_total(s));
        };
        failed_side = fraction(0) <= fraction(1) ? 0 : 1;  // the next split's side
        failed_at = map.splits_applied(failed_side);
        fail_next();
      }
    };
    if (failures == 3) {
      EXPECT_THROW(refine_surfaces(map, options), std::runtime_error);
      EXPECT_EQ(map.splits_applied(failed_side), failed_at);
      EXPECT_FALSE(map.validate());
      continue;
    }
    const SurfaceRefineStats stats = refine_surfaces(map, options);
    EXPECT_EQ(stats.split_deferrals, 2u);
    // The other side's splits of both times, then the split put off.
    const auto placed = std::find(sides_after.begin(), sides_after.end(), failed_side);
    EXPECT_EQ(std::size_t(placed - sides_after.begin()), all_others);
    EXPECT_GT(all_others, 2u);
    EXPECT_EQ(map.splits_applied(0), pa.splits.size());
    EXPECT_EQ(map.splits_applied(1), pb.splits.size());
    EXPECT_TRUE(map.is_pinned(0, pa.base_vertices[0]));
    EXPECT_FALSE(map.validate());
  }
  // Features to be released later: the blocked split releases them first,
  // and when it still finds no place it is put off.
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb), held);
  SurfaceRefineOptions options;
  options.release_features_at = 0.6;
  options.defer_growth = 0.1;
  std::size_t splits = 0;
  options.on_step = [&](const SurfaceStep& step) {
    if (step.kind == SurfaceStep::split && ++splits == total / 4)
      InterSurfaceMapTestAccess::refuse_split_attempts(map, 2 * every);  // held, then released
  };
  const SurfaceRefineStats stats = refine_surfaces(map, options);
  EXPECT_DOUBLE_EQ(stats.features_released_early_at, double(total / 4) / double(total));
  EXPECT_EQ(stats.split_deferrals, 1u);
  EXPECT_FALSE(map.is_pinned(0, pa.base_vertices[0]));
  EXPECT_EQ(map.splits_applied(0), pa.splits.size());
  EXPECT_EQ(map.splits_applied(1), pb.splits.size());
  EXPECT_FALSE(map.validate());
}

// The symmetric core resumed from a SurfaceMap refined part of the way (as
// gim-remesh's --core symmetric does): the same map at the start (its
// measures equal SurfaceMap's), then every step valid and each gain the
// drop of the energy, to full resolution; a map that does not fit is
// refused.
TEST(RefineSurfaces, ResumesASurfaceMapRefinedPartOfTheWay) {
  const auto [pm, domain] = blob_over_octahedron(800);
  SurfaceMap coarse(domain, pm);
  refine_to(coarse, 150);
  ASSERT_EQ(coarse.n_vertices(), 150u);
  const auto meta = meta_mesh(coarse);
  ASSERT_TRUE(meta);
  const std::array<std::size_t, 2> applied{0, coarse.splits_applied()};

  InterSurfaceMap map(*meta, side_from_domain(domain, pm), side_from_pm(pm), applied);
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_vertices(1), 150u);
  EXPECT_EQ(map.splits_applied(1), coarse.splits_applied());
  const MapMeasures at_start = map.measures(), surface_map = coarse.measures();
  EXPECT_NEAR(at_start.symmetric_efficiency, surface_map.symmetric_efficiency, 1e-9);
  EXPECT_NEAR(at_start.forward_efficiency, surface_map.forward_efficiency, 1e-9);

  SurfaceRefineOptions options;
  options.validate_each_step = true;
  double energy = map.energy();
  std::size_t steps = 0;
  options.on_step = [&](const SurfaceStep& step) {
    const double after = map.energy();
    if (step.kind == SurfaceStep::optimise) {
      EXPECT_GT(step.gain, 0.0);
      EXPECT_NEAR(energy - after, step.gain, 1e-9 * energy);
    }
    energy = after;
    ++steps;
  };
  refine_surfaces(map, options);
  EXPECT_EQ(map.n_faces(1), replay(pm).n_faces());
  EXPECT_FALSE(map.validate());
  EXPECT_GT(steps, pm.splits.size() - applied[1]);
  const double efficiency = map.measures().symmetric_efficiency;
  EXPECT_GT(efficiency, 0.9);
  std::printf("blob %zu faces resumed at 150 vertices: symmetric efficiency %.4f -> %.4f\n",
              map.n_faces(1), at_start.symmetric_efficiency, efficiency);

  // Refused: more splits applied than the side has, and a broken map (one
  // crossing dropped from one of its two edges).
  EXPECT_THROW(InterSurfaceMap(*meta, side_from_domain(domain, pm), side_from_pm(pm),
                               {0, pm.splits.size() + 1}),
               std::invalid_argument);
  MetaMesh broken = *meta;
  auto crossed = std::find_if(broken.side[1].crossings.begin(), broken.side[1].crossings.end(),
                              [](const auto& list) { return !list.empty(); });
  ASSERT_NE(crossed, broken.side[1].crossings.end());
  crossed->pop_back();
  EXPECT_THROW(InterSurfaceMap(broken, side_from_domain(domain, pm), side_from_pm(pm), applied),
               std::invalid_argument);
}

// The back-off of large charts (SurfaceRefineOptions::large_chart_backoff):
// the cones of a resumed map over the octahedron have charts holding much of
// the surface; with the back-off fewer of their optimisations run, the map
// stays valid after every step with exact gains, and it ends as good.
TEST(RefineSurfaces, LargeChartsThatFindNothingAreRetriedLessOften) {
  const auto [pm, domain, meta, applied] = resumed_blob();
  ASSERT_TRUE(meta);
  struct Run {
    SurfaceRefineStats stats;
    std::size_t optimizations = 0, cone_moves = 0;
    double efficiency = 0;
  };
  auto run = [&](bool backoff) {
    InterSurfaceMap map(*meta, side_from_domain(domain, pm), side_from_pm(pm), applied);
    SurfaceRefineOptions options;
    options.large_chart_backoff = backoff;
    options.validate_each_step = backoff;
    double energy = map.energy();
    Run r;
    options.on_step = [&](const SurfaceStep& step) {
      const double after = map.energy();
      if (step.kind == SurfaceStep::optimise) {
        EXPECT_NEAR(energy - after, step.gain, 1e-9 * energy);
        r.cone_moves += step.side == 0;
      }
      energy = after;
    };
    r.stats = refine_surfaces(map, options);
    EXPECT_FALSE(map.validate());
    // The timings are disjoint parts of the call; the cones' charts among them.
    double parts = r.stats.seconds_splits + r.stats.seconds_discs;
    for (const double s : r.stats.seconds_by_chart) {
      EXPECT_GE(s, 0);
      parts += s;
    }
    EXPECT_GT(r.stats.seconds_by_chart[std::size_t(ChartKind::large)], 0);
    EXPECT_GT(r.stats.seconds_splits, 0);
    EXPECT_LE(parts, r.stats.seconds);
    r.optimizations = map.stats().optimizations;
    r.efficiency = map.measures().symmetric_efficiency;
    return r;
  };
  const Run with = run(true), without = run(false);
  std::printf(
      "back-off: %zu optimisations (%zu skipped, %zu cone moves), efficiency %.4f; "
      "without: %zu (%zu cone moves), %.4f\n",
      with.optimizations, with.stats.large_chart_skips, with.cone_moves, with.efficiency,
      without.optimizations, without.cone_moves, without.efficiency);
  EXPECT_GT(with.stats.large_chart_skips, 0u);
  EXPECT_EQ(without.stats.large_chart_skips, 0u);
  EXPECT_LT(with.optimizations, without.optimizations);
  EXPECT_GT(with.efficiency, without.efficiency - 1e-3);
}

// Discs of side 1 over one face of the octahedron or two across an edge
// (InterSurfaceMap::disc_layout) are re-embedded whole during local
// relaxation (SurfaceRefineOptions::local_disc_every): every step valid
// with its gain the drop of the energy; a disc laid out and installed
// unmoved changes nothing; discs spanning two faces exist and are kept.
TEST(RefineSurfaces, DiscsOverOneOrTwoDomainFacesAreReembeddedWhole) {
  const auto [pm, domain, meta, applied] = resumed_blob();
  ASSERT_TRUE(meta);
  InterSurfaceMap map(*meta, side_from_domain(domain, pm), side_from_pm(pm), applied);
  SurfaceRefineOptions options;
  // (The remeshers: every 10, 3 rings; here few vertices keep gaining, and
  // 3 rings of a 400-vertex blob mostly span more than two domain faces.)
  options.local_disc_every = 1;
  options.local_disc_rings = 2;
  options.validate_each_step = true;
  double energy = map.energy();
  options.on_step = [&](const SurfaceStep& step) {
    const double after = map.energy();
    if (step.kind == SurfaceStep::optimise) {
      EXPECT_NEAR(energy - after, step.gain, 1e-9 * energy);
    }
    energy = after;
  };
  const SurfaceRefineStats stats = refine_surfaces(map, options);
  EXPECT_FALSE(map.validate());
  EXPECT_GT(stats.discs_applied, 0u);
  EXPECT_GT(map.measures().symmetric_efficiency, 0.9);

  // Every vertex's 2-ring disc, where one can be laid out: over how many
  // faces of side 0; installed where it is, nothing changes. disc_around
  // gives the same vertices, or none only where there is no layout.
  std::size_t over[3] = {0, 0, 0}, refused_early = 0;
  const double before = map.energy();
  for (std::size_t v = 0; v < map.n_vertices(1); ++v) {
    const std::vector<int> rings = map.rings_around(1, int(v), 2);
    const auto disc = map.disc_layout(rings);
    const std::vector<int> early = map.disc_around(int(v), 2);
    if (early.empty()) {
      ++refused_early;
      EXPECT_FALSE(disc) << "vertex " << v;
    } else {
      EXPECT_EQ(early, rings);
    }
    if (!disc) continue;
    std::vector<int> faces;
    for (int u : disc->vertex) faces.push_back(map.meta().side[1].location[u].face);
    std::sort(faces.begin(), faces.end());
    ++over[std::unique(faces.begin(), faces.end()) - faces.begin()];
    EXPECT_EQ(map.set_disc_layout(*disc), 0.0);
  }
  EXPECT_EQ(map.energy(), before);
  EXPECT_GT(over[1], 0u);
  EXPECT_GT(over[2], 0u);
  EXPECT_GT(refused_early, 0u);
  // And re-embedded whole, each a valid map with its energy lower by the gain.
  std::size_t kept = 0;
  for (std::size_t v = 0; v < map.n_vertices(1); v += 7) {
    const double e0 = map.energy();
    const double gain = reembed_disc(map, map.rings_around(1, int(v), 2));
    ASSERT_FALSE(map.validate()) << "disc around vertex " << v;
    EXPECT_GE(gain, 0.0);
    EXPECT_NEAR(e0 - map.energy(), gain, 1e-9 * e0);
    kept += gain > 0;
  }
  std::printf(
      "blob %zu faces resumed at 150 vertices: %zu of %zu discs kept in refinement, "
      "efficiency %.4f; 2-ring discs over one domain face %zu, over two %zu, refused while "
      "gathered %zu; %zu more kept\n",
      map.n_faces(1), stats.discs_applied, stats.discs, map.measures().symmetric_efficiency,
      over[1], over[2], refused_early, kept);
}

// A forward density (the remeshers' curvature weight) weighs the forward
// term of the energy per face of side 1 and nothing else: with density c
// everywhere the energy is c times the forward part plus the inverse one,
// and a map refined with a curvature density keeps every step valid, each
// gain the drop of that weighted energy.
TEST(RefineSurfaces, ForwardDensityWeighsTheForwardTerm) {
  const auto [pm, domain] = blob_over_octahedron(600);
  auto energy_with = [&](double c) {
    InterSurfaceOptions options;
    options.forward_density.assign(pm.base.n_vertices(), c);
    InterSurfaceMap map(side_from_domain(domain, pm), side_from_pm(pm), options);
    return map.energy();
  };
  const double plain = InterSurfaceMap(side_from_domain(domain, pm), side_from_pm(pm)).energy();
  const double e0 = energy_with(0), e1 = energy_with(1), e3 = energy_with(3);
  EXPECT_EQ(e1, plain);
  EXPECT_GT(e0, 0.0);
  EXPECT_LT(e0, e1);
  EXPECT_NEAR(e3 - e0, 3 * (e1 - e0), 1e-9 * e3);
  InterSurfaceOptions short_density;
  short_density.forward_density.assign(3, 1.0);
  EXPECT_THROW(InterSurfaceMap(side_from_domain(domain, pm), side_from_pm(pm), short_density),
               std::invalid_argument);

  InterSurfaceOptions options;
  options.forward_density = curvature_density(replay(pm), 0.5);
  InterSurfaceMap map(side_from_domain(domain, pm), side_from_pm(pm), options);
  SurfaceRefineOptions refine_options;
  refine_options.validate_each_step = true;
  double energy = map.energy();
  refine_options.on_step = [&](const SurfaceStep& step) {
    const double after = map.energy();
    if (step.kind == SurfaceStep::optimise) {
      EXPECT_NEAR(energy - after, step.gain, 1e-9 * energy);
    }
    energy = after;
  };
  refine_surfaces(map, refine_options);
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(1), replay(pm).n_faces());
  EXPECT_GT(map.measures().symmetric_efficiency, 0.9);
}

// fandisk (sharp creases, flat panels) on the equilateral octahedron: some
// splits raise the energy of their faces ten- to a billionfold (nearly
// degenerate pieces; a retried split's last attempt takes any valid place),
// which the new ring's one optimisation did not undo, and the next splits
// there compounded it (the map's energy 10¹² at M² split 6492, where no
// valid place remained). The relaxation queue after each such hard split
// keeps the map healthy to full resolution.
TEST(RefineSurfaces, HardSplitsAreRelaxedSoACreasedModelCompletes) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh surface =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / "fandisk.obj")).mesh;
  const TriangleMesh octahedron = domain::octahedron();
  const ProgressiveMesh pm = simplify_constrained(trace_octahedral_network(surface), octahedron);
  const DomainGeometry domain(octahedron,
                              octahedron_lengths(octahedron, DomainMetric::equilateral));
  InterSurfaceMap map(side_from_domain(domain, pm), side_from_pm(pm));
  const SurfaceRefineStats stats = refine_surfaces(map);
  EXPECT_EQ(map.n_faces(1), replay(pm).n_faces());  // full resolution
  EXPECT_FALSE(map.validate());
  EXPECT_GT(stats.hard_splits, 0u);
  const double efficiency = map.measures().symmetric_efficiency;
  EXPECT_GT(efficiency, 0.75);  // 0.7865 when written
  std::printf("fandisk, equilateral octahedron: %zu hard splits, symmetric efficiency %.4f\n",
              stats.hard_splits, efficiency);
}

/// The bytes of a map's meta-mesh file.
std::string meta_mesh_bytes(const InterSurfaceMap& map, const std::string& name) {
  // (Named by the process too: test runs of two checkouts may share the
  // temporary directory.)
  const auto path =
      std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  EXPECT_TRUE(write_meta_mesh(map.meta(), path));
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  return bytes;
}

// Sweeps and relaxation queues planned on several threads
// (SurfaceRefineOptions::threads, InterSurfaceMap::VertexPlan), and the
// splits' candidate places evaluated on them, refine to the very map one
// thread refines to, byte for byte: two surfaces both
// refining, and the remeshers' case (a resumed blob over the octahedron,
// large charts backed off, discs re-embedded). Most plans hold; the
// rest were optimised anew because an earlier commit changed their ring.
TEST(RefineSurfaces, PlansOnSeveralThreadsGiveTheMapOneThreadGives) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(240, 3);
  const TriangleMesh octahedron = domain::octahedron();
  const ProgressiveMesh pa = simplify_constrained(trace_octahedral_network(a), octahedron);
  const ProgressiveMesh pb = simplify_constrained(trace_octahedral_network(b), octahedron);
  const auto [pm, domain, meta, applied] = resumed_blob();
  ASSERT_TRUE(meta);
  for (const bool remesher : {false, true}) {
    std::vector<std::string> files;
    std::vector<double> energies;
    for (const int threads : {1, 2, 3}) {
      InterSurfaceMap map =
          remesher ? InterSurfaceMap(*meta, side_from_domain(domain, pm), side_from_pm(pm), applied)
                   : InterSurfaceMap(side_from_pm(pa), side_from_pm(pb));
      SurfaceRefineOptions options;
      options.threads = threads;
      if (remesher) {
        options.large_chart_backoff = true;
        options.local_disc_every = 2;
      }
      const SurfaceRefineStats stats = refine_surfaces(map, options);
      ASSERT_FALSE(map.validate()) << threads << " threads";
      const MapOperationStats& o = map.stats();
      if (threads == 1) {
        EXPECT_EQ(o.plans_held + o.plans_stale, 0u);
        EXPECT_EQ(stats.seconds_planning, 0.0);
      } else {
        EXPECT_GT(o.plans_held, 2 * o.plans_stale) << threads << " threads";
        // Most held plans are known unchanged from the edit stamps alone.
        EXPECT_GT(o.plans_untouched, o.plans_held / 2) << threads << " threads";
        EXPECT_LE(o.plans_untouched, o.plans_held);
      }
      files.push_back(meta_mesh_bytes(map, "ism_plans_" + std::to_string(threads) + ".meta"));
      energies.push_back(map.energy());
      std::printf(
          "%s, %d thread(s): energy %.17g; plans held %zu (%zu untouched), optimised anew %zu\n",
          remesher ? "blob over the octahedron" : "sphere / blob", threads, map.energy(),
          o.plans_held, o.plans_untouched, o.plans_stale);
    }
    EXPECT_FALSE(files[0].empty());
    for (std::size_t k = 1; k < files.size(); ++k) {
      EXPECT_EQ(energies[k], energies[0]);
      EXPECT_TRUE(files[k] == files[0]) << "the meta-mesh of " << k + 1 << " threads differs";
    }
  }
}

// Every optimisation refine_surfaces runs is counted once, under what it
// ran for: the stages sum to the map's count, and each stage of a
// refinement of two surfaces (splits' rings, the other side inside them,
// level sweeps, their relaxation queues, final sweeps and relaxation)
// ran, on one thread and with plans on two.
TEST(RefineSurfaces, OptimisationsAreCountedByStage) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(240, 3);
  const TriangleMesh octahedron = domain::octahedron();
  const ProgressiveMesh pa = simplify_constrained(trace_octahedral_network(a), octahedron);
  const ProgressiveMesh pb = simplify_constrained(trace_octahedral_network(b), octahedron);
  for (const int threads : {1, 2}) {
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
    SurfaceRefineOptions options;
    options.threads = threads;
    const SurfaceRefineStats stats = refine_surfaces(map, options);
    ASSERT_FALSE(map.validate());
    std::size_t sum = 0;
    for (std::size_t k = 0; k < kRefineStages; ++k) {
      const RefineStage stage = RefineStage(k);
      sum += stats.optimizations_by_stage[k];
      std::printf("%d thread(s), %s: %zu\n", threads, refine_stage_name(stage),
                  stats.optimizations_by_stage[k]);
      if (stage != RefineStage::hard_splits) {
        EXPECT_GT(stats.optimizations_by_stage[k], 0u) << refine_stage_name(stage);
      }
    }
    EXPECT_EQ(sum, map.stats().optimizations) << threads << " thread(s)";
  }
  EXPECT_STREQ(refine_stage_name(RefineStage::split_rings), "split_rings");
  EXPECT_STREQ(refine_stage_name(RefineStage::final_relaxation), "final_relaxation");
}

// A sphere and a blob of 400 / 480 faces over the octahedron (the search
// and placement tests' pair).
std::array<ProgressiveMesh, 2> sphere_and_blob() {
  const TriangleMesh a = shapes::sphere(400), b = shapes::blob(480, 3);
  const TriangleMesh octahedron = domain::octahedron();
  return {simplify_constrained(trace_octahedral_network(a), octahedron),
          simplify_constrained(trace_octahedral_network(b), octahedron)};
}

/// Both sides refined with `options` from the trivial map, checked valid:
/// the map and the bytes of its meta-mesh file (written as `name`).
struct Refined {
  InterSurfaceMap map;
  std::string file;
};
Refined refined(const ProgressiveMesh& pa, const ProgressiveMesh& pb,
                const SurfaceRefineOptions& options, const std::string& name) {
  Refined r{InterSurfaceMap(side_from_pm(pa), side_from_pm(pb)), {}};
  refine_surfaces(r.map, options);
  EXPECT_FALSE(r.map.validate());
  r.file = meta_mesh_bytes(r.map, name);
  return r;
}

// How far the optimisations search (search, then fine_search once
// fine_search_from of the splits are applied): a switch that never comes
// changes nothing, byte for byte; searching the fine levels in one round to
// 1e-3 costs far fewer energy evaluations per optimisation and ends at
// nearly the same energy, a valid map.
TEST(RefineSurfaces, FineLevelsSearchedLooselyCostFewerEvaluations) {
  const auto [pa, pb] = sphere_and_blob();
  struct Run {
    std::string file;
    double energy, evaluations;
  };
  auto run = [&](KernelSearch fine, double from) {
    SurfaceRefineOptions options;
    options.fine_search = fine;
    options.fine_search_from = from;
    const auto [map, file] = refined(pa, pb, options, "ism_search.meta");
    EXPECT_TRUE(map.search() == (from <= 1 ? fine : options.search));
    const MapOperationStats& o = map.stats();
    return Run{file, map.energy(), double(o.evaluations) / double(o.optimizations)};
  };
  const KernelSearch loose{1e-3, 1};
  const Run precise = run({}, 0.25), never = run(loose, 2.0), fine = run(loose, 0.25);
  EXPECT_FALSE(precise.file.empty());
  EXPECT_TRUE(never.file == precise.file);
  EXPECT_GT(precise.evaluations, 10.0);
  EXPECT_LT(fine.evaluations, 0.75 * precise.evaluations);
  EXPECT_LT(std::abs(fine.energy - precise.energy), 0.01 * precise.energy);
  std::printf(
      "sphere / blob: evaluations per optimisation %.2f -> %.2f (one round to 1e-3 past a "
      "quarter of the splits); energy %.6f -> %.6f\n",
      precise.evaluations, fine.evaluations, precise.energy, fine.energy);
}

// How splits place their new vertex (split_placement, then
// fine_split_placement from fine_search_from on): a switch that never comes
// changes nothing, byte for byte; placing the fine levels' splits from the
// first halving with the loose search costs far fewer evaluations per split
// and ends at nearly the same energy, a valid map.
TEST(RefineSurfaces, FineSplitsPlacedFromTheFirstHalvingCostFewerEvaluations) {
  const auto [pa, pb] = sphere_and_blob();
  struct Run {
    std::string file;
    double energy, evaluations;
  };
  const KernelSearch loose{1e-3, 1};
  auto run = [&](SplitPlacement fine, double from) {
    SurfaceRefineOptions options;
    options.fine_search = loose;
    options.fine_split_placement = fine;
    options.fine_search_from = from;
    const auto [map, file] = refined(pa, pb, options, "ism_split_placement.meta");
    EXPECT_TRUE(map.split_placement() == (from <= 1 ? fine : options.split_placement));
    const MapOperationStats& o = map.stats();
    return Run{file, map.energy(), double(o.split_evaluations) / double(o.splits)};
  };
  const SplitPlacement first{1, loose};
  const Run wide_never = run({}, 2.0), never = run(first, 2.0);
  EXPECT_FALSE(never.file.empty());
  EXPECT_TRUE(never.file == wide_never.file);
  const Run wide = run({}, 0.25), fine = run(first, 0.25);
  EXPECT_GT(wide.evaluations, 20.0);
  EXPECT_LT(fine.evaluations, 0.6 * wide.evaluations);
  EXPECT_LT(std::abs(fine.energy - wide.energy), 0.01 * wide.energy);
  std::printf(
      "sphere / blob: evaluations per split %.2f -> %.2f (from the first halving, one round "
      "to 1e-3, past a quarter of the splits); energy %.6f -> %.6f\n",
      wide.evaluations, fine.evaluations, wide.energy, fine.energy);
}

// The relaxation queues after the level sweeps and the final ones started
// from where the last sweep moved (relax_from_movers): fewer optimisations
// than from every vertex, a valid map at nearly the same energy.
TEST(RefineSurfaces, RelaxationFromTheMoversRunsFewerOptimisations) {
  const auto [pa, pb] = sphere_and_blob();
  auto run = [&](bool from_movers, SurfaceRefineStats& stats) {
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
    SurfaceRefineOptions options;
    options.relax_from_movers = from_movers;
    stats = refine_surfaces(map, options);
    EXPECT_FALSE(map.validate());
    return map.energy();
  };
  SurfaceRefineStats all, movers;
  const double e_all = run(false, all), e_movers = run(true, movers);
  auto relaxation = [](const SurfaceRefineStats& s) {
    return s.optimizations_by_stage[std::size_t(RefineStage::relaxation)] +
           s.optimizations_by_stage[std::size_t(RefineStage::final_relaxation)];
  };
  EXPECT_GT(relaxation(movers), 0u);
  EXPECT_LT(relaxation(movers), relaxation(all));
  EXPECT_LT(std::abs(e_movers - e_all), 0.01 * e_all);
  std::printf("sphere / blob: relaxation optimisations %zu -> %zu; energy %.6f -> %.6f\n",
              relaxation(all), relaxation(movers), e_all, e_movers);
}

}  // namespace
}  // namespace ism
