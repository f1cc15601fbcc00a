#include "refine/refine_surfaces.hpp"

#include "refine/disc_relaxation.hpp"
#include "refine/stopwatch.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace ism {

const char* refine_stage_name(RefineStage stage) {
  constexpr const char* names[kRefineStages] = {"split_rings",     "other_side", "hard_splits",
                                                "level_sweeps",    "relaxation", "final_sweeps",
                                                "final_relaxation"};
  return names[std::size_t(stage)];
}

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
  /// Whether skip(side, v) would skip v now (changes nothing).
  bool would_skip(int side, int v) const {
    if (std::size_t(v) >= failures_[side].size()) return false;
    if (failures_[side][v] > 0 && gains_[side] == 0 && fails_[side] >= kGiveUpAfter) return true;
    return left_[side][v] > 0;
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

/// Plans of the next vertices to optimise (SurfaceRefineOptions::threads),
/// made concurrently from the map as it is; each is then committed in
/// order by optimise(), which optimises anew where an earlier commit
/// changed what the plan saw. The result is the same for any number of
/// threads.
class Planner {
 public:
  Planner(const InterSurfaceMap& map, const SurfaceRefineOptions& options)
      : map_(map),
        threads_(options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency()) {
    if (threads_ != tbb::this_task_arena::max_concurrency()) arena_.emplace(threads_);
  }
  /// Runs f with the planner's threads (a split's candidate places are
  /// evaluated in parallel), isolated as plan() is.
  template <class F>
  void run(F&& f) {
    auto work = [&] { tbb::this_task_arena::isolate(f); };
    if (arena_)
      arena_->execute(work);
    else
      work();
  }
  /// The map's energy (InterSurfaceMap::cached_energy: the faces touched
  /// since they were summed cut on the planner's threads).
  double energy() {
    double e = 0;
    run([&] { e = map_.cached_energy(); });
    return e;
  }
  /// Whether plans are made: more than one thread.
  bool on() const { return threads_ > 1; }
  /// How many vertices a batch plans.
  std::size_t batch() const { return kPerThread * std::size_t(threads_); }
  /// Plans these (side, vertex), those the back-off will skip left
  /// unplanned; plan(k) is the k-th.
  void plan(std::span<const std::pair<int, int>> vertices, const Backoff* backoff,
            SurfaceRefineStats& stats) {
    const Stopwatch watch;
    if (plans_.size() < vertices.size()) plans_.resize(vertices.size());
    // Isolated: a thread waiting here takes no other work of the arena
    // (e.g. another map variant's whole refinement).
    auto work = [&] {
      tbb::this_task_arena::isolate([&] {
        // (One vertex a task: plans differ in cost by orders of magnitude.)
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, vertices.size(), 1),
            [&](const tbb::blocked_range<std::size_t>& range) {
              for (std::size_t k = range.begin(); k < range.end(); ++k) {
                const auto [side, v] = vertices[k];
                auto& plan = plans_[k];
                if (backoff && backoff->would_skip(side, v)) {
                  plan = {};
                  plan.side = side, plan.vertex = v;
                  continue;
                }
                map_.plan_vertex(side, v, plan);
              }
            },
            tbb::simple_partitioner());
      });
    };
    if (arena_)
      arena_->execute(work);
    else
      work();
    stats.seconds_planning += watch.seconds();
  }
  InterSurfaceMap::VertexPlan& plan(std::size_t k) { return plans_[k]; }

 private:
  // Larger batches split the work more evenly, smaller ones see fewer of
  // their plans' rings changed by earlier commits.
  static constexpr std::size_t kPerThread = 16;
  const InterSurfaceMap& map_;
  int threads_;
  std::optional<tbb::task_arena> arena_;
  std::vector<InterSurfaceMap::VertexPlan> plans_;
};

