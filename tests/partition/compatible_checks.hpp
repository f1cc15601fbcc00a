#pragma once
// Checks of two compatible networks and their progressive meshes that do not
// trust the library's own validation: patches recomputed from the faces,
// their adjacency compared with the base's and between the two surfaces,
// each patch a disc with exactly its base face's features on it, both
// progressive meshes ending in the base and replaying their surface exactly.
#include "partition/compatible_networks.hpp"
#include "pm/pm.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

namespace ism::test {

/// Faces of a mesh, each rotated to start at its smallest vertex, sorted.
inline std::vector<Triangle> canonical_face_list(std::vector<Triangle> faces) {
  for (Triangle& t : faces) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// Boundary loops of a triangle mesh (closed chains of edges used once).
inline std::size_t count_boundary_loops(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> uses;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  std::map<int, std::vector<int>> next;
  for (const auto& [e, n] : uses)
    if (n == 1) next[e.first].push_back(e.second), next[e.second].push_back(e.first);
  std::set<int> seen;
  std::size_t loops = 0;
  for (const auto& [v, around] : next) {
    if (seen.count(v)) continue;
    ++loops;
    std::vector<int> stack{v};
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      if (!seen.insert(u).second) continue;
      for (int w : next[u]) stack.push_back(w);
    }
  }
  return loops;
}

struct PatchFacts {
  std::set<std::pair<int, int>> adjacency;  // patches sharing an edge
  std::vector<long> euler;                  // V - E + F per patch
  std::vector<int> components;              // connected pieces per patch
  std::vector<std::set<int>> corners;       // base vertices (features) on each patch
};

/// Patch facts from the surface's faces and face_patch alone.
inline PatchFacts patch_facts(const PathNetwork& net, std::size_t patches,
                              std::size_t base_vertices) {
  PatchFacts p;
  p.euler.assign(patches, 0);
  p.components.assign(patches, 0);
  p.corners.assign(patches, {});
  std::map<int, int> feature_of;
  for (std::size_t i = 0; i < base_vertices; ++i) feature_of[net.features[i]] = int(i);
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  std::vector<std::set<int>> vertices(patches);
  std::vector<std::set<std::pair<int, int>>> edges(patches);
  std::vector<long> faces(patches, 0);
  for (std::size_t f = 0; f < net.surface.n_faces(); ++f) {
    const int q = net.face_patch[f];
    const Triangle& t = net.surface.triangles[f];
    ++faces[q];
    for (int k = 0; k < 3; ++k) {
      vertices[q].insert(t[k]);
      const auto e = std::minmax(t[k], t[(k + 1) % 3]);
      edges[q].insert(e);
      edge_faces[e].push_back(int(f));
      if (auto it = feature_of.find(t[k]); it != feature_of.end()) p.corners[q].insert(it->second);
    }
  }
  // Connected pieces of each patch (faces joined across shared edges).
  std::vector<int> parent(net.surface.n_faces());
  for (std::size_t f = 0; f < parent.size(); ++f) parent[f] = int(f);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [e, fs] : edge_faces) {
    if (fs.size() != 2) continue;
    const int a = net.face_patch[fs[0]], b = net.face_patch[fs[1]];
    if (a == b)
      parent[find(fs[0])] = find(fs[1]);
    else
      p.adjacency.insert(std::minmax(a, b));
  }
  for (std::size_t f = 0; f < parent.size(); ++f)
    if (find(int(f)) == int(f)) ++p.components[net.face_patch[f]];
  for (std::size_t q = 0; q < patches; ++q)
    p.euler[q] = long(vertices[q].size()) - long(edges[q].size()) + faces[q];
  return p;
}

/// Everything issue 16 asks of two compatible networks and their meshes.
inline void expect_compatible(const CompatibleNetworks& n,
                              const std::array<ProgressiveMesh, 2>& pms,
                              const std::array<const TriangleMesh*, 2>& inputs) {
  EXPECT_EQ(validate_compatible(n), std::nullopt);
  const TriangleMesh& base = n.base;
  ASSERT_EQ(n.features.size(), base.n_vertices());
  // The base's own face adjacency.
  std::map<std::pair<int, int>, std::vector<int>> base_edge_faces;
  for (std::size_t f = 0; f < base.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      base_edge_faces[std::minmax(base.triangles[f][k], base.triangles[f][(k + 1) % 3])].push_back(
          int(f));
  std::set<std::pair<int, int>> base_adjacency;
  for (const auto& [e, fs] : base_edge_faces) {
    ASSERT_LE(fs.size(), 2u) << "base edge in more than two faces";
    if (fs.size() == 2) base_adjacency.insert(std::minmax(fs[0], fs[1]));
  }
  std::array<PatchFacts, 2> facts;
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(s ? "surface B" : "surface A");
    const PathNetwork& net = n.networks[s];
    const TriangleMesh& input = *inputs[s];
    // The input's vertices are kept, in place.
    ASSERT_GE(net.surface.n_vertices(), input.n_vertices());
    for (std::size_t v = 0; v < input.n_vertices(); ++v)
      ASSERT_EQ(net.surface.positions[v], input.positions[v]);
    EXPECT_EQ(net.original_vertices, input.n_vertices());
    EXPECT_EQ(count_boundary_loops(net.surface), count_boundary_loops(input));
    EXPECT_EQ(euler_characteristic(net.surface), euler_characteristic(input));
    for (std::size_t i = 0; i < base.n_vertices(); ++i)
      EXPECT_EQ(net.features[i], n.features[i].vertex[s]);
    facts[s] = patch_facts(net, base.n_faces(), base.n_vertices());
    for (std::size_t q = 0; q < base.n_faces(); ++q) {
      EXPECT_EQ(facts[s].euler[q], 1) << "patch " << q << " is not a disc";
      EXPECT_EQ(facts[s].components[q], 1) << "patch " << q << " is in pieces";
      const std::set<int> corners(base.triangles[q].begin(), base.triangles[q].end());
      EXPECT_EQ(facts[s].corners[q], corners) << "patch " << q << " touches other features";
    }
    EXPECT_EQ(facts[s].adjacency, base_adjacency);
    // The progressive mesh: base = the common base, vertex for vertex, and
    // all splits rebuild the surface exactly.
    const ProgressiveMesh& pm = pms[s];
    ASSERT_EQ(pm.base_vertices.size(), base.n_vertices());
    for (std::size_t i = 0; i < base.n_vertices(); ++i)
      EXPECT_EQ(pm.base_vertices[i], n.features[i].vertex[s]);
    EXPECT_EQ(base_mesh(pm).triangles, base.triangles);
    const TriangleMesh full = replay(pm);
    EXPECT_EQ(full.positions, net.surface.positions);
    EXPECT_EQ(canonical_face_list(full.triangles), canonical_face_list(net.surface.triangles));
  }
  EXPECT_EQ(facts[0].adjacency, facts[1].adjacency);
}

}  // namespace ism::test
