#include "refine/network_choice.hpp"

#include <stdexcept>

namespace ism {

std::unique_ptr<MapSetup> choose_network(std::vector<PathNetwork> networks,
                                         const DomainGeometry& domain, const MapOptions& options,
                                         std::size_t coarse_vertices) {
  if (networks.empty()) throw std::invalid_argument("choose_network: no network");
  std::unique_ptr<MapSetup> best;
  double best_energy = 0;
  RefineOptions coarse;
  coarse.stop_at_vertices = coarse_vertices;
  for (PathNetwork& network : networks) {
    auto setup = std::make_unique<MapSetup>();
    setup->network = std::move(network);
    setup->pm = simplify_constrained(setup->network, domain.mesh());
    setup->map = std::make_unique<SurfaceMap>(domain, setup->pm, options);
    if (networks.size() == 1) return setup;
    refine(*setup->map, coarse);
    const double energy = setup->map->energy();
    if (!best || energy < best_energy) {
      best = std::move(setup);
      best_energy = energy;
    }
  }
  return best;
}

}  // namespace ism
