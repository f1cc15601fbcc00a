#include "refine/network_choice.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace ism {
namespace {

// Builds every candidate's map, refines it to `coarse_vertices` and keeps the
// lowest symmetric energy (the first of equals); a single candidate is
// returned unrefined. Candidates are independent, so they run in parallel,
// as many at a time as there are cores (each holds a copy of the surface).
template <class MakeSetup>
std::unique_ptr<MapSetup> choose(std::size_t count, const MakeSetup& make_setup,
                                 std::size_t coarse_vertices) {
  if (count == 1) return make_setup(0);
  RefineOptions coarse;
  coarse.stop_at_vertices = coarse_vertices;
  const std::size_t batch = std::max(1u, std::thread::hardware_concurrency());
  std::unique_ptr<MapSetup> best;
  double best_energy = 0;
  for (std::size_t first = 0; first < count; first += batch) {
    const std::size_t last = std::min(count, first + batch);
    std::vector<std::unique_ptr<MapSetup>> setups(last - first);
    tbb::parallel_for(first, last, [&](std::size_t i) {
      std::unique_ptr<MapSetup> setup = make_setup(i);
      setup->candidate = i;
      refine(*setup->map, coarse);
      setups[i - first] = std::move(setup);
    });
    for (std::unique_ptr<MapSetup>& setup : setups) {
      const double energy = setup->map->energy();
      if (!best || energy < best_energy) {
        best = std::move(setup);
        best_energy = energy;
      }
    }
  }
  return best;
}

}  // namespace

std::unique_ptr<MapSetup> choose_network(std::vector<PathNetwork> networks,
                                         const DomainGeometry& domain, const MapOptions& options,
                                         std::size_t coarse_vertices) {
  if (networks.empty()) throw std::invalid_argument("choose_network: no network");
  return choose(
      networks.size(),
      [&](std::size_t i) {
        auto setup = std::make_unique<MapSetup>();
        setup->network = std::move(networks[i]);
        setup->pm = simplify_constrained(setup->network, domain.mesh());
        setup->map = std::make_unique<SurfaceMap>(domain, setup->pm, options);
        return setup;
      },
      coarse_vertices);
}

std::unique_ptr<MapSetup> choose_domain(std::vector<DomainCandidate> candidates,
                                        const MapOptions& options, std::size_t coarse_vertices) {
  if (candidates.empty()) throw std::invalid_argument("choose_domain: no candidate");
  return choose(
      candidates.size(),
      [&](std::size_t i) {
        auto setup = std::make_unique<MapSetup>();
        setup->owned_domain = std::move(candidates[i].domain);
        setup->network = std::move(candidates[i].network);
        setup->pm = simplify_constrained(setup->network, setup->owned_domain->mesh());
        setup->map = std::make_unique<SurfaceMap>(*setup->owned_domain, setup->pm, options);
        return setup;
      },
      coarse_vertices);
}

}  // namespace ism
