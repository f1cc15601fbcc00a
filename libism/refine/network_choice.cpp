#include "refine/network_choice.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>

namespace ism {
namespace {

// How many candidates go on from the race's first stage to the coarse
// level. On every model measured (bunny, bunny_small, spot, dragon, sphere,
// cube, a generated blob, teapot with automatic features; gim-remesh's and
// torus-remesh's two variants each), the best map at the coarse level was
// among the best three at the first stage (docs/results-speed.md).
std::size_t race_survivors(std::size_t count, std::size_t keep) {
  return std::max(keep + 3, (count + 2) / 3);
}

// Builds every candidate's map, refines it to `coarse_vertices` and keeps the
// best `keep` by score (default: the lowest symmetric energy), best first
// (the first of equals first); a single candidate is returned unrefined. A
// candidate whose map fails (a split the map core cannot place) drops out;
// when all fail, the first failure is rethrown.
//
// A race: every candidate is first refined to its last level sweep at or
// below a quarter of `coarse_vertices`, and only the best race_survivors()
// there go on to `coarse_vertices`. Stopping at a level sweep and going on
// refines exactly as one refinement would (last_level_sweep_at_most), so
// the result is the full ranking's whenever its winners survive the first
// stage. Candidates are independent, so they run in parallel, as many at a
// time as there are cores (each holds a copy of the surface), taken from
// candidate `start` on (wrapping round; the result does not depend on it).
template <class MakeSetup>
std::vector<std::unique_ptr<MapSetup>> choose(std::size_t count, const MakeSetup& make_setup,
                                              std::size_t coarse_vertices,
                                              const RefineOptions& refine_options,
                                              const CoarseScore& score = {}, std::size_t keep = 1,
                                              std::size_t start = 0) {
  std::vector<std::unique_ptr<MapSetup>> out;
  if (count == 1) {
    out.push_back(make_setup(0));
    return out;
  }
  RefineOptions coarse = refine_options;
  coarse.progress = nullptr;
  std::exception_ptr first_failure;
  // Refines n candidates, candidate i given by take(i), each to stop(map),
  // and returns the best `kept` by score, best first, the first candidate of
  // equals first. Side by side without a barrier: a map is scored as soon as
  // it is refined and let go unless it is among the best so far, so no more
  // maps are held than threads run and kept; the result does not depend on
  // the order they finish in.
  // Failures are kept by candidate (take(i) makes candidate i + `rotation`
  // mod n), so the first one rethrown does not depend on the start.
  auto stage = [&](std::size_t n, const auto& take, const auto& stop, std::size_t kept,
                   std::size_t rotation) {
    std::vector<std::pair<double, std::unique_ptr<MapSetup>>> best;
    std::mutex best_mutex;
    std::vector<std::exception_ptr> failures(n);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            std::unique_ptr<MapSetup> setup;
            try {
              setup = take(i);
              RefineOptions options = coarse;
              options.stop_at_vertices = stop(*setup->map);
              refine(*setup->map, options);
            } catch (const std::runtime_error&) {
              failures[(i + rotation) % n] = std::current_exception();
              continue;
            }
            const double value = score ? score(*setup->map) : -setup->map->energy();
            auto ahead = [&](const auto& entry) {
              return value > entry.first ||
                     (value == entry.first && setup->candidate < entry.second->candidate);
            };
            std::lock_guard lock(best_mutex);
            best.emplace(std::find_if(best.begin(), best.end(), ahead), value, std::move(setup));
            if (best.size() > kept) best.pop_back();
          }
        },
        tbb::simple_partitioner());
    for (const std::exception_ptr& failure : failures)
      if (failure && !first_failure) first_failure = failure;
    return best;
  };
  auto make = [&](std::size_t j) {
    const std::size_t i = (j + start) % count;
    std::unique_ptr<MapSetup> setup = make_setup(i);
    setup->candidate = i;
    return setup;
  };
  auto to_coarse = [&](const SurfaceMap&) { return coarse_vertices; };
  std::vector<std::pair<double, std::unique_ptr<MapSetup>>> best;
  const std::size_t survivors = race_survivors(count, keep);
  if (survivors < count) {
    auto first_stage = stage(
        count, make,
        [&](const SurfaceMap& map) {
          // At least one level sweep, or the first stage would rank trivial
          // maps; a candidate with no level sweep before the coarse level
          // (a base of more than 2/3 of it) is refined to it at once.
          const std::size_t first_sweep =
              std::size_t(std::ceil(coarse.sweep_growth * double(map.n_vertices())));
          const std::size_t stop = last_level_sweep_at_most(
              coarse, map.n_vertices(),
              std::min(coarse_vertices, std::max(coarse_vertices / 4, first_sweep)));
          return stop > map.n_vertices() ? stop : coarse_vertices;
        },
        survivors, start);
    best = stage(
        first_stage.size(), [&](std::size_t i) { return std::move(first_stage[i].second); },
        to_coarse, keep, 0);
  } else {
    best = stage(count, make, to_coarse, keep, start);
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

std::size_t NetworkCandidates::next_start() {
  return (rankings_++ % users_) * networks_.size() / users_;
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
      coarse_vertices, refine_options, score, count, candidates.next_start());
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
