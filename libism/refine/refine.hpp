#pragma once
// Coarse-to-fine refinement (paper §5): replay the vertex splits of M²; after
// each, optimise the new vertex, the split vertex and their neighbours; a
// full sweep whenever the vertex count has grown by `sweep_growth`, then
// local relaxation where the map still moves; final sweeps until the
// relative gain is small, and local relaxation again.
#include "map/surface_map.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace ism {

struct RefineOptions {
  double sweep_growth = 1.5;
  int max_level_sweeps = 10;  // sweeps per level while they still gain
  double level_relative_gain = 2e-3;
  std::size_t coarse_vertices = 2000;  // below this, 4x the sweeps and 1/10 the gain
  double final_relative_gain = 1e-3;   // stop final sweeps below this gain
  int max_final_sweeps = 8;
  /// After each level's sweeps and after the final ones, vertices keep being
  /// re-optimised where the map still moves (local_relaxation): a vertex
  /// whose move lowered the energy by more than this fraction of the mean
  /// energy per vertex queues its neighbours, at most
  /// `local_relaxation_budget` × vertices moves each time (0: never). A
  /// region squeezed at a coarse level unfolds only a little per sweep,
  /// since each vertex is confined by its squeezed neighbours; the queue
  /// keeps working there without sweeping the settled rest (fandisk.obj:
  /// one-way efficiency 0.05 -> 0.84; bunny: 102 -> 31 folded grid
  /// triangles in its image).
  double local_relaxation_gain = 1e-4;
  double local_relaxation_budget = 100;
  /// During local relaxation, a vertex that keeps gaining has the disc of
  /// `local_disc_rings` rings around it re-embedded whole after every
  /// `local_disc_every` gaining moves (0: never). fandisk.obj's octahedral
  /// map: refinement 29 s -> 11 s, one-way efficiency 0.787 -> 0.804.
  int local_disc_every = 10;
  int local_disc_rings = 3;
  /// Before each local relaxation, discs around the faces whose energy
  /// exceeds `disc_outlier` × the mean face energy are re-embedded whole
  /// (disc_relaxation.hpp; at most `max_discs` faces each time, 0: never):
  /// regions squeezed into a sliver of M¹ that vertex-at-a-time moves
  /// cannot open.
  double disc_outlier = 50;
  std::size_t max_discs = 64;
  /// Stop the refinement once the surface has this many vertices (skipping
  /// the final sweeps); refine() can be called again to go on.
  std::size_t stop_at_vertices = SIZE_MAX;
  /// Global flat-torus re-embedding (flat_reembedding.hpp) on domains where
  /// it applies (SurfaceMap::is_free_flat_torus: the unit-square torus with
  /// its features released): before the sweeps of each level while the
  /// surface has at most `reembed_max_vertices` vertices, and before the
  /// final sweeps if `reembed_final`. Each is kept only if it lowers the
  /// symmetric energy; the vertex-at-a-time sweeps follow it. The final
  /// one decides the result (the level ones cost little and keep the
  /// coarse maps, which choose_network compares, out of squeezed states).
  bool global_flat_reembedding = false;
  std::size_t reembed_max_vertices = 3000;
  bool reembed_final = true;
  /// Call validate() after every split and sweep (for tests; slow).
  bool validate_each_step = false;
  /// Re-embed the disc around a split that leaves a face squeezed almost
  /// flat (above 1e6 x the mean face energy); off only to study the squeezed
  /// maps it prevents.
  bool repair_squeezed_splits = true;
  std::function<void(double)> progress;  // fraction of splits done
};

struct RefineStats {
  std::size_t splits = 0;
  // Discs re-embedded around blocked splits (SplitBlocked) and around
  // splits that left a face squeezed almost flat.
  std::size_t split_repairs = 0;
  std::size_t sweeps = 0;
  std::size_t final_sweeps = 0;
  std::size_t local_moves = 0;               // optimisations by local_relaxation
  std::size_t discs = 0, discs_applied = 0;  // disc re-embeddings tried and kept (both kinds)
  std::size_t optimizations = 0;
  std::size_t single_face_rings = 0;  // optimisations whose one-ring lay in one M¹ face
  double energy_before_final = 0, energy = 0;
  std::size_t reembeddings = 0, reembeddings_applied = 0;  // global flat-torus re-embeddings
  double seconds = 0;                                      // wall seconds of the call
};

/// Refines `map` to the full resolution of its progressive mesh. Throws
/// std::runtime_error when a validation (if asked for) fails.
RefineStats refine(SurfaceMap& map, const RefineOptions& options = {});

/// Whether refine() sweeps a level once the surface has `vertices` vertices,
/// its last level sweep (or its start) having been at `last_sweep`.
inline bool level_sweep_due(const RefineOptions& options, std::size_t vertices,
                            std::size_t last_sweep) {
  return double(vertices) >= options.sweep_growth * double(last_sweep);
}

/// The largest vertex count at most `limit` at which refine(), started on a
/// map of `vertices` vertices, sweeps a level (`vertices` if there is none).
/// Stopping there (stop_at_vertices) and calling refine() again refines
/// exactly as one call would, so candidates can be compared there and the
/// kept ones refined on (choose_network's race).
std::size_t last_level_sweep_at_most(const RefineOptions& options, std::size_t vertices,
                                     std::size_t limit);

/// One optimisation pass: released cones first, then every active vertex in
/// index order; returns the energy decrease. With `validate_each_step`,
/// validate() after every operation (throws std::runtime_error naming it).
double optimization_sweep(SurfaceMap& map, bool validate_each_step = false);

/// Re-optimises free vertices from a queue holding every active vertex in
/// index order; a move that gains more than `relative_gain` × energy /
/// vertices queues the mover's neighbours again. A vertex still gaining
/// after every `disc_every` such moves (0: never) has its `disc_rings`
/// rings re-embedded whole (reembed_disc), which queues them again when it
/// gains: where single moves converge slowly (skinny triangles, squeezed
/// bands) the disc's joint descent goes the distance at once. Stops when
/// the queue is empty or after `budget` × vertices single moves.
/// Deterministic.
struct LocalRelaxationStats {
  double gain = 0;  // energy decrease
  std::size_t moves = 0, discs = 0, discs_applied = 0;
};
LocalRelaxationStats local_relaxation(SurfaceMap& map, double relative_gain, double budget,
                                      int disc_every = 0, int disc_rings = 3,
                                      bool validate_each_step = false);

}  // namespace ism
