// Choosing among candidate maps: the lowest coarse energy wins, whether the
// candidates share a domain (octahedral networks) or bring their own (bases).
#include "refine/network_choice.hpp"
#include "domain/domain.hpp"
#include "domain_candidates.hpp"
#include "map/map.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <numeric>

namespace ism {
namespace {

constexpr std::size_t coarse_vertices = 300;

// The energy a candidate reaches on its own at the coarse level.
double coarse_energy(const DomainGeometry& domain, const PathNetwork& network,
                     std::size_t coarse = coarse_vertices) {
  const ProgressiveMesh pm = simplify_constrained(network, domain.mesh());
  SurfaceMap map(domain, pm);
  RefineOptions options;
  options.stop_at_vertices = coarse;
  refine(map, options);
  return map.energy();
}

// gim-remesh's candidates on the right-isosceles octahedron: every
// antipodal pair of features tried as the poles (more networks than the race
// lets through).
struct PoleNetworks {
  TriangleMesh octahedron = domain::octahedron();
  DomainGeometry domain{octahedron, octahedron_lengths(octahedron, DomainMetric::right_isosceles)};
  std::vector<PathNetwork> networks;
  explicit PoleNetworks(const TriangleMesh& surface) {
    PartitionOptions every_pole_pair;
    every_pole_pair.distinguish_poles = true;
    networks = trace_octahedral_networks(surface, every_pole_pair);
  }
};

TEST(NetworkChoice, KeepsTheLowestCoarseEnergyAmongNetworks) {
  const TriangleMesh surface = shapes::blob(2000, 4, 0.4);
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry domain(octahedron,
                              octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  const std::vector<PathNetwork> networks = trace_octahedral_networks(surface);
  ASSERT_GE(networks.size(), 2u);
  std::vector<double> energies;
  for (const PathNetwork& n : networks) energies.push_back(coarse_energy(domain, n));
  const std::size_t best =
      std::size_t(std::min_element(energies.begin(), energies.end()) - energies.begin());

  const auto chosen = choose_network(networks, domain, {}, coarse_vertices);
  EXPECT_EQ(chosen->candidate, best);
  EXPECT_EQ(chosen->owned_domain, nullptr);
  EXPECT_DOUBLE_EQ(chosen->map->energy(), energies[best]);
  EXPECT_EQ(chosen->map->validate(), std::nullopt);
}

// The candidates race: all to a quarter of the coarse level, the best few
// on. The two kept are still the full ranking's best two, their maps as if
// refined to the coarse level in one call.
TEST(NetworkChoice, TheRaceKeepsTheFullRankingsBest) {
  constexpr std::size_t coarse_vertices = 1000;
  const PoleNetworks candidates(shapes::blob(5000, 4, 0.4));
  const DomainGeometry& domain = candidates.domain;
  const std::vector<PathNetwork>& networks = candidates.networks;
  ASSERT_GT(networks.size(), 5u);  // more than the race lets through for two kept
  std::vector<std::size_t> order(networks.size());
  std::vector<double> energies;
  for (const PathNetwork& n : networks)
    energies.push_back(coarse_energy(domain, n, coarse_vertices));
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return energies[a] < energies[b]; });