/// Optimises v (unless the back-off, when given, skips it), through its
/// plan when given, on the planner's threads (the faces it checks are cut
/// concurrently); the gain (the step reported when kept). Its time goes to
/// `stats` by chart.
double optimise(InterSurfaceMap& map, const SurfaceRefineOptions& options, int side, int v,
                RefineStage stage, Planner& planner, Backoff* backoff, SurfaceRefineStats& stats,
                InterSurfaceMap::VertexPlan* plan = nullptr) {
  if (backoff && backoff->skip(side, v)) return 0.0;
  const Stopwatch watch;
  double g = 0;
  planner.run([&] { g = plan ? map.commit_plan(*plan) : map.optimize_vertex(side, v); });
  const ChartKind chart = map.last_chart();
  if (chart != ChartKind::none) ++stats.optimizations_by_stage[std::size_t(stage)];
  stats.seconds_by_chart[std::size_t(chart)] += watch.seconds();
  if (backoff) backoff->record(side, v, chart == ChartKind::large, g);
  if (g > 0) after(map, options, {SurfaceStep::optimise, side, v, g});
  return g;
}

/// Vertices of one side grouped by colour: a greedy colouring of the
/// active ones (each once) in the order given, in which no two neighbours
/// share a colour; each colour in the order given.
struct Coloured {
  std::vector<int> order;
  std::vector<std::size_t> starts;  // where each colour starts in `order`, then its size
};
Coloured by_colour(const InterSurfaceMap& map, int side, const std::vector<int>& vertices) {
  // (Per thread, -1 but where this call sets it and back to -1 after: a
  // split batch's few rings cost their size, not the side's.)
  thread_local std::vector<int> colour;
  if (colour.size() < map.meta().side[side].n_vertices())
    colour.resize(map.meta().side[side].n_vertices(), -1);
  std::vector<int> seen;
  std::vector<char> taken;
  std::vector<std::size_t> count;
  for (const int v : vertices) {
    if (!map.is_active(side, v) || colour[v] >= 0) continue;
    taken.assign(count.size() + 1, 0);
    for (int w : map.neighbours(side, v))
      if (colour[w] >= 0) taken[colour[w]] = 1;
    int c = 0;
    while (taken[c]) ++c;
    colour[v] = c;
    if (std::size_t(c) == count.size()) count.push_back(0);
    ++count[c];
    seen.push_back(v);
  }
  Coloured out;
  out.starts.assign(count.size() + 1, 0);
  for (std::size_t c = 0; c < count.size(); ++c) out.starts[c + 1] = out.starts[c] + count[c];
  out.order.resize(seen.size());
  std::vector<std::size_t> next(out.starts.begin(), out.starts.end() - 1);
  for (const int v : seen) out.order[next[colour[v]]++] = v;
  for (const int v : seen) colour[v] = -1;
  return out;
}

/// The active vertices of a side by colour (by_colour of them in index order).
Coloured colour_order(const InterSurfaceMap& map, int side) {
  std::vector<int> all(map.meta().side[side].n_vertices());
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = int(v);
  return by_colour(map, side, all);
}

/// The vertices whose move gained more than `threshold` (pairs side, vertex).
struct Movers {
  double threshold = 0;
  std::vector<std::pair<int, int>> list;
};

/// The gain above which a move queues its neighbours in the local
/// relaxation (the options' share of the mean energy per vertex at `energy`).
double relaxation_threshold(const InterSurfaceMap& map, const SurfaceRefineOptions& options,
                            double energy) {
  return options.local_relaxation_gain * energy / double(map.n_vertices(0) + map.n_vertices(1));
}

/// Optimises these vertices of a side colour after colour; with the
/// planner on, each colour in batches planned ahead (no two of a batch
/// neighbours, so a commit seldom changes a later plan of its batch). The
/// energy gained.
double optimise_by_colour(InterSurfaceMap& map, const SurfaceRefineOptions& options, int side,
                          const Coloured& coloured, RefineStage stage, Planner& planner,
                          Backoff* backoff, SurfaceRefineStats& stats, Movers* movers = nullptr) {
  double gain = 0;
  std::vector<std::pair<int, int>> batch;
  const auto& order = coloured.order;
  for (std::size_t c = 0; c + 1 < coloured.starts.size(); ++c) {
    const std::size_t end = coloured.starts[c + 1];
    for (std::size_t k0 = coloured.starts[c]; k0 < end;) {
      const bool planning = planner.on();
      const std::size_t k1 = std::min(end, k0 + planner.batch());
      if (planning) {
        batch.clear();
        for (std::size_t k = k0; k < k1; ++k) batch.push_back({side, order[k]});
        planner.plan(batch, backoff, stats);
      }
      for (std::size_t k = k0; k < k1; ++k) {
        const double g = optimise(map, options, side, order[k], stage, planner, backoff, stats,
                                  planning ? &planner.plan(k - k0) : nullptr);
        gain += g;
        if (movers && g > movers->threshold) movers->list.push_back({side, order[k]});
      }
      k0 = k1;
    }
  }
  return gain;
}

