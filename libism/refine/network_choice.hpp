#pragma once
// Choosing among path networks. Each valid network fixes a homotopy class of
// maps that vertex-by-vertex optimisation cannot leave, so the choice matters
// more than any later effort: each candidate is refined to a coarse level and
// the one with the lowest symmetric energy there is kept.
#include "map/surface_map.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"

#include <memory>
#include <vector>

namespace ism {

/// A map together with what it refers to (SurfaceMap keeps references).
struct MapSetup {
  PathNetwork network;
  ProgressiveMesh pm;
  std::unique_ptr<SurfaceMap> map;
};

/// Builds a map per network (progressive mesh, trivial map), refines each to
/// `coarse_vertices` and returns the lowest-energy one, refined to that
/// level only (refine() it again to finish). `domain` must outlive the result.
std::unique_ptr<MapSetup> choose_network(std::vector<PathNetwork> networks,
                                         const DomainGeometry& domain, const MapOptions& options,
                                         std::size_t coarse_vertices = 1000);

}  // namespace ism
