#pragma once
// Coarse-to-fine refinement of an InterSurfaceMap on both sides (paper §5):
// the vertex splits of both progressive meshes are replayed, the side that
// is less refined (as a fraction of its splits) next, so both reach full
// resolution together; after each batch of splits (split_batch) the new
// vertices and their neighbours are optimised, then the other side's
// vertices inside their rings (after a hard split, the relaxation queue
// from them);
// whenever the vertices of both sides together have grown by
// `sweep_growth`, every vertex of both sides is (unless that level lies
// within `final_level_merge` of full resolution); final sweeps at full
// resolution until the relative gain is small.
#include "map/inter_surface_map.hpp"
#include "refine/refine.hpp"

#include <array>
#include <functional>
#include <string>

namespace ism {

/// One operation of the refinement, as reported to SurfaceRefineOptions::on_step.
struct SurfaceStep {
  enum Kind { split, optimise } kind;
  int side, vertex;
  /// The energy gained (optimise: > 0, the move was kept); 0 for a split,
  /// which may raise the energy.
  double gain;
};

struct SurfaceRefineOptions {
  double sweep_growth = 1.5;
  int max_level_sweeps = 2;
  /// A level that would fall within this factor of full resolution (the
  /// vertices of both sides times it more than those of both at the end)
  /// runs no sweeps and no relaxation of its own: the final sweeps, soon
  /// after, do that work (1: every level runs, one at full resolution too).
  double final_level_merge = 1;
  int max_final_sweeps = 4;
  double final_relative_gain = 1e-3;
  /// Splits of one side in a row before the other side's turn (the paper
  /// refines one side for a number of steps, then swaps); 1 interleaves.
  std::size_t block = 1;
  /// After a split and its ring's optimisation, optimise also the other
  /// side's vertices inside or on the new ring, so the detail a split brings
  /// is met from both sides (false: the split side only).
  bool optimise_other_side = true;
  /// After each level's sweeps and after the final ones, vertices keep being
  /// re-optimised where the map still moves: a vertex whose move gained
  /// more than `local_relaxation_gain` × the mean energy per vertex queues
  /// its neighbours, at most `local_relaxation_budget` × the vertices of
  /// both sides moves each time (0: never). As in refine(): a region
  /// squeezed at a coarse level unfolds a little per sweep, each vertex
  /// confined by its squeezed neighbours.
  double local_relaxation_gain = 1e-4;
  double local_relaxation_budget = 100;
  /// The queue after a level's sweeps and after the final ones starts from
  /// where the last sweep still moved (each vertex that gained more than
  /// the queue's threshold, its neighbours, the other side's vertices in
  /// its ring) instead of from every vertex (false). ism-map sets it.
  bool relax_from_movers = false;
  /// How far the optimisations search in general charts
  /// (InterSurfaceMap::set_search): `search` until `fine_search_from` of
  /// both sides' splits are applied, then `fine_search` to the end (the
  /// final sweeps too). A map's basin is decided at its coarse levels,
  /// whose searches cost little; ism-map searches its fine levels in one
  /// round to 1e-3 (half the energy evaluations at the same energy within
  /// 0.01 %; docs/results-ism.md, stop 71).
  KernelSearch search;
  KernelSearch fine_search;
  double fine_search_from = 0.25;
  /// How splits place their new vertex (InterSurfaceMap::set_split_placement),
  /// switched with the search at `fine_search_from`. ism-map's fine levels
  /// evaluate the first halving only and search like the optimisations:
  /// the ring's optimisation soon after moves the vertex again
  /// (docs/results-ism.md, stop 89).
  SplitPlacement split_placement;
  SplitPlacement fine_split_placement;
  /// During local relaxation, a vertex of side 1 that keeps gaining has the
  /// disc of `local_disc_rings` rings around it re-embedded whole after
  /// every `local_disc_every` gaining moves (0: never), where the disc lies
  /// over one face of side 0 or two across their shared edge (reembed_disc,
  /// refine/disc_relaxation.hpp; RefineOptions::local_disc_every's
  /// counterpart).
  int local_disc_every = 0;
  int local_disc_rings = 3;
  /// After a hard split, one that raised the energy of its faces more than
  /// `hard_split_growth`-fold (InterSurfaceMap::last_split_growth(): a
  /// nearly degenerate piece, which the new ring's one optimisation may
  /// not undo, and later splits there compound), the same queue runs from
  /// the vertices just optimised (the new ring's and the other side's
  /// inside it), at most `hard_split_relaxation` moves per such vertex (0:
  /// never).
  double hard_split_growth = 10;
  std::size_t hard_split_relaxation = 50;
  /// Vertices whose optimisation in a large chart (InterSurfaceMap::
  /// last_chart() is ChartKind::large: a cone of a coarse domain, whose
  /// chart holds much of the surface) found no lower energy are retried
  /// less and less often: after k such failures in a row, the next 2^k - 1
  /// of its optimisations
  /// are skipped (k at most 6); a kept move resets it. Once 8 large charts
  /// of a side have failed and none has gained, the vertices of that side
  /// whose last chart was large are not optimised again. Such a chart costs
  /// as much as a thousand small ones, and where SurfaceMap has placed the
  /// cones (a resumed map, as the remeshers' symmetric core is) their
  /// continuous moves do not get below the map's energy. Off by default:
  /// from a trivial map the cones do move, and a skipped move changes all
  /// that follows (fandisk from the trivial map then stops at a split).
  bool large_chart_backoff = false;
  /// A step that moves the whole map at once, run at full resolution before
  /// the final sweeps (e.g. the flat torus's global re-embedding,
  /// refine/flat_reembedding.hpp); returns the energy it gained (0: the map
  /// unchanged). Empty: none.
  std::function<double(InterSurfaceMap&)> before_final;
  /// validate() after every operation (for tests; slow). Throws
  /// std::runtime_error naming the operation that broke the map.
  bool validate_each_step = false;
  /// Splits made in a row before their new rings are optimised (together,
  /// by colour, planned ahead on `threads`); 1: after every split, as the
  /// paper does. (8 spreads more of the work over the threads, but moved
  /// the two-surface pairs' medians down: results-two-surfaces.md, stop 61.)
  std::size_t split_batch = 8;
  /// Threads that plan vertex optimisations ahead (InterSurfaceMap::VertexPlan:
  /// the sweeps', the split batches' and the relaxation queues'; 0: as many
  /// as the task arena has, 1: none). The map refined is the same for every
  /// value.
  int threads = 0;
  /// Features held by the map (InterSurfaceOptions::hold_features) are
  /// released (InterSurfaceMap::release_features) before the first batch of
  /// splits that starts at or after this fraction of all splits (0: at once;
  /// negative: never). The paper uses its constraints to initialise the map
  /// and drops them during the coarse-to-fine optimisation.
  double release_features_at = -1;
  /// A split that finds no place while the other side still has splits
  /// (after the features are released, if they were to be) is put off: the other
  /// side splits until its vertices have grown by this fraction (at least
  /// one split; with their optimisations and any level that falls due),
  /// then the split is tried again; at most `max_deferrals` times in a
  /// row, then its error is thrown. Near a held feature a coarse other side
  /// may leave a split no room that its own refinement makes. 0: never
  /// put off.
  double defer_growth = 0;
  int max_deferrals = 4;
  std::function<void(double)> progress;  // fraction of all splits done
  /// Called after every split and every kept move (for traces and tests of
  /// the energy bookkeeping); may throw to stop the refinement.
  std::function<void(const SurfaceStep&)> on_step;
  /// Called after each level's sweeps and local relaxation (both sides'
  /// vertices grown `sweep_growth`-fold since the last) with the map there;
  /// false stops the refinement at once: the map is left valid at that
  /// level, no final sweeps run, and SurfaceRefineStats::stopped is set.
  std::function<bool(const InterSurfaceMap&)> after_level;
  /// Schedules raced at the coarse levels (empty: none). While a side has
  /// fewer faces than its race size (`race_faces`, or `race_fraction` of
  /// its faces at full resolution if that is fewer), a copy of the map is
  /// refined with each of these level-sweep counts (in place of
  /// max_level_sweeps) to the first level at which both sides have reached
  /// their race size; the copy of lowest energy (ties: the earlier entry)
  /// goes on, with max_level_sweeps. All copies apply the same splits, so
  /// they are compared at the same resolution. The coarse levels decide the
  /// basin the map refines into (docs/results-ism.md, stop 68). The copies
  /// refine side by side on `threads` (one after the other on one); they
  /// report no on_step, the first reports progress, and after_level is
  /// called on each (one at a time) and stops the whole refinement when it
  /// returns false (the map left is the first copy it stopped). A copy
  /// whose split throws is out of the race; if all do, the first one's
  /// error is thrown with the map as it was before the race.
  std::vector<int> race_level_sweeps;
  std::size_t race_faces = 500;
  double race_fraction = 0.1;
};

/// The searches ism-map and the remeshers' symmetric core refine with: every
/// line search seeded by the energy's quadratic model, the fine levels
/// (from `fine_search_from`) searched in one round to 1e-3 of the ring's
/// size, and their splits placed after the first halving with that search
/// (the ring's optimisation soon after moves the vertex again). Leaves
/// every other option as it is (measured: docs/results-ism.md, stops 71,
/// 73, 89; docs/results-two-surfaces.md, stop 92).
inline void use_fast_searches(SurfaceRefineOptions& options) {
  options.fine_search = {1e-3, 1};
  options.search.model_seed = options.fine_search.model_seed = true;
  options.fine_split_placement = {1, options.fine_search};
}

/// What an optimisation of refine_surfaces ran for: the new rings of a
/// batch of splits, the other side's vertices inside them, the relaxation
/// after a hard split, the level sweeps, the local relaxation queue after
/// each level, the final sweeps, the local relaxation queue after them.
enum class RefineStage {
  split_rings,
  other_side,
  hard_splits,
  level_sweeps,
  relaxation,
  final_sweeps,
  final_relaxation
};
inline constexpr std::size_t kRefineStages = 7;
/// "split_rings", "other_side", ... (report keys).
const char* refine_stage_name(RefineStage stage);

struct SurfaceRefineStats {
  std::size_t splits = 0, sweeps = 0, final_sweeps = 0;
  /// The vertex optimisations that ran (laid out a chart: those the
  /// back-off skipped and pinned or inactive vertices not counted), by what
  /// they ran for (indexed by RefineStage); they sum to the map's
  /// MapOperationStats::optimizations gained in refine_surfaces.
  std::array<std::size_t, kRefineStages> optimizations_by_stage{};
  std::size_t local_moves = 0;               // moves of the local relaxation queues
  std::size_t discs = 0, discs_applied = 0;  // their disc re-embeddings: tried, kept
  std::size_t hard_splits = 0;               // splits above hard_split_growth, relaxed
  std::size_t large_chart_skips = 0;         // optimisations skipped by large_chart_backoff
  std::size_t global_steps = 0, global_steps_applied = 0;  // before_final: run, gained
  double energy = 0;
  /// Wall seconds of the call, and the parts they went to: the vertex
  /// optimisations it ran, by the chart each was laid out in (indexed by
  /// ChartKind; those a split's retries run count with the split), the
  /// splits, and the discs of the local relaxation (gathered, laid out,
  /// descended, committed or refused). The rest (sweep bookkeeping, the
  /// global step, validation when asked) is the difference.
  double seconds = 0;
  std::array<double, kChartKinds> seconds_by_chart{};
  double seconds_splits = 0, seconds_discs = 0;
  /// Wall seconds of planning optimisations on several threads (their
  /// commits count by chart above).
  double seconds_planning = 0;
  bool stopped = false;  // after_level returned false: not fully refined
  /// The fraction of the splits done when the held features were released
  /// early because a split found no place while they were held (-1: not).
  double features_released_early_at = -1;
  /// Splits put off until the other side had refined (defer_growth).
  std::size_t split_deferrals = 0;
  /// The coarse race (SurfaceRefineOptions::race_level_sweeps): each
  /// schedule's energy where the race ended (same order; HUGE_VAL for a
  /// copy whose split failed), the winner's
  /// index (-1: no race ran) and the seconds it took.
  std::vector<double> race_energies;
  int race_winner = -1;
  double seconds_race = 0;
};

/// Refines both sides to full resolution. Throws std::runtime_error (from
/// InterSurfaceMap::split_next, naming the split) when a split finds no valid
/// place after its retries; the map is then the valid one before that split.
/// When the features are to be released later (release_features_at >= 0)
/// and a split fails while they are held, they are released there and the
/// split tried again (a held feature may be the vertex that has to move);
/// a split that still fails, or fails with no features to release, may be
/// put off (defer_growth); only the last failure throws.
SurfaceRefineStats refine_surfaces(InterSurfaceMap& map, const SurfaceRefineOptions& options = {});

/// One line (no newline) on a refinement refine_surfaces stopped with the
/// message `what`: both sides' face counts, the reason, whether the map left
/// is valid from both sides, its symmetric efficiency (when valid) and
/// energy, the splits retried and placed in place.
std::string describe_stop(const InterSurfaceMap& map, const std::string& what);

/// One optimisation of every active vertex of both sides; the energy gained.
double surfaces_sweep(InterSurfaceMap& map, const SurfaceRefineOptions& options = {});

/// The local relaxation queue described at SurfaceRefineOptions (with its
/// gain, budget and discs): the energy gained, the moves and discs made.
LocalRelaxationStats surfaces_local_relaxation(InterSurfaceMap& map,
                                               const SurfaceRefineOptions& options);

/// The same queue started from `seeds` (pairs side, vertex) instead of every
/// vertex, at most `max_moves` optimisations: what refine_surfaces runs
/// after a hard split (SurfaceRefineOptions::hard_split_growth), for
/// drivers of their own. Each kept move goes through the options' hooks.
LocalRelaxationStats surfaces_relax_from(InterSurfaceMap& map, const SurfaceRefineOptions& options,
                                         const std::vector<std::pair<int, int>>& seeds,
                                         std::size_t max_moves);

}  // namespace ism
