#include "refine/refine_surfaces.hpp"

#include <stdexcept>
#include <string>

namespace ism {

namespace {

void check(const InterSurfaceMap& map, bool on, const char* what, int side, int v) {
  if (!on) return;
  if (auto problem = map.validate())
    throw std::runtime_error(std::string("map invalid after ") + what + " of vertex " +
                             std::to_string(v) + " of side " + std::to_string(side) + ": " +
                             *problem);
}

}  // namespace

double surfaces_sweep(InterSurfaceMap& map, bool validate_each_step) {
  double gain = 0;
  for (int side = 0; side < 2; ++side)
    for (std::size_t v = 0; v < map.meta().side[side].n_vertices(); ++v) {
      if (!map.is_active(side, int(v))) continue;
      const double g = map.optimize_vertex(side, int(v));
      if (g > 0) check(map, validate_each_step, "optimising", side, int(v));
      gain += g;
    }
  return gain;
}

SurfaceRefineStats refine_surfaces(InterSurfaceMap& map, const SurfaceRefineOptions& options) {
  SurfaceRefineStats stats;
  const bool each = options.validate_each_step;
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
    const int vs = map.split_next(side);
    ++in_block;
    ++stats.splits;
    check(map, each, "splitting", side, vs);
    std::vector<int> todo = map.neighbours(side, vs);
    todo.push_back(vs);
    for (int v : todo)
      if (map.optimize_vertex(side, v) > 0) check(map, each, "optimising", side, v);
    const std::size_t total = map.n_vertices(0) + map.n_vertices(1);
    if (double(total) >= options.sweep_growth * double(last_sweep)) {
      const double e = map.energy();
      for (int k = 0; k < options.max_level_sweeps; ++k) {
        ++stats.sweeps;
        if (surfaces_sweep(map, each) < 1e-3 * e) break;
      }
      last_sweep = total;
    }
    if (options.progress && total_splits)
      options.progress(double(stats.splits) / double(total_splits));
  }
  for (int k = 0; k < options.max_final_sweeps; ++k) {
    const double e = map.energy();
    ++stats.final_sweeps;
    if (surfaces_sweep(map, each) < options.final_relative_gain * e) break;
  }
  stats.energy = map.energy();
  return stats;
}

}  // namespace ism
