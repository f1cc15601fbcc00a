#pragma once
// An octahedral map of a genus-0 surface at its base level: the automatic
// network, its constrained progressive mesh and the trivial map (the
// octahedral counterpart of torus_map_fixture.hpp).
#include "domain/domain.hpp"
#include "map/map.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"

namespace ism::test {

struct OctahedralMap {
  TriangleMesh octahedron = domain::octahedron();
  DomainGeometry geometry;
  PathNetwork network;
  ProgressiveMesh pm;
  SurfaceMap map;
  explicit OctahedralMap(const TriangleMesh& surface,
                         DomainMetric metric = DomainMetric::right_isosceles,
                         MapOptions options = {})
      : geometry(octahedron, octahedron_lengths(octahedron, metric)),
        network(trace_octahedral_network(surface)),
        pm(simplify_constrained(network, octahedron)),
        map(geometry, pm, options) {}
};

}  // namespace ism::test
