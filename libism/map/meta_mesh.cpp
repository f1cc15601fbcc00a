// Building a meta-mesh from a SurfaceMap.
#include "map/meta_mesh.hpp"

#include "map/overlay.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ism {

void set_edge_location(MetaLocation& loc, const MetaSide& other, int f, int e, double t) {
  const auto& fe = other.face_edges[std::size_t(f)];
  const int k = fe[0] == e ? 0 : fe[1] == e ? 1 : fe[2] == e ? 2 : -1;
  if (k < 0)
    throw std::invalid_argument("set_edge_location: edge " + std::to_string(e) +
                                " is not an edge of face " + std::to_string(f));
  const int k1 = (k + 1) % 3;
  const bool forward = other.faces[std::size_t(f)][k] == other.edges[std::size_t(e)][0];
  loc.vertex = -1;
  loc.face = f;
  loc.edge = e;
  loc.t = t;
  loc.bary.setZero();
  loc.bary[k] = forward ? 1 - t : t;
  loc.bary[k1] = forward ? t : 1 - t;
}

bool build_edges(MetaSide& side, bool allow_boundary) {
  std::unordered_map<std::uint64_t, int> id;  // undirected (u, v), u < v
  std::vector<std::array<int, 2>> uses;       // per edge: times used u -> v, v -> u
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> face_edges(side.faces.size());
  for (std::size_t f = 0; f < side.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int u = side.faces[f][k], v = side.faces[f][(k + 1) % 3];
      const int lo = std::min(u, v), hi = std::max(u, v);
      auto [it, added] = id.try_emplace(undirected_edge_key(u, v), int(edges.size()));
      if (added) {
        edges.push_back({lo, hi});
        uses.push_back({0, 0});
      }
      if (++uses[it->second][u < v ? 0 : 1] > 1) return false;
      face_edges[f][k] = it->second;
    }
  for (const auto& u : uses)
    if (u[0] + u[1] != 2 && !(allow_boundary && u[0] + u[1] == 1)) return false;
  side.edges = std::move(edges);
  side.face_edges = std::move(face_edges);
  return true;
}

std::optional<MetaMesh> meta_mesh(const SurfaceMap& map) {
  if (map.validate()) return std::nullopt;
  const DomainGeometry& domain = map.domain();
  MetaMesh meta;
  MetaSide& d = meta.side[0];
  MetaSide& s = meta.side[1];
  d.faces = domain.mesh().triangles;
  for (std::size_t f = 0; f < d.faces.size(); ++f) d.lengths.push_back(domain.lengths(int(f)));
  s.faces = map.faces();
  const auto& x = map.positions();
  s.positions = x;
  for (const Triangle& t : s.faces)
    s.lengths.push_back(
        {(x[t[1]] - x[t[0]]).norm(), (x[t[2]] - x[t[1]]).norm(), (x[t[0]] - x[t[2]]).norm()});
  if (!build_edges(d) || !build_edges(s)) return std::nullopt;
  d.location.assign(domain.n_vertices(), {});
  s.location.assign(x.size(), {});
  d.crossings.resize(d.edges.size());
  s.crossings.resize(s.edges.size());

  for (std::size_t v = 0; v < x.size(); ++v) {
    if (!map.is_active(int(v))) continue;
    if (const int on = map.domain_vertex_at(int(v)); on >= 0) {
      s.location[v].vertex = on;
      d.location[on].vertex = int(v);
    } else {
      s.location[v].face = map.location(int(v)).face;
      s.location[v].bary = map.location(int(v)).bary;
    }
  }

  const auto& domain_faces = domain.mesh().triangles;
  SurfaceMap::FaceChart chart;
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    map.face_chart(int(t), chart);
    // M¹ vertices inside this face: corners of the M¹ faces its pieces
    // come from that fall inside its chart triangle (the first face to
    // claim a vertex on an M² edge keeps it).
    for_each_piece(map, int(t), [&](const OverlayPiece& piece) {
      for (int j = 0; j < 3; ++j) {
        MetaLocation& loc = d.location[domain_faces[piece.domain_face][j]];
        if (loc.vertex >= 0 || loc.face >= 0) continue;
        const Eigen::Vector3d b =
            barycentric(piece.domain_layout[j], chart.corner[0], chart.corner[1], chart.corner[2]);
        if (b.minCoeff() >= 0) loc = {-1, int(t), b / b.sum()};
      }
    });
    // Crossings, from the half-edge that runs from the smaller vertex.
    for (int k = 0; k < 3; ++k) {
      const Triangle& tri = s.faces[t];
      if (tri[k] > tri[(k + 1) % 3]) continue;
      const EdgeWalk& w = map.walk(int(t), k);
      const int surface_edge = s.face_edges[t][k];
      const Vec2 from = chart.corner[k], to = chart.corner[(k + 1) % 3];
      int face = w.start_face;
      std::array<Vec2, 3> layout = chart.walk_layout[k];
      for (int i = 0; i < w.count; ++i) {
        const int e = w.exit(i);
        const Vec2 &a = layout[e], &b = layout[(e + 1) % 3];
        const double along_domain =
            orient(from, to, a) / (orient(from, to, a) - orient(from, to, b));
        const double along_surface = orient(a, b, from) / (orient(a, b, from) - orient(a, b, to));
        const bool forward = domain_faces[face][e] < domain_faces[face][(e + 1) % 3];
        const double there = forward ? along_domain : 1 - along_domain;
        const int domain_edge = d.face_edges[face][e];
        s.crossings[surface_edge].push_back({domain_edge, along_surface, there});
        d.crossings[domain_edge].push_back({surface_edge, there, along_surface});
        layout = domain.unfold(face, layout, e);
        face = domain.neighbour(face, e);
      }
    }
  }
  for (MetaSide* side : {&d, &s})
    for (auto& list : side->crossings)
      std::sort(list.begin(), list.end(),
                [](const MetaCrossing& a, const MetaCrossing& b) { return a.here < b.here; });
  return meta;
}

MetaMesh swapped(const MetaMesh& meta) {
  // Every record is relative to its own side: exchanging the sides is all.
  return MetaMesh{{meta.side[1], meta.side[0]}};
}

}  // namespace ism
