#include "refine/network_choice.hpp"

#include <stdexcept>

namespace ism {
namespace {

// Builds every candidate's map, refines it to `coarse_vertices` and keeps the
// lowest symmetric energy; a single candidate is returned unrefined.
template <class MakeSetup>
std::unique_ptr<MapSetup> choose(std::size_t count, const MakeSetup& make_setup,
                                 std::size_t coarse_vertices) {
  std::unique_ptr<MapSetup> best;
  double best_energy = 0;
  RefineOptions coarse;
  coarse.stop_at_vertices = coarse_vertices;
  for (std::size_t i = 0; i < count; ++i) {
    std::unique_ptr<MapSetup> setup = make_setup(i);
    setup->candidate = i;
    if (count == 1) return setup;
    refine(*setup->map, coarse);
    const double energy = setup->map->energy();
    if (!best || energy < best_energy) {
      best = std::move(setup);
      best_energy = energy;
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
