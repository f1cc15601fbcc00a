#pragma once
// Reports: the JSON value and the sections every tool shares.
#include "mesh/mesh_check.hpp"
#include "report/json.hpp"

namespace ism {

/// The check of an input mesh: sizes, topology, defects, repairs.
Json to_json(const MeshCheck& check);

}  // namespace ism
