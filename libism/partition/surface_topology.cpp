// Boundary loops and genus of a surface given as a plain triangle mesh.
#include "mesh/boundary.hpp"
#include "partition/compatible_detail.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <algorithm>
#include <set>
#include <unordered_map>

namespace ism::partition_detail {

std::vector<std::vector<int>> boundary_loops(const TriangleMesh& surface) {
  try {
    return ism::boundary_loops(surface);
  } catch (const std::invalid_argument& e) {
    throw PartitionError(e.what());
  }
}

int genus_of(const TriangleMesh& surface, std::size_t loops) {
  const long chi = euler_characteristic(surface);
  return int((2 - long(loops) - chi) / 2);
}

}  // namespace ism::partition_detail
