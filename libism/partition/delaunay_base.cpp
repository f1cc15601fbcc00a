// Free connectivity (paper §4, for bases given by their vertices only): the
// sites' geodesic Voronoi regions on the surface, and their dual. Regions
// are grown by Dijkstra over the edges; a face whose three corners belong
// to three regions is a corner of the diagram and gives one dual triangle,
// oriented like the face. With well-spread sites every region is a disc and
// the dual is a closed manifold of the surface's genus; anything else is
// refused, since a path network needs exactly that.
#include "partition/partition.hpp"

#include <algorithm>
#include <map>
#include <queue>
#include <set>

namespace ism {

TriangleMesh delaunay_base(const TriangleMesh& surface, const std::vector<int>& sites) {
  const std::size_t nv = surface.n_vertices();
  std::vector<int> region(nv, -1);
  std::vector<double> distance(nv, INFINITY);
  std::vector<std::vector<int>> neighbours(nv);
  for (const Triangle& t : surface.triangles)
    for (int k = 0; k < 3; ++k) neighbours[t[k]].push_back(t[(k + 1) % 3]);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  for (std::size_t i = 0; i < sites.size(); ++i) {
    const int s = sites[i];
    if (s < 0 || std::size_t(s) >= nv)
      throw PartitionError("base vertex " + std::to_string(i) + ": surface vertex " +
                           std::to_string(s) + " out of range");
    if (region[s] >= 0)
      throw PartitionError("base vertices " + std::to_string(region[s]) + " and " +
                           std::to_string(i) + " are the same surface vertex " + std::to_string(s));
    region[s] = int(i);
    distance[s] = 0;
    open.push({0.0, s});
  }
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > distance[v]) continue;
    for (int w : neighbours[v]) {
      const double dw = d + (surface.positions[w] - surface.positions[v]).norm();
      if (dw < distance[w]) {
        distance[w] = dw;
        region[w] = region[v];
        open.push({dw, w});
      }
    }
  }

  TriangleMesh base;
  for (int s : sites) base.positions.push_back(surface.positions[s]);
  std::set<Triangle> seen;  // rotated so that the smallest index comes first
  for (const Triangle& t : surface.triangles) {
    Triangle d = {region[t[0]], region[t[1]], region[t[2]]};
    if (d[0] < 0 || d[0] == d[1] || d[1] == d[2] || d[2] == d[0]) continue;
    std::rotate(d.begin(), std::min_element(d.begin(), d.end()), d.end());
    if (seen.insert(d).second) base.triangles.push_back(d);
  }

  // Closed manifold: every directed edge once, with its opposite; every
  // site in one fan; Euler characteristic of the surface.
  auto refuse = [&](const std::string& why) {
    throw PartitionError("no triangulation of the " + std::to_string(sites.size()) +
                         " base vertices from their Voronoi regions (" + why +
                         "); give the base's faces or spread the vertices more evenly");
  };
  std::map<std::pair<int, int>, int> directed;
  for (const Triangle& t : base.triangles)
    for (int k = 0; k < 3; ++k)
      if (++directed[{t[k], t[(k + 1) % 3]}] > 1)
        refuse("regions " + std::to_string(t[k]) + " and " + std::to_string(t[(k + 1) % 3]) +
               " meet twice");
  for (const auto& [edge, count] : directed)
    if (!directed.count({edge.second, edge.first}))
      refuse("a diagram corner missing near regions " + std::to_string(edge.first) + " and " +
             std::to_string(edge.second));
  std::vector<std::map<int, int>> next(sites.size());  // fan successor around each site
  for (const Triangle& t : base.triangles)
    for (int k = 0; k < 3; ++k) next[t[k]][t[(k + 1) % 3]] = t[(k + 2) % 3];
  for (std::size_t i = 0; i < sites.size(); ++i) {
    if (next[i].empty()) refuse("region " + std::to_string(i) + " has no corner");
    std::size_t steps = 0;
    const int start = next[i].begin()->first;
    int a = start;
    do {
      a = next[i].at(a);
      ++steps;
    } while (a != start && steps <= next[i].size());
    if (steps != next[i].size()) refuse("region " + std::to_string(i) + " is not a disc");
  }
  if (euler_characteristic(base) != euler_characteristic(surface))
    refuse("the regions' dual has another genus than the surface");
  return base;
}

}  // namespace ism