double sweep(InterSurfaceMap& map, const SurfaceRefineOptions& options, RefineStage stage,
             Planner& planner, Backoff* backoff, SurfaceRefineStats& stats,
             Movers* movers = nullptr) {
  // Vertices of one colour (no two adjacent) next to each other: the rings
  // of a batch planned together do not share faces, so an earlier commit
  // seldom changes a later plan.
  double gain = 0;
  for (int side = 0; side < 2; ++side)
    gain += optimise_by_colour(map, options, side, colour_order(map, side), stage, planner, backoff,
                               stats, movers);
  return gain;
}

}  // namespace

double surfaces_sweep(InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  SurfaceRefineStats unused;
  Planner planner(map, options);
  return sweep(map, options, RefineStage::level_sweeps, planner, nullptr, unused);
}

namespace {

/// The local relaxation queue from `seeds` (pairs side, vertex): each
/// optimised, and a vertex whose move gained more than the options' share
/// of the mean energy per vertex queues its neighbours; at most `max_moves`
/// optimisations.
LocalRelaxationStats relax_from(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                const std::vector<std::pair<int, int>>& seeds,
                                std::size_t max_moves, RefineStage stage, Planner& planner,
                                Backoff* backoff, SurfaceRefineStats& timing) {
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
  const double threshold = relaxation_threshold(map, options, planner.energy());
  std::vector<int> gaining;  // moves of side 1 that gained, per vertex (with discs only)
  if (options.local_disc_every > 0) gaining.assign(map.meta().side[1].n_vertices(), 0);
  // With plans: the queue's first entries planned together; committed as
  // they come off the queue (new entries go to its back).
  std::vector<std::pair<int, int>> batch;
  std::size_t next_plan = 0;
  bool planning = false;
  for (; !queue.empty() && stats.moves < max_moves; ++stats.moves) {
    if (next_plan == batch.size()) {
      batch.clear();
      next_plan = 0;
      planning = planner.on();
      if (planning) {
        batch.assign(queue.begin(),
                     queue.begin() + std::ptrdiff_t(std::min({queue.size(), planner.batch(),
                                                              max_moves - stats.moves})));
        planner.plan(batch, backoff, timing);
      }
    }
    const auto [side, v] = queue.front();
    queue.pop_front();
    queued[side][v] = 0;
    InterSurfaceMap::VertexPlan* plan = planning ? &planner.plan(next_plan++) : nullptr;
    const double g = optimise(map, options, side, v, stage, planner, backoff, timing, plan);
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
                                      RefineStage stage, Planner& planner, Backoff* backoff,
                                      SurfaceRefineStats& timing, const Movers* movers = nullptr) {
  if (!(options.local_relaxation_budget > 0)) return {};
  // Seeds: every vertex, or where the sweep before moved: each mover, its
  // neighbours and the other side's vertices in its ring.
  std::array<std::vector<char>, 2> seed;
  if (movers) {
    for (int side = 0; side < 2; ++side) seed[side].assign(map.meta().side[side].n_vertices(), 0);
    for (const auto& [side, v] : movers->list) {
      seed[side][v] = 1;
      for (int w : map.neighbours(side, v)) seed[side][w] = 1;
      for (int x : map.others_in_ring(side, v)) seed[1 - side][x] = 1;
    }
  }
  // (By colour, as a sweep: the queue's first entries planned together
  // seldom share a face.)
  std::vector<std::pair<int, int>> all;
  for (int side = 0; side < 2; ++side)
    for (int v : colour_order(map, side).order)
      if (!movers || seed[side][v]) all.push_back({side, v});
  const double vertices = double(map.n_vertices(0) + map.n_vertices(1));
  return relax_from(map, options, all, std::size_t(options.local_relaxation_budget * vertices),
                    stage, planner, backoff, timing);
}

}  // namespace

LocalRelaxationStats surfaces_local_relaxation(InterSurfaceMap& map,
                                               const SurfaceRefineOptions& options) {
  SurfaceRefineStats unused;
  Planner planner(map, options);
  return local_relaxation(map, options, RefineStage::relaxation, planner, nullptr, unused);
}

LocalRelaxationStats surfaces_relax_from(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                         const std::vector<std::pair<int, int>>& seeds,
                                         std::size_t max_moves) {
  SurfaceRefineStats unused;
  Planner planner(map, options);
  return relax_from(map, options, seeds, max_moves, RefineStage::relaxation, planner, nullptr,
                    unused);
}

namespace {

/// Whether both sides of `map` have reached their race size
/// (SurfaceRefineOptions::race_faces, race_fraction).
bool past_race(const InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  for (int s = 0; s < 2; ++s) {
    // (A split adds two faces.)
    const std::size_t full = map.n_faces(s) + 2 * (map.splits_total(s) - map.splits_applied(s));
    const auto size = std::min(double(options.race_faces), options.race_fraction * double(full));
    if (double(map.n_faces(s)) < size) return false;
  }
  return true;
}

/// Whether the race of the options is still to run on `map`.
bool race_ahead(const InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  const bool finished =
      map.splits_applied(0) >= map.splits_total(0) && map.splits_applied(1) >= map.splits_total(1);
  return !options.race_level_sweeps.empty() && !finished && !past_race(map, options);
}

/// The coarse race (SurfaceRefineOptions::race_level_sweeps): `map`
/// replaced by the copy of lowest energy. The copies refine side by side
/// (each one the same map whatever runs beside it). False if after_level
/// stopped a copy (`map` is then the first such copy).
bool race(InterSurfaceMap& map, const SurfaceRefineOptions& options, SurfaceRefineStats& stats) {
  const Stopwatch watch;
  const std::size_t n = options.race_level_sweeps.size();
  std::vector<std::optional<InterSurfaceMap>> copies(n);
  std::vector<SurfaceRefineStats> runs(n);
  std::vector<char> stopped_by_caller(n, 0);
  std::vector<std::exception_ptr> failed(n);
  std::mutex caller;  // after_level of the caller, one copy at a time
  // (On the options' threads: one, the copies one after the other.)
  tbb::task_arena arena(options.threads > 0 ? options.threads
                                            : tbb::this_task_arena::max_concurrency());
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
      copies[k].emplace(map);
      SurfaceRefineOptions o = options;
      o.race_level_sweeps.clear();
      o.max_level_sweeps = options.race_level_sweeps[k];
      o.on_step = nullptr;
      if (k > 0) o.progress = nullptr;  // (the first copy's progress stands for all)
      o.after_level = [&, k](const InterSurfaceMap& m) {
        if (options.after_level) {
          const std::lock_guard lock(caller);
          if (!options.after_level(m)) return !(stopped_by_caller[k] = 1);
        }
        return !past_race(m, options);
      };
      try {
        runs[k] = refine_surfaces(*copies[k], o);
      } catch (const std::exception&) {
        failed[k] = std::current_exception();
      }
    });
  });
  // A copy whose split found no place is out of the race; if all are, the
  // first one's error is thrown (`map` unchanged).
  if (std::all_of(failed.begin(), failed.end(), [](const auto& e) { return bool(e); }))
    std::rethrow_exception(failed[0]);
  std::vector<double> energies;
  for (std::size_t k = 0; k < n; ++k)
    energies.push_back(failed[k] ? HUGE_VAL : copies[k]->energy());
  const auto first_stopped = std::find(stopped_by_caller.begin(), stopped_by_caller.end(), 1);
  const std::size_t winner =
      first_stopped != stopped_by_caller.end()
          ? std::size_t(first_stopped - stopped_by_caller.begin())
          : std::size_t(std::min_element(energies.begin(), energies.end()) - energies.begin());
  // (The winner's counts are the map's; the losers' are dropped.)
  stats = std::move(runs[winner]);
  map = std::move(*copies[winner]);
  const bool go_on = !stopped_by_caller[winner];
  stats.stopped = false;
  stats.race_energies = std::move(energies);
  stats.race_winner = int(winner);
  stats.seconds_race = watch.seconds();
  if (options.progress) {
    const double total = double(map.splits_total(0) + map.splits_total(1));
    if (total > 0) options.progress(double(map.splits_applied(0) + map.splits_applied(1)) / total);
  }
  return go_on;
}

}  // namespace

