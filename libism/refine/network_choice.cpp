#include "refine/network_choice.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <thread>

namespace ism {
namespace {

// Builds every candidate's map, refines it to `coarse_vertices` and keeps the
// best `count` by score (default: the lowest symmetric energy), best first
// (the first of equals first); a single candidate is
// returned unrefined. A candidate whose map fails (a split the map core
// cannot place) drops out; when all fail, the first failure is rethrown.
// Candidates are independent, so they run in parallel, as many at a time as
// there are cores (each holds a copy of the surface).
template <class MakeSetup>
std::vector<std::unique_ptr<MapSetup>> choose(std::size_t count, const MakeSetup& make_setup,
                                              std::size_t coarse_vertices,
                                              const RefineOptions& refine_options,
                                              const CoarseScore& score = {}, std::size_t keep = 1) {
  std::vector<std::unique_ptr<MapSetup>> out;
  if (count == 1) {
    out.push_back(make_setup(0));
    return out;
  }
  RefineOptions coarse = refine_options;
  coarse.stop_at_vertices = coarse_vertices;
  coarse.progress = nullptr;
  const std::size_t batch = std::max(1u, std::thread::hardware_concurrency());
  // The best `keep` so far, best first (the first of equals first).
  std::vector<std::pair<double, std::unique_ptr<MapSetup>>> best;
  std::exception_ptr first_failure;
  for (std::size_t first = 0; first < count; first += batch) {
    const std::size_t last = std::min(count, first + batch);
    std::vector<std::unique_ptr<MapSetup>> setups(last - first);
    std::vector<std::exception_ptr> failures(last - first);
    tbb::parallel_for(first, last, [&](std::size_t i) {
      try {
        std::unique_ptr<MapSetup> setup = make_setup(i);
        setup->candidate = i;
        refine(*setup->map, coarse);
        setups[i - first] = std::move(setup);
      } catch (const std::runtime_error&) {
        failures[i - first] = std::current_exception();
      }
    });
    for (std::size_t k = 0; k < setups.size(); ++k) {
      if (!setups[k]) {
        if (!first_failure) first_failure = failures[k];
        continue;
      }
      const double value = score ? score(*setups[k]->map) : -setups[k]->map->energy();
      auto at = std::find_if(best.begin(), best.end(),
                             [&](const auto& entry) { return value > entry.first; });
      best.emplace(at, value, std::move(setups[k]));
      if (best.size() > keep) best.pop_back();
    }
  }
  if (best.empty()) std::rethrow_exception(first_failure);
  for (auto& entry : best) out.push_back(std::move(entry.second));
  return out;
}

}  // namespace

NetworkCandidates::NetworkCandidates(std::vector<PathNetwork> networks,
                                     const DomainGeometry& domain, std::size_t users)
    : networks_(std::move(networks)), domain_(domain), users_(std::max<std::size_t>(users, 1)) {
  for (std::size_t i = 0; i < networks_.size(); ++i) entries_.push_back(std::make_unique<Entry>());
}

std::shared_ptr<const ConstrainedNetwork> NetworkCandidates::take(std::size_t i) {
  Entry& entry = *entries_.at(i);
  std::lock_guard lock(entry.mutex);
  std::shared_ptr<const ConstrainedNetwork> out = entry.built;
  if (!out && !entry.error) {
    try {
      auto built = std::make_shared<ConstrainedNetwork>();
      built->network = networks_[i];
      built->pm = simplify_constrained(built->network, domain_.mesh());
      out = std::move(built);
    } catch (const std::runtime_error&) {
      entry.error = std::current_exception();
    }
  }
  if (++entry.taken % users_ == 0) {
    entry.built.reset();  // every ranking has it
  } else {
    entry.built = out;
  }
  if (entry.error) std::rethrow_exception(entry.error);
  return out;
}

std::vector<std::unique_ptr<MapSetup>> rank_networks(NetworkCandidates& candidates,
                                                     const MapOptions& options,
                                                     std::size_t coarse_vertices,
                                                     const RefineOptions& refine_options,
                                                     std::size_t count, const CoarseScore& score) {
  if (candidates.size() == 0) throw std::invalid_argument("rank_networks: no network");
  return choose(
      candidates.size(),
      [&](std::size_t i) {
        auto setup = std::make_unique<MapSetup>();
        setup->constrained = candidates.take(i);
        setup->map = std::make_unique<SurfaceMap>(candidates.domain(), setup->pm(), options);
        return setup;
      },
      coarse_vertices, refine_options, score, count);
}

std::vector<std::unique_ptr<MapSetup>> rank_networks(std::vector<PathNetwork> networks,
                                                     const DomainGeometry& domain,
                                                     const MapOptions& options,
                                                     std::size_t coarse_vertices,
                                                     const RefineOptions& refine_options,
                                                     std::size_t count, const CoarseScore& score) {
  NetworkCandidates candidates(std::move(networks), domain);
  return rank_networks(candidates, options, coarse_vertices, refine_options, count, score);
}

std::unique_ptr<MapSetup> choose_network(std::vector<PathNetwork> networks,
                                         const DomainGeometry& domain, const MapOptions& options,
                                         std::size_t coarse_vertices,
                                         const RefineOptions& refine_options) {
  return std::move(
      rank_networks(std::move(networks), domain, options, coarse_vertices, refine_options, 1)
          .front());
}

std::vector<std::unique_ptr<MapSetup>> rank_domains(std::vector<DomainCandidate> candidates,
                                                    const MapOptions& options,
                                                    std::size_t coarse_vertices,
                                                    const CoarseScore& score, std::size_t count) {
  if (candidates.empty()) throw std::invalid_argument("rank_domains: no candidate");
  return choose(
      candidates.size(),
      [&](std::size_t i) {
        auto setup = std::make_unique<MapSetup>();
        setup->owned_domain = std::move(candidates[i].domain);
        auto built = std::make_shared<ConstrainedNetwork>();
        built->network = std::move(candidates[i].network);
        built->pm = simplify_constrained(built->network, setup->owned_domain->mesh());
        setup->constrained = std::move(built);
        setup->map = std::make_unique<SurfaceMap>(*setup->owned_domain, setup->pm(), options);
        return setup;
      },
      coarse_vertices, RefineOptions{}, score, std::max<std::size_t>(count, 1));
}

std::unique_ptr<MapSetup> choose_domain(std::vector<DomainCandidate> candidates,
                                        const MapOptions& options, std::size_t coarse_vertices) {
  if (candidates.empty()) throw std::invalid_argument("choose_domain: no candidate");
  return std::move(rank_domains(std::move(candidates), options, coarse_vertices).front());
}

}  // namespace ism
