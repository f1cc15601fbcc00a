#include "refine/refine_surfaces.hpp"

#include "refine/disc_relaxation.hpp"
#include "refine/stopwatch.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

namespace ism {

namespace {

/// After a split or a kept move: validation when asked, then the hook.
void after(const InterSurfaceMap& map, const SurfaceRefineOptions& options, SurfaceStep step) {
  if (options.validate_each_step)
    if (auto problem = map.validate())
      throw std::runtime_error(std::string("map invalid after ") +
                               (step.kind == SurfaceStep::split ? "splitting" : "optimising") +
                               " of vertex " + std::to_string(step.vertex) + " of side " +
                               std::to_string(step.side) + ": " + *problem);
  if (options.on_step) options.on_step(step);
}

/// The back-off of vertices whose optimisation in a large chart found no
/// lower energy (SurfaceRefineOptions::large_chart_backoff): after k such
/// failures in a row, the next 2^k - 1 optimisations of the vertex are
/// skipped (k at most kMaxFailures); once kGiveUpAfter large charts of a
/// side have failed and none has gained, that side's vertices whose last
/// chart was large (then: failed) are skipped for good.
class Backoff {
 public:
  static constexpr unsigned kMaxFailures = 6;
  static constexpr std::size_t kGiveUpAfter = 8;
  /// Whether this optimisation of v is skipped (and counts it).
  bool skip(int side, int v) {
    grow(side, v);
    if (failures_[side][v] > 0 && gains_[side] == 0 && fails_[side] >= kGiveUpAfter) {
      ++skipped_;
      return true;
    }
    if (left_[side][v] == 0) return false;
    --left_[side][v];
    ++skipped_;
    return true;
  }
  /// After an optimisation of v that ran: its chart was large, its gain.
  void record(int side, int v, bool large, double gain) {
    grow(side, v);
    if (large) ++(gain > 0 ? gains_[side] : fails_[side]);
    if (!large || gain > 0) {
      failures_[side][v] = 0;
      return;
    }
    failures_[side][v] = std::min(failures_[side][v] + 1, kMaxFailures);
    left_[side][v] = (1u << failures_[side][v]) - 1;
  }
  std::size_t skipped() const { return skipped_; }

