#include "mesh/union_find.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

namespace ism {

namespace partition_detail {

DirectedEdgeFaces::DirectedEdgeFaces(const TriangleMesh& mesh) : first_(mesh.n_vertices() + 1, 0) {
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++first_[std::size_t(t[k]) + 1];
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v) first_[v + 1] += first_[v];
  out_.resize(first_.back());
  std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Triangle& t = mesh.triangles[f];
      out_[next[std::size_t(t[k])]++] = {t[(k + 1) % 3], int(f)};
    }
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    std::sort(out_.begin() + std::ptrdiff_t(first_[v]),
              out_.begin() + std::ptrdiff_t(first_[v + 1]));
}

int DirectedEdgeFaces::operator()(int a, int b) const {
  if (a < 0 || std::size_t(a) + 1 >= first_.size()) return -1;
  int face = -1;
  for (std::size_t i = first_[std::size_t(a)]; i < first_[std::size_t(a) + 1]; ++i)
    if (out_[i].first == b) face = out_[i].second;  // (the last of equals)
  return face;
}

std::vector<int> regions(const TriangleMesh& mesh, const std::unordered_set<std::uint64_t>& cuts,
                         int* region_count) {
  // The cut edges flagged on the faces' sides once, then faces joined
  // across every other side.
  const DirectedEdgeFaces faces(mesh);
  std::vector<char> cut(3 * mesh.n_faces(), 0);
  auto flag = [&](int a, int b) {
    const int f = faces(a, b);
    if (f < 0) return;
    const Triangle& t = mesh.triangles[std::size_t(f)];
    for (int k = 0; k < 3; ++k)
      if (t[k] == a && t[(k + 1) % 3] == b) cut[3 * std::size_t(f) + std::size_t(k)] = 1;
  };
  for (const std::uint64_t key : cuts) {
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    flag(a, b), flag(b, a);
  }
  UnionFind sets(mesh.n_faces());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      if (a > b || cut[3 * f + std::size_t(k)]) continue;
      const int other = faces(b, a);
      if (other >= 0) sets.unite(f, std::size_t(other));
    }
  std::vector<int> region(mesh.n_faces(), -1);
  std::vector<int> id_of_root(mesh.n_faces(), -1);
  int count = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    int& id = id_of_root[sets.find(f)];
    if (id < 0) id = count++;
    region[f] = id;
  }
  if (region_count) *region_count = count;
  return region;
}

}  // namespace partition_detail

using namespace partition_detail;

double PathNetwork::total_length() const {
  double sum = 0.0;
  for (const auto& path : paths)
    for (std::size_t k = 1; k < path.size(); ++k)
      sum += (surface.positions[path[k]] - surface.positions[path[k - 1]]).norm();
  return sum;
}

std::optional<std::string> validate_network(const PathNetwork& network,
                                            const TriangleMesh& domain) {
  const TriangleMesh& surface = network.surface;
  if (network.features.size() != domain.n_vertices()) return "wrong number of features";
  if (network.face_patch.size() != surface.n_faces()) return "face_patch has the wrong size";

  // The domain face on the left of each directed domain edge; a boundary
  // edge of an open domain has a face on one side only.
  std::map<std::pair<int, int>, int> left_face;
  std::set<std::pair<int, int>> domain_edges;
  for (std::size_t f = 0; f < domain.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = domain.triangles[f][k], b = domain.triangles[f][(k + 1) % 3];
      left_face[{a, b}] = int(f);
      domain_edges.insert(std::minmax(a, b));
    }
  if (network.domain_edges.size() != domain_edges.size() ||
      network.paths.size() != network.domain_edges.size())
    return "wrong number of paths";

  const DirectedEdgeFaces faces(surface);
  std::unordered_set<std::uint64_t> cuts;
  std::vector<int> owner(surface.n_vertices(), -1);  // path of each interior path vertex
  std::set<int> feature_set(network.features.begin(), network.features.end());
  if (feature_set.size() != network.features.size()) return "two features on one vertex";
  for (std::size_t e = 0; e < network.paths.size(); ++e) {
    const auto& path = network.paths[e];
    const auto [a, b] = network.domain_edges[e];
    const std::string name = "path " + std::to_string(a) + "-" + std::to_string(b);
    if (path.size() < 2 || path.front() != network.features[a] ||
        path.back() != network.features[b])
      return name + " does not join its features";
    for (std::size_t k = 1; k + 1 < path.size(); ++k) {
      if (feature_set.count(path[k])) return name + " passes through a feature";
      if (owner[path[k]] >= 0) return name + " touches another path";
      owner[path[k]] = int(e);
    }
    auto left = left_face.find({a, b}), right = left_face.find({b, a});
    if (left == left_face.end() && right == left_face.end()) return name + " is not a domain edge";
    for (std::size_t k = 1; k < path.size(); ++k) {
      const int l = faces(path[k - 1], path[k]), r = faces(path[k], path[k - 1]);
      if (l < 0 && r < 0) return name + " leaves the surface's edges";
      // A boundary edge of the domain runs along the surface's boundary.
      if ((l < 0) != (left == left_face.end()) || (r < 0) != (right == left_face.end()))
        return name + (l < 0 || r < 0
                           ? " runs along the surface's boundary, its domain edge does not"
                           : " is a boundary edge of the domain but not of the surface");
      if ((l >= 0 && network.face_patch[std::size_t(l)] != left->second) ||
          (r >= 0 && network.face_patch[std::size_t(r)] != right->second))
        return name + " separates the wrong patches (orientation or order differs from the domain)";
      if (!cuts.insert(undirected_edge_key(path[k - 1], path[k])).second)
        return name + " reuses an edge";
    }
  }

  // The surface's boundary lies on paths: no patch reaches it elsewhere.
  std::optional<std::string> open_edge;
  faces.for_each([&](int a, int b, int) {
    if (!open_edge && faces(b, a) < 0 && !cuts.count(undirected_edge_key(a, b)))
      open_edge = "boundary edge " + std::to_string(a) + "-" + std::to_string(b) + " is on no path";
  });
  if (open_edge) return open_edge;

  int count = 0;
  const std::vector<int> region = regions(surface, cuts, &count);
  if (std::size_t(count) != domain.n_faces())
    return std::to_string(count) + " patches, the domain has " + std::to_string(domain.n_faces()) +
           " faces";
  std::vector<int> label_of_region(count, -1);
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    int& label = label_of_region[region[f]];
    if (label < 0) label = network.face_patch[f];
    if (label != network.face_patch[f]) return "a patch mixes two domain faces";
  }
  // Each patch must be a disc: Euler characteristic 1 over its faces.
  std::vector<long> v(count, 0), e(count, 0), fcount(count, 0);
  std::vector<std::set<int>> verts(count);
  std::vector<std::set<std::uint64_t>> edges(count);
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const int r = region[f];
    ++fcount[r];
    for (int k = 0; k < 3; ++k) {
      verts[r].insert(surface.triangles[f][k]);
      edges[r].insert(
          undirected_edge_key(surface.triangles[f][k], surface.triangles[f][(k + 1) % 3]));
    }
  }
  for (int r = 0; r < count; ++r) {
    const long chi = long(verts[r].size()) - long(edges[r].size()) + fcount[r];
    if (chi != 1)
      return "patch of domain face " + std::to_string(label_of_region[r]) +
             " is not a disc (Euler characteristic " + std::to_string(chi) + ")";
  }
  return std::nullopt;
}

}  // namespace ism