  const auto ranked = rank_networks(networks, domain, {}, coarse_vertices, {}, 2);
  ASSERT_EQ(ranked.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(ranked[k]->candidate, order[k]);
    EXPECT_EQ(ranked[k]->map->energy(), energies[order[k]]);
    EXPECT_EQ(ranked[k]->map->n_vertices(), coarse_vertices);
  }
}

// A coarse level too close to the base for a level sweep before it: the
// race has no first stage to judge by, and every candidate is refined to the
// coarse level at once (not ranked as its trivial map).
TEST(NetworkChoice, TheRaceWithoutALevelSweepBeforeTheCoarseLevel) {
  const PoleNetworks candidates(shapes::blob(2000, 4, 0.4));
  const DomainGeometry& domain = candidates.domain;
  const std::vector<PathNetwork>& networks = candidates.networks;
  const TriangleMesh& octahedron = candidates.octahedron;
  ASSERT_GT(networks.size(), 4u);
  constexpr std::size_t coarse = 8;  // the octahedron's 6, the first level sweep at 9
  ASSERT_EQ(last_level_sweep_at_most({}, octahedron.n_vertices(), coarse), octahedron.n_vertices());
  std::vector<double> energies;
  for (const PathNetwork& n : networks) energies.push_back(coarse_energy(domain, n, coarse));
  const std::size_t best =
      std::size_t(std::min_element(energies.begin(), energies.end()) - energies.begin());
  // Every map ranked, in either stage, has the coarse level's vertices.
  std::mutex scored_mutex;
  std::vector<std::size_t> scored_sizes;
  const CoarseScore lowest_energy = [&](const SurfaceMap& m) {
    std::lock_guard lock(scored_mutex);
    scored_sizes.push_back(m.n_vertices());
    return -m.energy();
  };
  const auto ranked = rank_networks(networks, domain, {}, coarse, {}, 1, lowest_energy);
  ASSERT_EQ(ranked.size(), 1u);
  EXPECT_EQ(ranked[0]->candidate, best);
  EXPECT_EQ(ranked[0]->map->n_vertices(), coarse);
  EXPECT_EQ(ranked[0]->map->energy(), energies[best]);
  EXPECT_GT(scored_sizes.size(), networks.size());  // both stages ran
  for (std::size_t n : scored_sizes) EXPECT_EQ(n, coarse);
}

TEST(NetworkChoice, VariantsShareEachNetworksProgressiveMesh) {
  // Two rankings with different options (as two map variants) over one set
  // of candidates, concurrently: each network's progressive mesh is built
  // once and the maps built on it share it; each ranking chooses as it
  // would alone; a network whose simplification fails drops out of both.
  const TriangleMesh surface = shapes::blob(2000, 4, 0.4);
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry domain(octahedron,
                              octahedron_lengths(octahedron, DomainMetric::right_isosceles));
  std::vector<PathNetwork> networks = trace_octahedral_networks(surface);
  ASSERT_GE(networks.size(), 3u);
  // The first candidate's paths run along two of its faces' patches: not a
  // network its simplification accepts.
  networks.front().face_patch.assign(networks.front().face_patch.size(), 0);
  const std::size_t n = networks.size();
  const std::array<MapOptions, 2> variants{MapOptions{}, MapOptions{.inverse_stretch_weight = 0.1}};
  std::array<std::vector<std::unique_ptr<MapSetup>>, 2> alone, together;
  for (int v = 0; v < 2; ++v)
    alone[v] = rank_networks(networks, domain, variants[v], coarse_vertices, {}, n);
  NetworkCandidates shared(networks, domain, 2);
  tbb::parallel_for(0, 2, [&](int v) {
    together[v] = rank_networks(shared, variants[v], coarse_vertices, {}, n);
  });
  for (int v = 0; v < 2; ++v) {
    ASSERT_EQ(together[v].size(), n - 1);
    ASSERT_EQ(alone[v].size(), n - 1);
    for (std::size_t k = 0; k < n - 1; ++k) {
      EXPECT_NE(together[v][k]->candidate, 0u);
      EXPECT_EQ(together[v][k]->candidate, alone[v][k]->candidate);
      EXPECT_EQ(together[v][k]->map->energy(), alone[v][k]->map->energy());
    }
  }
  for (const auto& a : together[0])
    for (const auto& b : together[1])
      if (a->candidate == b->candidate) EXPECT_EQ(a->constrained.get(), b->constrained.get());
}

TEST(NetworkChoice, CandidatesWithTheirOwnDomains) {
  const TriangleMesh surface = shapes::blob(3000, 5, 0.4);
  std::vector<DomainCandidate> candidates;
  std::vector<double> energies;
  for (SimplifyPriority priority : {SimplifyPriority::quadric, SimplifyPriority::isotropic}) {
    const ProgressiveMesh decimated = simplify_to(surface, 30, {.priority = priority});
    const TriangleMesh base = base_mesh(decimated);
    auto domain = std::make_unique<DomainGeometry>(base, equilateral_lengths(base));
    PathNetwork network = trace_path_network(surface, base, decimated.base_vertices);
    energies.push_back(coarse_energy(*domain, network));
    candidates.push_back({std::move(domain), std::move(network)});
  }
  const std::size_t best = energies[1] < energies[0] ? 1 : 0;
  const auto chosen = choose_domain(std::move(candidates), {}, coarse_vertices);
  EXPECT_EQ(chosen->candidate, best);
  ASSERT_NE(chosen->owned_domain, nullptr);
  EXPECT_EQ(&chosen->map->domain(), chosen->owned_domain.get());
  EXPECT_DOUBLE_EQ(chosen->map->energy(), energies[best]);
  EXPECT_EQ(chosen->map->validate(), std::nullopt);
  // The chosen map goes on to full resolution.
  refine(*chosen->map);
  EXPECT_EQ(chosen->map->validate(), std::nullopt);
  EXPECT_EQ(chosen->map->n_vertices(), chosen->network().surface.n_vertices());
}

// A front end's score ranks the candidates instead, and several can be
// kept, best first (fewer when fewer there are).
TEST(NetworkChoice, RanksCandidatesByAScore) {
  const TriangleMesh surface = shapes::blob(3000, 5, 0.4);
  std::vector<DomainCandidate> candidates = test::decimated_candidates(surface, 30);
  const CoarseScore one_way = [](const SurfaceMap& m) { return m.measures().forward_efficiency; };
  const auto ranked = rank_domains(std::move(candidates), {}, coarse_vertices, one_way, 5);
  ASSERT_EQ(ranked.size(), 2u);
  EXPECT_NE(ranked[0]->candidate, ranked[1]->candidate);
  EXPECT_GT(one_way(*ranked[0]->map), one_way(*ranked[1]->map));
  for (const auto& setup : ranked) {
    EXPECT_EQ(setup->map->validate(), std::nullopt);
    EXPECT_EQ(&setup->map->domain(), setup->owned_domain.get());
    EXPECT_EQ(setup->map->n_vertices(), coarse_vertices);
  }
}

TEST(NetworkChoice, RefusesAnEmptyChoice) {
  EXPECT_THROW(choose_domain({}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ism