 private:
  void grow(int side, int v) {
    if (std::size_t(v) >= failures_[side].size()) {
      failures_[side].resize(std::size_t(v) + 1, 0);
      left_[side].resize(std::size_t(v) + 1, 0);
    }
  }
  std::array<std::vector<unsigned>, 2> failures_, left_;
  std::array<std::size_t, 2> fails_{}, gains_{};  // large charts of a side: failed, gained
  std::size_t skipped_ = 0;
};

/// Optimises v (unless the back-off, when given, skips it); the gain (the
/// step reported when kept). Its time goes to `stats` by chart.
double optimise(InterSurfaceMap& map, const SurfaceRefineOptions& options, int side, int v,
                Backoff* backoff, SurfaceRefineStats& stats) {
  if (backoff && backoff->skip(side, v)) return 0.0;
  const Stopwatch watch;
  const double g = map.optimize_vertex(side, v);
  const ChartKind chart = map.last_chart();
  stats.seconds_by_chart[std::size_t(chart)] += watch.seconds();
  if (backoff) backoff->record(side, v, chart == ChartKind::large, g);
  if (g > 0) after(map, options, {SurfaceStep::optimise, side, v, g});
  return g;
}

double sweep(InterSurfaceMap& map, const SurfaceRefineOptions& options, Backoff* backoff,
             SurfaceRefineStats& stats) {
  double gain = 0;
  for (int side = 0; side < 2; ++side)
    for (std::size_t v = 0; v < map.meta().side[side].n_vertices(); ++v)
      if (map.is_active(side, int(v))) gain += optimise(map, options, side, int(v), backoff, stats);
  return gain;
}

}  // namespace

double surfaces_sweep(InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  SurfaceRefineStats unused;
  return sweep(map, options, nullptr, unused);
}

namespace {

/// The local relaxation queue from `seeds` (pairs side, vertex): each
/// optimised, and a vertex whose move gained more than the options' share
/// of the mean energy per vertex queues its neighbours; at most `max_moves`
/// optimisations.
LocalRelaxationStats relax_from(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                const std::vector<std::pair<int, int>>& seeds,
                                std::size_t max_moves, Backoff* backoff,
                                SurfaceRefineStats& timing) {
  LocalRelaxationStats stats;
  std::deque<std::pair<int, int>> queue;
  std::array<std::vector<char>, 2> queued;
  for (int side = 0; side < 2; ++side) queued[side].assign(map.meta().side[side].n_vertices(), 0);
  auto enqueue = [&](int side, int v) {
    if (queued[side][v] || !map.is_active(side, v) || map.is_pinned(side, v)) return;
    queue.push_back({side, v});
    queued[side][v] = 1;
  };
  for (const auto& [side, v] : seeds) enqueue(side, v);
  const double vertices = double(map.n_vertices(0) + map.n_vertices(1));
  const double threshold = options.local_relaxation_gain * map.energy() / vertices;
  std::vector<int> gaining;  // moves of side 1 that gained, per vertex (with discs only)
  if (options.local_disc_every > 0) gaining.assign(map.meta().side[1].n_vertices(), 0);
  for (; !queue.empty() && stats.moves < max_moves; ++stats.moves) {
    const auto [side, v] = queue.front();
    queue.pop_front();
    queued[side][v] = 0;
    const double g = optimise(map, options, side, v, backoff, timing);
    stats.gain += g;
    if (!(g > threshold)) continue;
    for (int w : map.neighbours(side, v)) enqueue(side, w);
    if (side != 1 || options.local_disc_every <= 0 || ++gaining[v] % options.local_disc_every != 0)
      continue;
    // (No layout, found while the rings are gathered: mostly near a cone.)
    const Stopwatch watch;
    const std::vector<int> disc = map.disc_around(v, options.local_disc_rings);
    const double d = disc.empty() ? 0.0 : reembed_disc(map, disc);
    timing.seconds_discs += watch.seconds();
    ++stats.discs;
    if (!(d > 0)) continue;
    ++stats.discs_applied;
    stats.gain += d;
    after(map, options, {SurfaceStep::optimise, 1, v, d});
    for (int w : disc) enqueue(1, w);
  }
  return stats;
}

LocalRelaxationStats local_relaxation(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                      Backoff* backoff, SurfaceRefineStats& timing) {
  if (!(options.local_relaxation_budget > 0)) return {};
  std::vector<std::pair<int, int>> all;
  for (int side = 0; side < 2; ++side)
    for (std::size_t v = 0; v < map.meta().side[side].n_vertices(); ++v)
      all.push_back({side, int(v)});
  const double vertices = double(map.n_vertices(0) + map.n_vertices(1));
  return relax_from(map, options, all, std::size_t(options.local_relaxation_budget * vertices),
                    backoff, timing);
}

}  // namespace

LocalRelaxationStats surfaces_local_relaxation(InterSurfaceMap& map,
                                               const SurfaceRefineOptions& options) {
  SurfaceRefineStats unused;
  return local_relaxation(map, options, nullptr, unused);
}

LocalRelaxationStats surfaces_relax_from(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                         const std::vector<std::pair<int, int>>& seeds,
                                         std::size_t max_moves) {
  SurfaceRefineStats unused;
  return relax_from(map, options, seeds, max_moves, nullptr, unused);
}

SurfaceRefineStats refine_surfaces(InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  const Stopwatch watch;
  SurfaceRefineStats stats;
  auto add = [&](const LocalRelaxationStats& local) {
    stats.local_moves += local.moves;
    stats.discs += local.discs;
    stats.discs_applied += local.discs_applied;
  };
  Backoff backoff_state;
  Backoff* backoff = options.large_chart_backoff ? &backoff_state : nullptr;
  const std::size_t total_splits = map.splits_total(0) + map.splits_total(1);
  auto fraction = [&](int side) {
    return map.splits_total(side)
               ? double(map.splits_applied(side)) / double(map.splits_total(side))
               : 1.0;
  };
  std::size_t last_sweep = map.n_vertices(0) + map.n_vertices(1);
  int side = fraction(0) <= fraction(1) ? 0 : 1;
  std::size_t in_block = 0;
  for (;;) {
    if (fraction(0) >= 1 && fraction(1) >= 1) break;
    if (in_block >= options.block || fraction(side) >= 1) {
      side = fraction(0) <= fraction(1) ? 0 : 1;
      in_block = 0;
    }
    const Stopwatch split_watch;
    const int vs = map.split_next(side);
    stats.seconds_splits += split_watch.seconds();
    ++in_block;
    ++stats.splits;
    after(map, options, {SurfaceStep::split, side, vs, 0.0});
    std::vector<int> todo = map.neighbours(side, vs);
    todo.push_back(vs);
    std::vector<std::pair<int, int>> region;
    for (int v : todo) {
      optimise(map, options, side, v, backoff, stats);
      region.push_back({side, v});
    }
    if (options.optimise_other_side)
      for (int x : map.others_in_ring(side, vs))
        if (map.is_active(1 - side, x)) {
          optimise(map, options, 1 - side, x, backoff, stats);
          region.push_back({1 - side, x});
        }
    if (map.last_split_growth() > options.hard_split_growth) {
      ++stats.hard_splits;
      if (options.hard_split_relaxation > 0)
        add(relax_from(map, options, region, options.hard_split_relaxation * region.size(), backoff,
                       stats));
    }
    const std::size_t total = map.n_vertices(0) + map.n_vertices(1);
    if (double(total) >= options.sweep_growth * double(last_sweep)) {
      const double e = map.energy();
      for (int k = 0; k < options.max_level_sweeps; ++k) {
        ++stats.sweeps;
        if (sweep(map, options, backoff, stats) < 1e-3 * e) break;
      }
      add(local_relaxation(map, options, backoff, stats));
      last_sweep = total;
    }
    if (options.progress && total_splits)
      options.progress(double(stats.splits) / double(total_splits));
  }
  if (options.before_final) {
    ++stats.global_steps;
    const double gain = options.before_final(map);
    if (gain > 0) ++stats.global_steps_applied;
    if (options.validate_each_step)
      if (const auto problem = map.validate())
        throw std::runtime_error("map invalid after the global step before the final sweeps: " +
                                 *problem);
  }
  for (int k = 0; k < options.max_final_sweeps; ++k) {
    const double e = map.energy();
    ++stats.final_sweeps;
    if (sweep(map, options, backoff, stats) < options.final_relative_gain * e) break;
  }
  add(local_relaxation(map, options, backoff, stats));
  stats.large_chart_skips = backoff_state.skipped();
  stats.energy = map.energy();
  stats.seconds = watch.seconds();
  return stats;
}

std::string describe_stop(const InterSurfaceMap& map, const std::string& what) {
  const auto problem = map.validate();
  char sizes[64], figures[160];
  std::snprintf(sizes, sizeof sizes, "%zu / %zu faces", map.n_faces(0), map.n_faces(1));
  std::snprintf(figures, sizeof figures,
                ", symmetric efficiency %.4f (energy %.4g); splits retried %zu, in place %zu",
                problem ? 0.0 : map.measures().symmetric_efficiency, map.energy(),
                map.stats().split_retries, map.stats().splits_in_place);
  return std::string("refinement stopped at ") + sizes + ": " + what +
         "; the map there: " + (problem ? *problem : std::string("valid from both sides")) +
         figures;
}

}  // namespace ism
