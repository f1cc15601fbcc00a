#pragma once
// Internal to partition: faces of a surface grouped into the regions that a
// set of cut edges separates, and the directed-edge lookup both the tracer
// and the validator use.
#include "mesh/triangle_mesh.hpp"

#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace ism::partition_detail {

inline std::uint64_t directed_key(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}
inline std::uint64_t undirected_key(int a, int b) {
  return a < b ? directed_key(a, b) : directed_key(b, a);
}

/// Face that holds the directed edge a->b (ccw), for every directed edge.
std::unordered_map<std::uint64_t, int> directed_edge_faces(const TriangleMesh& mesh);

/// Region id of each face: faces joined across edges not in `cuts`
/// (undirected keys). Regions are numbered in order of their lowest face.
std::vector<int> regions(const TriangleMesh& mesh, const std::unordered_set<std::uint64_t>& cuts,
                         int* region_count);

}  // namespace ism::partition_detail
