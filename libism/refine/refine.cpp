#include "refine/refine.hpp"

#include "refine/disc_relaxation.hpp"
#include "refine/flat_reembedding.hpp"
#include "refine/stopwatch.hpp"

#include <algorithm>
#include <deque>
#include <stdexcept>

namespace ism {

namespace {

// A face whose energy exceeds this many times the mean face energy is
// squeezed beyond what optimisation repairs (a healthy map's largest are
// within 1e3 of the mean).
constexpr double kSqueezedFaceEnergy = 1e6;

// With validation on, every single operation is checked, so a failure names
// the operation that broke the map.
void check_operation(const SurfaceMap& map, bool on, const char* what, int v) {
  if (!on) return;
  if (auto problem = map.validate())
    throw std::runtime_error(std::string("map invalid after ") + what + " of vertex " +
                             std::to_string(v) + ": " + *problem);
}

}  // namespace

double optimization_sweep(SurfaceMap& map, bool validate_each_step) {
  double gain = 0.0;
  // Released cones first: each may walk a few steps downhill (one when each
  // step relaxes its neighbourhood, which costs as much as a few steps).
  const int steps = map.options().cone_relaxation_rings > 0 ? 1 : 4;
  for (std::size_t x = 0; x < map.domain().n_vertices(); ++x)
    for (int step = 0; step < steps; ++step) {
      const int v = map.vertex_at_domain_vertex(int(x));
      const double g = v >= 0 ? map.relocate_cone(v) : 0.0;
      check_operation(map, validate_each_step, "moving a cone", v);
      if (g <= 0) break;
      gain += g;
    }
  for (std::size_t v = 0; v < map.positions().size(); ++v)
    if (map.is_active(int(v))) {
      gain += map.optimize_vertex(int(v));
      check_operation(map, validate_each_step, "optimising", int(v));
    }
  return gain;
}

LocalRelaxationStats local_relaxation(SurfaceMap& map, double relative_gain, double budget,
                                      int disc_every, int disc_rings, bool validate_each_step) {
  LocalRelaxationStats stats;
  const std::size_t n = map.positions().size();
  std::deque<int> queue;
  std::vector<char> queued(n, 0);
  auto enqueue = [&](int v) {
    if (!queued[v] && map.is_active(v) && !map.is_pinned(v)) queue.push_back(v), queued[v] = 1;
  };
  for (std::size_t v = 0; v < n; ++v) enqueue(int(v));
  const double threshold = relative_gain * map.energy() / double(map.n_vertices());
  const auto max_moves = std::size_t(budget * double(map.n_vertices()));
  std::vector<int> gaining(n, 0);  // moves that gained, per vertex
  while (!queue.empty() && stats.moves < max_moves) {
    const int v = queue.front();
    queue.pop_front();
    queued[v] = 0;
    const double g = map.optimize_vertex(v);
    ++stats.moves;
    check_operation(map, validate_each_step, "optimising", v);
    stats.gain += g;
    if (g <= threshold) continue;
    for (int w : map.neighbours(v)) enqueue(w);
    if (disc_every <= 0 || ++gaining[v] % disc_every != 0) continue;
    const std::vector<int> disc = map.rings_around(v, disc_rings);
    const double d = reembed_disc(map, disc);
    check_operation(map, validate_each_step, "re-embedding a disc around", v);
    ++stats.discs;
    if (d <= 0) continue;
    ++stats.discs_applied;
    stats.gain += d;
    for (int w : disc) enqueue(w);
  }
  return stats;
}

std::size_t last_level_sweep_at_most(const RefineOptions& options, std::size_t vertices,
                                     std::size_t limit) {
  for (std::size_t last = vertices, n = vertices + 1;; ++n) {
    if (n > limit) return last;
    if (level_sweep_due(options, n, last)) last = n;
  }
}

RefineStats refine(SurfaceMap& map, const RefineOptions& options) {
  const Stopwatch watch;
  RefineStats stats;
  auto check = [&](const char* when) {
    if (!options.validate_each_step) return;
    if (auto problem = map.validate())
      throw std::runtime_error(std::string("map invalid ") + when + ": " + *problem);
  };
  const bool reembed = options.global_flat_reembedding && map.is_free_flat_torus();
  auto reembedding = [&] {
    ++stats.reembeddings;
    if (global_flat_reembedding(map).applied) ++stats.reembeddings_applied;
    check("after a global re-embedding");
  };
  auto relax_locally = [&] {
    if (options.max_discs > 0) {
      disc_relaxation(map, options.disc_outlier, options.max_discs, stats.discs,
                      stats.discs_applied, options.validate_each_step);
    }
    if (options.local_relaxation_budget <= 0) return;
    const LocalRelaxationStats local = local_relaxation(
        map, options.local_relaxation_gain, options.local_relaxation_budget,
        options.local_disc_every, options.local_disc_rings, options.validate_each_step);
    stats.local_moves += local.moves;
    stats.discs += local.discs;
    stats.discs_applied += local.discs_applied;
  };
  std::size_t last_sweep = map.n_vertices();
  const std::size_t total = map.splits_total();
  // A split whose one-ring is squeezed flat has no place for its new
  // vertex: the discs of 2, 4, then 8 rings around it are re-embedded whole
  // (which opens such a region when it lowers the energy) and the split
  // retried.
  auto split = [&] {
    for (int rings = 2;; rings *= 2) {
      try {
        return map.split_next();
      } catch (const SplitBlocked&) {
        if (rings > 8) throw;
        ++stats.split_repairs;
        reembed_disc(map, map.rings_around(map.next_split_vertex(), rings));
        check("after re-embedding a blocked split's disc");
      }
    }
  };
  // A split whose one-ring is squeezed almost flat still places its vertex,
  // in a sliver of the kernel: faces of absurd stretch (1e10 times the
  // mean energy seen on bunny_open) that the vertex-by-vertex optimisation
  // cannot open again. Such a split's disc is re-embedded too.
  double mean_face_energy = map.energy() / double(std::max<std::size_t>(map.n_faces(), 1));
  auto squeezed = [&](int v) {
    for (int t : map.vertex_faces(v))
      if (!(map.face_energy(t) <= kSqueezedFaceEnergy * mean_face_energy)) return true;
    return false;
  };
  for (int vs; map.n_vertices() < options.stop_at_vertices && (vs = split()) >= 0;) {
    ++stats.splits;
    check("after a split");
    const std::vector<int> ring = map.neighbours(vs);
    map.optimize_vertex(vs);
    for (int w : ring) map.optimize_vertex(w);
    check("after optimising a split");
    for (int rings = 2; options.repair_squeezed_splits && rings <= 8 && squeezed(vs); rings *= 2) {
      ++stats.split_repairs;
      reembed_disc(map, map.rings_around(vs, rings));
      check("after re-embedding a squeezed split's disc");
    }
    if (level_sweep_due(options, map.n_vertices(), last_sweep)) {
      // Sweep until this level has settled: cheap while the mesh is coarse,
      // and it is there that the large-scale shape of the map is decided.
      if (reembed && map.n_vertices() <= options.reembed_max_vertices) reembedding();
      double energy = map.energy();
      // Coarse levels are cheap: let them converge further.
      const bool coarse = map.n_vertices() < options.coarse_vertices;
      const int max_sweeps = coarse ? 4 * options.max_level_sweeps : options.max_level_sweeps;
      const double min_gain =
          coarse ? 0.1 * options.level_relative_gain : options.level_relative_gain;
      for (int i = 0; i < max_sweeps; ++i) {
        const double gain = optimization_sweep(map, options.validate_each_step);
        ++stats.sweeps;
        energy -= gain;
        if (gain < min_gain * energy) break;
      }
      relax_locally();
      mean_face_energy = map.energy() / double(map.n_faces());
      last_sweep = map.n_vertices();
      check("after a sweep");
    }
    if (options.progress && (stats.splits & 255) == 0)
      options.progress(double(stats.splits) / total);
  }
  if (map.splits_applied() < map.splits_total()) {  // stopped early: no final sweeps
    stats.energy = map.energy();
    stats.seconds = watch.seconds();
    return stats;
  }
  if (reembed && options.reembed_final) reembedding();
  stats.energy_before_final = map.energy();
  double energy = stats.energy_before_final;
  for (int i = 0; i < options.max_final_sweeps; ++i) {
    const double gain = optimization_sweep(map, options.validate_each_step);
    ++stats.final_sweeps;
    energy -= gain;
    if (gain < options.final_relative_gain * energy) break;
  }
  relax_locally();
  check("after the final sweeps");
  stats.energy = map.energy();
  stats.optimizations = map.optimizations();
  stats.single_face_rings = map.single_face_rings();
  if (options.progress) options.progress(1.0);
  stats.seconds = watch.seconds();
  return stats;
}

}  // namespace ism
