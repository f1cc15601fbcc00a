#pragma once
// Checks of the meshes a progressive mesh produces: closed manifold, Euler
// characteristic, face sets up to rotation, and the path network of an
// intermediate level (the input network restricted to the vertices present).
#include "partition/partition.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace ism::test {

/// The triangle rotated so that its smallest index comes first.
inline Triangle canonical(const Triangle& t) {
  const int k = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

/// The faces as a sorted list of rotated triples (orientation kept).
inline std::vector<Triangle> face_set(const std::vector<Triangle>& faces) {
  std::vector<Triangle> out;
  for (const Triangle& t : faces) out.push_back(canonical(t));
  std::sort(out.begin(), out.end());
  return out;
}

struct SurfaceTopology {
  std::size_t vertices = 0, edges = 0, faces = 0;  // used vertices only
  long euler = 0;
  std::optional<std::string> problem;  // why it is not a closed manifold
};

/// Counts used vertices, edges and faces, and checks that the mesh is a
/// closed, oriented 2-manifold: every directed edge once with its opposite,
/// every used vertex with one fan of faces.
inline SurfaceTopology surface_topology(const TriangleMesh& mesh) {
  SurfaceTopology out;
  std::map<std::pair<int, int>, int> directed;  // directed edge -> face
  std::vector<std::vector<int>> vertex_faces(mesh.n_vertices());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const Triangle& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      out.problem = "face " + std::to_string(f) + " repeats a vertex";
      return out;
    }
    for (int k = 0; k < 3; ++k) {
      if (!directed.emplace(std::pair{t[k], t[(k + 1) % 3]}, static_cast<int>(f)).second) {
        out.problem = "directed edge used twice";
        return out;
      }
      vertex_faces[t[k]].push_back(static_cast<int>(f));
    }
  }
  for (const auto& [edge, f] : directed)
    if (!directed.count({edge.second, edge.first})) {
      out.problem = "boundary edge";
      return out;
    }
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v) {
    const auto& fan = vertex_faces[v];
    if (fan.empty()) continue;
    ++out.vertices;
    // Walk around v: from face (v, x, y) to the face holding (v, y).
    int f = fan.front();
    std::size_t steps = 0;
    do {
      const Triangle& t = mesh.triangles[f];
      const int k = t[0] == int(v) ? 0 : t[1] == int(v) ? 1 : 2;
      const int y = t[(k + 2) % 3];
      f = directed.at({int(v), y});
      ++steps;
    } while (f != fan.front() && steps <= fan.size());
    if (steps != fan.size()) {
      out.problem = "vertex " + std::to_string(v) + " is non-manifold";
      return out;
    }
  }
  out.faces = mesh.n_faces();
  out.edges = directed.size() / 2;
  out.euler = long(out.vertices) - long(out.edges) + long(out.faces);
  return out;
}

/// The network restricted to the vertices `mesh` uses must still cut it into
/// one disc per domain face, bounded by that face's three paths in its
/// orientation. Returns the first problem found.
inline std::optional<std::string> check_network_level(const TriangleMesh& mesh,
                                                      const PathNetwork& network,
                                                      const TriangleMesh& domain) {
  std::vector<char> used(mesh.n_vertices(), 0);
  for (const Triangle& t : mesh.triangles)
    for (int v : t) used[v] = 1;
  for (int f : network.features)
    if (!used[f]) return "feature " + std::to_string(f) + " is missing";

  std::map<std::pair<int, int>, int> directed;  // directed edge -> face
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      directed[{mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]}] = static_cast<int>(f);

  // Paths restricted to present vertices; (feature of d0 -> feature of d1)
  // gives each path's vertices in that direction.
  std::set<std::pair<int, int>> path_edges;  // undirected (min, max)
  std::map<std::pair<int, int>, std::vector<int>> path_between;
  for (std::size_t e = 0; e < network.paths.size(); ++e) {
    std::vector<int> path;
    for (int v : network.paths[e])
      if (used[v]) path.push_back(v);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      if (!directed.count({path[i], path[i + 1]}))
        return "path " + std::to_string(e) + " is broken between " + std::to_string(path[i]) +
               " and " + std::to_string(path[i + 1]);
      path_edges.insert({std::min(path[i], path[i + 1]), std::max(path[i], path[i + 1])});
    }
    const auto [a, b] = network.domain_edges[e];
    path_between[{a, b}] = path;
    std::reverse(path.begin(), path.end());
    path_between[{b, a}] = path;
  }

  // Patches: faces connected across edges on no path.
  std::vector<int> component(mesh.n_faces(), -1);
  std::vector<std::size_t> boundary_size;
  int components = 0;
  for (std::size_t seed = 0; seed < mesh.n_faces(); ++seed) {
    if (component[seed] >= 0) continue;
    std::vector<int> stack{int(seed)}, faces;
    component[seed] = components;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      faces.push_back(f);
      for (int k = 0; k < 3; ++k) {
        const int u = mesh.triangles[f][k], v = mesh.triangles[f][(k + 1) % 3];
        if (path_edges.count({std::min(u, v), std::max(u, v)})) continue;
        const int g = directed.at({v, u});
        if (component[g] < 0) component[g] = components, stack.push_back(g);
      }
    }
    // Closure: V - E + F = 1 for a disc.
    std::set<int> vertices;
    std::set<std::pair<int, int>> edges;
    std::size_t boundary = 0;
    for (int f : faces)
      for (int k = 0; k < 3; ++k) {
        const int u = mesh.triangles[f][k], v = mesh.triangles[f][(k + 1) % 3];
        vertices.insert(u);
        edges.insert({std::min(u, v), std::max(u, v)});
        if (path_edges.count({std::min(u, v), std::max(u, v)})) ++boundary;
      }
    if (long(vertices.size()) - long(edges.size()) + long(faces.size()) != 1)
      return "patch " + std::to_string(components) + " is not a disc";
    boundary_size.push_back(boundary);
    ++components;
  }
  if (std::size_t(components) != domain.n_faces())
    return std::to_string(components) + " patches for " + std::to_string(domain.n_faces()) +
           " domain faces";

  // Domain face (x, y, z): its three paths, in its direction, bound one patch.
  std::set<int> matched;
  for (std::size_t d = 0; d < domain.n_faces(); ++d) {
    const Triangle& t = domain.triangles[d];
    int patch = -1;
    std::size_t length = 0;
    for (int k = 0; k < 3; ++k) {
      const std::vector<int>& path = path_between.at({t[k], t[(k + 1) % 3]});
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const int c = component[directed.at({path[i], path[i + 1]})];
        if (patch < 0) patch = c;
        if (c != patch)
          return "domain face " + std::to_string(d) + " is not bounded by a single patch";
        ++length;
      }
    }
    if (boundary_size[patch] != length || !matched.insert(patch).second)
      return "patch of domain face " + std::to_string(d) + " has a wrong boundary";
  }
  return std::nullopt;
}

}  // namespace ism::test
