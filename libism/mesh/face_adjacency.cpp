#include "mesh/face_adjacency.hpp"
#include "mesh/edge_key.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace ism {

std::vector<std::array<FaceAcross, 3>> faces_across(const std::vector<Triangle>& triangles) {
  // Every directed edge a -> b with its face and corner a, sorted by edge
  // (stably: of repeated edges the last in the list is found last).
  std::vector<std::pair<std::uint64_t, FaceAcross>> starting;
  starting.reserve(3 * triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      starting.push_back(
          {directed_edge_key(triangles[f][k], triangles[f][(k + 1) % 3]), FaceAcross{int(f), k}});
  std::stable_sort(starting.begin(), starting.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::array<FaceAcross, 3>> out(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t twin = directed_edge_key(triangles[f][(k + 1) % 3], triangles[f][k]);
      const auto end =
          std::upper_bound(starting.begin(), starting.end(), twin,
                           [](std::uint64_t key, const auto& e) { return key < e.first; });
      if (end != starting.begin() && std::prev(end)->first == twin)
        out[f][std::size_t(k)] = std::prev(end)->second;
    }
  return out;
}

}  // namespace ism
