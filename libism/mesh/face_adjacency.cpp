#include "mesh/face_adjacency.hpp"
#include "mesh/edge_key.hpp"

#include <cstdint>
#include <unordered_map>

namespace ism {

std::vector<std::array<FaceAcross, 3>> faces_across(const std::vector<Triangle>& triangles) {
  std::unordered_map<std::uint64_t, FaceAcross> starting;  // directed edge a -> b: face, corner a
  starting.reserve(3 * triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      starting[directed_edge_key(triangles[f][k], triangles[f][(k + 1) % 3])] = {int(f), k};
  std::vector<std::array<FaceAcross, 3>> out(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto twin =
          starting.find(directed_edge_key(triangles[f][(k + 1) % 3], triangles[f][k]));
      if (twin != starting.end()) out[f][std::size_t(k)] = twin->second;
    }
  return out;
}

}  // namespace ism
