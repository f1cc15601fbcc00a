#include "mesh/union_find.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <map>
#include <set>

namespace ism {

namespace partition_detail {

std::unordered_map<std::uint64_t, int> directed_edge_faces(const TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, int> faces;
  faces.reserve(3 * mesh.n_faces());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      faces[directed_key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3])] = int(f);
  return faces;
}

std::vector<int> regions(const TriangleMesh& mesh, const std::unordered_set<std::uint64_t>& cuts,
                         int* region_count) {
  const auto faces = directed_edge_faces(mesh);
  UnionFind sets(mesh.n_faces());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      if (a > b || cuts.count(undirected_key(a, b))) continue;
      auto other = faces.find(directed_key(b, a));
      if (other != faces.end()) sets.unite(f, std::size_t(other->second));
    }
  std::vector<int> region(mesh.n_faces(), -1);
  std::unordered_map<std::size_t, int> id_of_root;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    auto [it, inserted] = id_of_root.try_emplace(sets.find(f), int(id_of_root.size()));
    region[f] = it->second;
  }
  if (region_count) *region_count = int(id_of_root.size());
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

  const auto faces = directed_edge_faces(surface);
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
      auto l = faces.find(directed_key(path[k - 1], path[k]));
      auto r = faces.find(directed_key(path[k], path[k - 1]));
      if (l == faces.end() && r == faces.end()) return name + " leaves the surface's edges";
      // A boundary edge of the domain runs along the surface's boundary.
      if ((l == faces.end()) != (left == left_face.end()) ||
          (r == faces.end()) != (right == left_face.end()))
        return name + (l == faces.end() || r == faces.end()
                           ? " runs along the surface's boundary, its domain edge does not"
                           : " is a boundary edge of the domain but not of the surface");
      if ((l != faces.end() && network.face_patch[l->second] != left->second) ||
          (r != faces.end() && network.face_patch[r->second] != right->second))
        return name + " separates the wrong patches (orientation or order differs from the domain)";
      if (!cuts.insert(undirected_key(path[k - 1], path[k])).second)
        return name + " reuses an edge";
    }
  }

  // The surface's boundary lies on paths: no patch reaches it elsewhere.
  for (const auto& [key, f] : faces) {
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    if (!faces.count(directed_key(b, a)) && !cuts.count(undirected_key(a, b)))
      return "boundary edge " + std::to_string(a) + "-" + std::to_string(b) + " is on no path";
  }

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
      edges[r].insert(undirected_key(surface.triangles[f][k], surface.triangles[f][(k + 1) % 3]));
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