SurfaceRefineStats refine_surfaces(InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  const Stopwatch watch;
  SurfaceRefineStats stats;
  if (race_ahead(map, options) && !race(map, options, stats)) {
    stats.stopped = true;
    stats.energy = map.energy();
    stats.seconds = watch.seconds();
    return stats;
  }
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
  // (A split adds one vertex.)
  const std::size_t full_vertices =
      last_sweep + total_splits - map.splits_applied(0) - map.splits_applied(1);
  int side = fraction(0) <= fraction(1) ? 0 : 1;
  std::size_t in_block = 0;
  // A split put off (options.defer_growth): its side, the other side's
  // splits still to make before it is tried again, how often it was; and
  // the failures since the last split made (two in a row: neither side can
  // go on).
  struct Deferred {
    int side = -1;
    std::size_t left = 0;
    int times = 0;
    int stalled = 0;
  } deferred;
  Planner planner(map, options);
  // The closing figures, when finished or stopped by after_level.
  auto closed = [&] {
    stats.large_chart_skips = backoff_state.skipped();
    stats.energy = map.energy();
    stats.seconds = watch.seconds();
    return stats;
  };
  struct Split {
    int side, vs;
    bool hard;  // its growth above options.hard_split_growth
  };
  std::vector<Split> splits;
  // Both sides' splits applied so far.
  auto applied = [&] { return double(map.splits_applied(0) + map.splits_applied(1)); };
  bool released = false;
  auto release = [&] {
    map.release_features();
    released = true;
  };
  // How far optimisations search: the fine way from fine_search_from of
  // the splits on (the final sweeps too).
  bool fine = false;
  auto search_settings = [&] {
    if (!fine && applied() >= options.fine_search_from * double(total_splits)) fine = true;
    map.set_search(fine ? options.fine_search : options.search);
    map.set_split_placement(fine ? options.fine_split_placement : options.split_placement);
  };
  for (;;) {
    search_settings();
    if (fraction(0) >= 1 && fraction(1) >= 1) break;
    if (!released && options.release_features_at >= 0 &&
        applied() >= options.release_features_at * double(total_splits))
      release();
    // A batch of splits, then their new rings optimised together (by
    // colour, planned ahead), then the other side's vertices inside them.
    splits.clear();
    std::array<std::vector<int>, 2> rings, others;
    bool level = false;
    while (!level && splits.size() < std::max<std::size_t>(options.split_batch, 1) &&
           (fraction(0) < 1 || fraction(1) < 1)) {
      const bool retry =  // the split put off, tried again
          deferred.side >= 0 && (deferred.left == 0 || fraction(1 - deferred.side) >= 1);
      if (retry) {
        side = deferred.side;
        deferred.side = -1;
        in_block = 0;
      } else if (deferred.side >= 0) {
        side = 1 - deferred.side;
        --deferred.left;
      } else if (in_block >= options.block || fraction(side) >= 1) {
        side = fraction(0) <= fraction(1) ? 0 : 1;
        in_block = 0;
      }
      const Stopwatch split_watch;
      int vs = -1;
      try {
        planner.run([&] { vs = map.split_next(side); });
      } catch (const std::runtime_error&) {
        // The map is as before the split. Holding the features may be what
        // blocks it: release them now, as the schedule would later.
        std::exception_ptr failure = std::current_exception();
        if (!released && options.release_features_at >= 0) {
          stats.features_released_early_at = applied() / double(total_splits);
          release();
          try {
            planner.run([&] { vs = map.split_next(side); });
            failure = nullptr;
          } catch (const std::runtime_error&) {
            failure = std::current_exception();
          }
        }
        if (failure) {
          // Or the other side is too coarse there yet: put the split off
          // while the other side refines, then try it again.
          const std::size_t other_left = map.splits_total(1 - side) - map.splits_applied(1 - side);
          const int times = retry ? deferred.times : 0;
          if (!(options.defer_growth > 0) || other_left == 0 || ++deferred.stalled > 1 ||
              times >= options.max_deferrals)
            std::rethrow_exception(failure);
          deferred.times = times + 1;
          ++stats.split_deferrals;
          deferred.side = side;
          deferred.left = std::min(
              other_left,
              std::max<std::size_t>(1, std::size_t(std::ceil(options.defer_growth *
                                                             double(map.n_vertices(1 - side))))));
          stats.seconds_splits += split_watch.seconds();
          continue;
        }
      }
      deferred.stalled = 0;
      if (retry) deferred.times = 0;
      stats.seconds_splits += split_watch.seconds();
      ++in_block;
      ++stats.splits;
      after(map, options, {SurfaceStep::split, side, vs, 0.0});
      splits.push_back({side, vs, map.last_split_growth() > options.hard_split_growth});
      for (int v : map.neighbours(side, vs)) rings[side].push_back(v);
      rings[side].push_back(vs);
      const std::size_t total = map.n_vertices(0) + map.n_vertices(1);
      level = double(total) >= options.sweep_growth * double(last_sweep) &&
              double(total) * options.final_level_merge <= double(full_vertices);
      if (options.progress && total_splits) options.progress(applied() / double(total_splits));
    }
    for (int s = 0; s < 2; ++s)
      optimise_by_colour(map, options, s, by_colour(map, s, rings[s]), RefineStage::split_rings,
                         planner, backoff, stats);
    if (options.optimise_other_side) {
      for (const Split& split : splits)
        for (int x : map.others_in_ring(split.side, split.vs)) others[1 - split.side].push_back(x);
      for (int s = 0; s < 2; ++s)
        optimise_by_colour(map, options, s, by_colour(map, s, others[s]), RefineStage::other_side,
                           planner, backoff, stats);
    }
    for (const Split& split : splits) {
      if (!split.hard) continue;
      ++stats.hard_splits;
      if (!(options.hard_split_relaxation > 0)) continue;
      std::vector<std::pair<int, int>> region;
      for (int v : map.neighbours(split.side, split.vs)) region.push_back({split.side, v});
      region.push_back({split.side, split.vs});
      if (options.optimise_other_side)
        for (int x : map.others_in_ring(split.side, split.vs))
          if (map.is_active(1 - split.side, x)) region.push_back({1 - split.side, x});
      add(relax_from(map, options, region, options.hard_split_relaxation * region.size(),
                     RefineStage::hard_splits, planner, backoff, stats));
    }
    if (level) {
      const double e = planner.energy();
      Movers movers;
      Movers* record = options.relax_from_movers ? &movers : nullptr;
      for (int k = 0; k < options.max_level_sweeps; ++k) {
        ++stats.sweeps;
        movers = {relaxation_threshold(map, options, planner.energy()), {}};
        if (sweep(map, options, RefineStage::level_sweeps, planner, backoff, stats, record) <
            1e-3 * e)
          break;
      }
      add(local_relaxation(map, options, RefineStage::relaxation, planner, backoff, stats, record));
      last_sweep = map.n_vertices(0) + map.n_vertices(1);
      if (options.after_level && !options.after_level(map)) {
        stats.stopped = true;
        return closed();
      }
    }
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
  Movers movers;
  Movers* record = options.relax_from_movers ? &movers : nullptr;
  for (int k = 0; k < options.max_final_sweeps; ++k) {
    const double e = planner.energy();
    ++stats.final_sweeps;
    movers = {relaxation_threshold(map, options, e), {}};
    if (sweep(map, options, RefineStage::final_sweeps, planner, backoff, stats, record) <
        options.final_relative_gain * e)
      break;
  }
  add(local_relaxation(map, options, RefineStage::final_relaxation, planner, backoff, stats,
                       record));
  return closed();
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
