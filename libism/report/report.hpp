#pragma once
// Reports: the JSON value and the sections every tool shares.
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "report/json.hpp"

namespace ism {

/// The check of an input mesh: sizes, topology, defects, repairs.
Json to_json(const MeshCheck& check);

/// The "partition" section: features, Steiner vertices, patches (face count
/// and Euler characteristic of each), total path length, base mesh V/E/F.
Json partition_report(const PathNetwork& network, const TriangleMesh& domain,
                      const ProgressiveMesh& pm);

}  // namespace ism
