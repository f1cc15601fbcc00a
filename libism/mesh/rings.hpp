#pragma once
// Rings of vertices around a vertex, for any mesh that lists a vertex's
// neighbours (SurfaceMap's and InterSurfaceMap's discs).
#include <cstddef>
#include <unordered_set>
#include <vector>

namespace ism {

/// v and the vertices within `rings` edges of it, nearest first (each ring
/// in the order `neighbours(u)` lists them, u in the order found); none as
/// soon as `accept(u)` is false for one of them.
template <class Neighbours, class Accept>
std::vector<int> rings_around(int v, int rings, Neighbours&& neighbours, Accept&& accept) {
  if (!accept(v)) return {};
  std::vector<int> region{v};
  std::unordered_set<int> seen{v};
  for (std::size_t begin = 0, r = 0; r < std::size_t(rings); ++r) {
    const std::size_t end = region.size();
    for (std::size_t i = begin; i < end; ++i)
      for (int u : neighbours(region[i]))
        if (seen.insert(u).second) {
          if (!accept(u)) return {};
          region.push_back(u);
        }
    begin = end;
  }
  return region;
}

/// Every vertex accepted.
template <class Neighbours>
std::vector<int> rings_around(int v, int rings, Neighbours&& neighbours) {
  return rings_around(v, rings, neighbours, [](int) { return true; });
}

}  // namespace ism
