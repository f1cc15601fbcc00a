// Boundary loops and genus of a surface given as a plain triangle mesh.
#include "partition/compatible_detail.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <algorithm>
#include <set>
#include <unordered_map>

namespace ism::partition_detail {

std::vector<std::vector<int>> boundary_loops(const TriangleMesh& surface) {
  std::unordered_map<std::uint64_t, int> directed;
  for (std::size_t f = 0; f < surface.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      directed[directed_key(surface.triangles[f][k], surface.triangles[f][(k + 1) % 3])] = int(f);
  // Boundary half-edges a -> b: the face holds b -> a, nothing holds a -> b.
  std::unordered_map<int, int> next;
  for (const Triangle& t : surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[(k + 1) % 3], b = t[k];
      if (directed.count(directed_key(a, b))) continue;
      if (!next.emplace(a, b).second)
        throw PartitionError("vertex " + std::to_string(a) +
                             " is on the boundary twice (the boundary is not a set of loops)");
    }
  std::vector<int> starts;
  for (const auto& [a, b] : next) starts.push_back(a);
  std::sort(starts.begin(), starts.end());
  std::set<int> done;
  std::vector<std::vector<int>> loops;
  for (int start : starts) {
    if (done.count(start)) continue;
    std::vector<int> loop;
    int v = start;
    do {
      loop.push_back(v);
      done.insert(v);
      auto it = next.find(v);
      if (it == next.end() || loop.size() > next.size())
        throw PartitionError("the boundary through vertex " + std::to_string(start) +
                             " does not close into a loop");
      v = it->second;
    } while (v != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

int genus_of(const TriangleMesh& surface, std::size_t loops) {
  const long chi = euler_characteristic(surface);
  return int((2 - long(loops) - chi) / 2);
}

}  // namespace ism::partition_detail
