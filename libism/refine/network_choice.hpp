#pragma once
// Choosing among path networks. Each valid network fixes a homotopy class of
// maps that vertex-by-vertex optimisation cannot leave, so the choice matters
// more than any later effort: each candidate is refined to a coarse level and
// the one with the lowest symmetric energy there is kept. The candidates
// race there: all are refined to a quarter of the coarse level (its last
// level sweep, where refinement goes on exactly as one call), and only the
// best few (the number kept + 3, or a third if more) go on.
#include "map/surface_map.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace ism {

/// Scores a candidate's coarse map; the higher the better.
using CoarseScore = std::function<double(const SurfaceMap&)>;

/// A path network with its constrained progressive mesh: the part of a
/// candidate map that does not depend on MapOptions (immutable once built).
struct ConstrainedNetwork {
  PathNetwork network;
  ProgressiveMesh pm;
};

/// A map together with what it refers to (SurfaceMap keeps references).
struct MapSetup {
  std::unique_ptr<const DomainGeometry> owned_domain;  // null when the domain is shared
  /// Shared with every other map built on the same network (NetworkCandidates).
  std::shared_ptr<const ConstrainedNetwork> constrained;
  std::unique_ptr<SurfaceMap> map;
  std::size_t candidate = 0;  // index of the chosen candidate

  const PathNetwork& network() const { return constrained->network; }
  const ProgressiveMesh& pm() const { return constrained->pm; }
};

/// Candidate networks over one domain whose progressive meshes are built on
/// first demand and shared by every ranking of them, e.g. the map variants
/// of a front end, which rank the same networks with different MapOptions
/// (gim-remesh bunny: 24 simplifications of the surface became 12).
/// Thread-safe: rankings may run concurrently, and one that asks for a mesh
/// being built waits for it. An entry is let go once `users` rankings have
/// taken it (the maps built on it keep it alive), and built again if asked
/// for after that. `domain` must outlive this object and the maps.
class NetworkCandidates {
 public:
  NetworkCandidates(std::vector<PathNetwork> networks, const DomainGeometry& domain,
                    std::size_t users = 1);
  std::size_t size() const { return networks_.size(); }
  const DomainGeometry& domain() const { return domain_; }
  /// Network i with its progressive mesh; throws the simplification's
  /// std::runtime_error (every time it is asked for) where it fails.
  std::shared_ptr<const ConstrainedNetwork> take(std::size_t i);
  /// Where the next ranking starts: rankings k = 0, 1, ... start at network
  /// (k mod users) × size / users, so concurrent rankings build different
  /// meshes instead of one waiting for the other's (the order does not
  /// change a ranking's result).
  std::size_t next_start();

 private:
  struct Entry {
    std::mutex mutex;
    std::shared_ptr<const ConstrainedNetwork> built;
    std::exception_ptr error;
    std::size_t taken = 0;
  };
  std::vector<PathNetwork> networks_;
  const DomainGeometry& domain_;
  std::size_t users_;
  std::atomic<std::size_t> rankings_{0};
  std::vector<std::unique_ptr<Entry>> entries_;
};

/// A domain of its own (e.g. one of several base meshes) with a path network
/// of the surface that has the domain's connectivity.
struct DomainCandidate {
  std::unique_ptr<const DomainGeometry> domain;
  PathNetwork network;
};

/// Builds a map per network (progressive mesh, trivial map), refines each to
/// `coarse_vertices` and returns the lowest-energy one, refined to that
/// level only (refine() it again to finish). A candidate whose map throws
/// std::runtime_error drops out; if all do, the first error is rethrown.
/// `domain` must outlive the result. The coarse refinement runs with
/// `refine_options` (its stop and progress replaced), e.g. to compare the
/// candidates after the global flat-torus re-embeddings the final
/// refinement will make too.
std::unique_ptr<MapSetup> choose_network(std::vector<PathNetwork> networks,
                                         const DomainGeometry& domain, const MapOptions& options,
                                         std::size_t coarse_vertices = 1000,
                                         const RefineOptions& refine_options = {});

/// choose_network() keeping the best `count` candidates (fewer when fewer
/// map), best first, to be refined and compared at full resolution; ranked
/// by `score` (highest first) when given, else by the lowest symmetric
/// energy.
std::vector<std::unique_ptr<MapSetup>> rank_networks(
    std::vector<PathNetwork> networks, const DomainGeometry& domain, const MapOptions& options,
    std::size_t coarse_vertices = 1000, const RefineOptions& refine_options = {},
    std::size_t count = 1, const CoarseScore& score = {});

/// The same over shared candidates (their domain), their progressive meshes
/// built once for every ranking.
std::vector<std::unique_ptr<MapSetup>> rank_networks(
    NetworkCandidates& candidates, const MapOptions& options, std::size_t coarse_vertices = 1000,
    const RefineOptions& refine_options = {}, std::size_t count = 1, const CoarseScore& score = {});

/// The same choice among candidates that differ in their domain as well;
/// the result owns its domain.
std::unique_ptr<MapSetup> choose_domain(std::vector<DomainCandidate> candidates,
                                        const MapOptions& options,
                                        std::size_t coarse_vertices = 1000);

/// choose_domain() keeping the best `count` candidates (fewer when fewer
/// map), best first, to be refined and compared at full resolution; with
/// `score` they are ranked by it (highest first) instead of by the lowest
/// energy, e.g. by the measure the front end keeps its final map by.
std::vector<std::unique_ptr<MapSetup>> rank_domains(std::vector<DomainCandidate> candidates,
                                                    const MapOptions& options,
                                                    std::size_t coarse_vertices = 1000,
                                                    const CoarseScore& score = {},
                                                    std::size_t count = 1);

}  // namespace ism
