// The pieces of a meta-mesh: each face of either side cut by the other
// side's edges into cells, found as the faces of a planar graph in the
// face's own metric. validate() compares the cells of both sides; the
// measures read the affine map of each cell from its two layouts.
#include "map/meta_mesh.hpp"
#include "metrics/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace ism {
namespace {

const char* mesh_name(int m) {
  return m == 0 ? "M¹" : "M²";
}
std::string edge_name(const MetaSide& side, int m, int e) {
  return std::string(mesh_name(m)) + " edge " + std::to_string(side.edges[e][0]) + "-" +
         std::to_string(side.edges[e][1]);
}
std::string vertex_name(int m, int v) {
  return std::string(mesh_name(m)) + " vertex " + std::to_string(v);
}
std::string face_name(int m, int f) {
  return std::string(mesh_name(m)) + " face " + std::to_string(f);
}

/// A piece: the ids of the meta-vertices around it (counter-clockwise,
/// smallest first), where it lies and its corners in that face's layout.
struct Piece {
  std::vector<int> nodes;
  int face;
  std::vector<Vec2> position;
  double area;
};

/// Ids of meta-vertices: M¹ vertices 0..n0-1 (also for an M² vertex on
/// one), other M² vertices n0 + v, crossing i of M¹ edge e n0 + n1 +
/// offset[e] + i.
struct NodeIds {
  std::size_t n0 = 0, n1 = 0;
  std::vector<std::size_t> offset;  // per M¹ edge
  int vertex(const MetaMesh& meta, int m, int v) const {
    if (m == 0) return v;
    const int on = meta.side[1].location[v].vertex;
    return on >= 0 ? on : int(n0) + v;
  }
  int crossing(int e, int i) const { return int(n0 + n1 + offset[e] + i); }
};

/// Everything validate() and the measures need: the first violation, or the
/// pieces of both sides in the same order (piece i of one is piece i of the
/// other).
struct Cut {
  std::optional<std::string> error;
  std::array<std::vector<Piece>, 2> pieces;
};

struct Arrangement {
  std::vector<std::pair<int, Vec2>> nodes;  // id, position
  std::vector<std::array<int, 2>> segments;
};

std::optional<std::string> check_side(const MetaMesh& meta, int m, std::vector<char>& used) {
  const MetaSide& side = meta.side[m];
  const MetaSide& other = meta.side[1 - m];
  if (side.lengths.size() != side.faces.size() || side.face_edges.size() != side.faces.size() ||
      side.crossings.size() != side.edges.size())
    return std::string(mesh_name(m)) + ": inconsistent sizes";
  used.assign(side.n_vertices(), 0);
  for (std::size_t f = 0; f < side.faces.size(); ++f) {
    for (int v : side.faces[f]) {
      if (v < 0 || std::size_t(v) >= side.n_vertices())
        return face_name(m, int(f)) + ": no such vertex";
      used[v] = 1;
    }
    const auto& l = side.lengths[f];
    if (!(triangle_area({l[0], l[1], l[2]}) > 0))
      return face_name(m, int(f)) + ": its edge lengths give no triangle";
  }
  for (std::size_t v = 0; v < side.n_vertices(); ++v) {
    if (!used[v]) continue;
    const MetaLocation& loc = side.location[v];
    if ((loc.vertex >= 0) == (loc.face >= 0))
      return vertex_name(m, int(v)) + ": not located on the other mesh";
    if (loc.vertex >= 0) {
      if (std::size_t(loc.vertex) >= other.n_vertices() ||
          other.location[loc.vertex].vertex != int(v))
        return vertex_name(m, int(v)) + ": on a vertex that is not on it";
    } else if (std::size_t(loc.face) >= other.faces.size() || loc.bary.minCoeff() < 0 ||
               std::abs(loc.bary.sum() - 1) > 1e-9) {
      return vertex_name(m, int(v)) + ": bad location";
    }
  }
  for (std::size_t e = 0; e < side.edges.size(); ++e) {
    double last = 0;
    for (const MetaCrossing& c : side.crossings[e]) {
      if (!(c.here > last && c.here < 1 && c.there > 0 && c.there < 1) || c.edge < 0 ||
          std::size_t(c.edge) >= other.edges.size())
        return edge_name(side, m, int(e)) + ": crossings out of order or off the edges";
      last = c.here;
    }
  }
  return std::nullopt;
}

/// The crossing of M² edge `e1` at index `i` of its list, in M¹'s lists:
/// its index there, or -1.
int matching_crossing(const MetaMesh& meta, int e1, int i) {
  const MetaCrossing& c = meta.side[1].crossings[e1][i];
  const auto& list = meta.side[0].crossings[c.edge];
  const double tolerance = 1e-12;
  auto it = std::lower_bound(list.begin(), list.end(), c.there - tolerance,
                             [](const MetaCrossing& a, double h) { return a.here < h; });
  for (; it != list.end() && it->here <= c.there + tolerance; ++it)
    if (it->edge == e1 && std::abs(it->there - c.here) <= tolerance) return int(it - list.begin());
  return -1;
}

/// The edges of side 1 - m run through the faces of side m, each segment
/// added to the arrangement of the face it lies in.
std::optional<std::string> route_edges(const MetaMesh& meta, int m, const NodeIds& ids,
                                       const std::vector<std::vector<int>>& crossing_id,
                                       std::vector<Arrangement>& cells) {
  const MetaSide& side = meta.side[m];
  const MetaSide& other = meta.side[1 - m];
  std::vector<std::array<int, 2>> edge_faces(side.edges.size(), {-1, -1});
  for (std::size_t f = 0; f < side.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      auto& ef = edge_faces[side.face_edges[f][k]];
      ef[ef[0] < 0 ? 0 : 1] = int(f);
    }
  std::unordered_set<std::uint64_t> has_edge;
  for (const auto& [u, v] : side.edges) has_edge.insert(undirected_edge_key(u, v));
  auto corner_of = [&](int f, int v) {
    for (int k = 0; k < 3; ++k)
      if (side.faces[f][k] == v) return k;
    return -1;
  };
  for (std::size_t g = 0; g < other.edges.size(); ++g) {
    const auto [a, b] = other.edges[g];
    const auto& list = other.crossings[g];
    const MetaLocation &la = other.location[a], &lb = other.location[b];
    auto name = [&] { return edge_name(other, 1 - m, int(g)); };
    int face = la.face;
    if (face < 0) {
      // Leaving a vertex of this side: through the face opposite the first
      // edge crossed, or the face the other end lies in.
      if (!list.empty()) {
        for (int f : edge_faces[list[0].edge])
          if (f >= 0 && corner_of(f, la.vertex) >= 0 &&
              side.face_edges[f][(corner_of(f, la.vertex) + 1) % 3] == list[0].edge)
            face = f;
      } else if (lb.face >= 0) {
        face = corner_of(lb.face, la.vertex) >= 0 ? lb.face : -1;
      } else {
        // From vertex to vertex with no crossing: it lies on an edge.
        if (!has_edge.count(undirected_edge_key(la.vertex, lb.vertex)))
          return name() + ": joins two vertices of an edge the other mesh lacks";
        continue;
      }
      if (face < 0) return name() + ": leaves its vertex through no face";
    }
    int previous = ids.vertex(meta, 1 - m, a);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const int e = list[i].edge;
      const auto& fe = side.face_edges[face];
      if (fe[0] != e && fe[1] != e && fe[2] != e)
        return name() + ": crosses an edge of a face it is not in";
      const int node = crossing_id[g][i];
      cells[face].segments.push_back({previous, node});
      previous = node;
      face = edge_faces[e][0] == face ? edge_faces[e][1] : edge_faces[e][0];
    }
    if (lb.face >= 0 ? lb.face != face : corner_of(face, lb.vertex) < 0)
      return name() + ": does not end in the face its last crossing leads to";
    cells[face].segments.push_back({previous, ids.vertex(meta, 1 - m, b)});
  }
  return std::nullopt;
}

/// The cells of one face's arrangement, appended to `pieces`.
std::optional<std::string> trace_cells(Arrangement& cell, int m, int f, double face_area,
                                       std::vector<Piece>& pieces) {
  auto& nodes = cell.nodes;
  std::sort(nodes.begin(), nodes.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  auto name = [&] { return face_name(m, f); };
  for (std::size_t i = 1; i < nodes.size(); ++i)
    if (nodes[i].first == nodes[i - 1].first) {
      if ((nodes[i].second - nodes[i - 1].second).norm() > 1e-9 * std::sqrt(face_area))
        return name() + ": a meta-vertex at two places";
      nodes.erase(nodes.begin() + i--);
    }
  auto local = [&](int id) {
    auto it = std::lower_bound(nodes.begin(), nodes.end(), id,
                               [](const auto& n, int x) { return n.first < x; });
    return it != nodes.end() && it->first == id ? int(it - nodes.begin()) : -1;
  };
  // Neighbours of each node, counter-clockwise.
  std::vector<std::vector<std::pair<double, int>>> around(nodes.size());
  for (const auto& [p, q] : cell.segments) {
    const int u = local(p), v = local(q);
    if (u < 0 || v < 0) return name() + ": an edge of the other mesh ends at no meta-vertex in it";
    if (u == v) return name() + ": an edge of the other mesh has no length in it";
    const Vec2 d = nodes[v].second - nodes[u].second;
    around[u].push_back({std::atan2(d.y(), d.x()), v});
    around[v].push_back({std::atan2(-d.y(), -d.x()), u});
  }
  for (auto& a : around) {
    std::sort(a.begin(), a.end());
    for (std::size_t i = 1; i < a.size(); ++i)
      if (a[i].second == a[i - 1].second)
        return name() + ": two segments join the same meta-vertices";
    if (a.size() < 2) return name() + ": a meta-vertex on fewer than two of its edges";
  }
  // Each directed segment bounds the cell on its left; the next one turns
  // as far right as possible (the first neighbour clockwise of the way back).
  std::vector<std::vector<char>> done(nodes.size());
  for (std::size_t u = 0; u < nodes.size(); ++u) done[u].assign(around[u].size(), 0);
  int outer = 0;
  double total = 0;
  for (std::size_t u0 = 0; u0 < nodes.size(); ++u0)
    for (std::size_t j0 = 0; j0 < around[u0].size(); ++j0) {
      if (done[u0][j0]) continue;
      Piece piece{{}, f, {}, 0};
      int u = int(u0), j = int(j0);
      while (!done[u][j]) {
        done[u][j] = 1;
        piece.nodes.push_back(nodes[u].first);
        piece.position.push_back(nodes[u].second);
        const int v = around[u][j].second;
        int back = 0;
        while (around[v][back].second != u) ++back;
        j = (back + int(around[v].size()) - 1) % int(around[v].size());
        u = v;
        if (piece.nodes.size() > nodes.size()) return name() + ": its arrangement is not planar";
      }
      if (u != int(u0)) return name() + ": its arrangement is not planar";
      const std::size_t n = piece.position.size();
      for (std::size_t i = 0; i < n; ++i) {
        const Vec2 &p = piece.position[i], &q = piece.position[(i + 1) % n];
        piece.area += 0.5 * (p.x() * q.y() - p.y() * q.x());
      }
      if (piece.area < 0) {
        ++outer;
        continue;
      }
      if (!(piece.area > 0)) return name() + ": a piece with no area";
      total += piece.area;
      const auto first = std::min_element(piece.nodes.begin(), piece.nodes.end());
      const auto shift = first - piece.nodes.begin();
      std::rotate(piece.nodes.begin(), first, piece.nodes.end());
      std::rotate(piece.position.begin(), piece.position.begin() + shift, piece.position.end());
      pieces.push_back(std::move(piece));
    }
  if (outer != 1)
    return name() + ": the other mesh's edges in it are not connected to its boundary";
  if (std::abs(total - face_area) > 1e-9 * face_area)
    return name() + ": its pieces cover " + std::to_string(total / face_area) + " of it";
  return std::nullopt;
}

Cut cut(const MetaMesh& meta) {
  Cut result;
  std::array<std::vector<char>, 2> used;
  for (int m = 0; m < 2; ++m)
    if ((result.error = check_side(meta, m, used[m]))) return result;

  NodeIds ids;
  ids.n0 = meta.side[0].n_vertices();
  ids.n1 = meta.side[1].n_vertices();
  const MetaSide& d = meta.side[0];
  ids.offset.assign(d.edges.size() + 1, 0);
  for (std::size_t e = 0; e < d.edges.size(); ++e)
    ids.offset[e + 1] = ids.offset[e] + d.crossings[e].size();
  // crossing_id[m][e][i]: the node of crossing i of edge e of side m.
  std::array<std::vector<std::vector<int>>, 2> crossing_id;
  crossing_id[0].resize(d.edges.size());
  for (std::size_t e = 0; e < d.edges.size(); ++e)
    for (std::size_t i = 0; i < d.crossings[e].size(); ++i)
      crossing_id[0][e].push_back(ids.crossing(int(e), int(i)));
  const MetaSide& s = meta.side[1];
  std::size_t matched = 0;
  crossing_id[1].resize(s.edges.size());
  for (std::size_t e = 0; e < s.edges.size(); ++e)
    for (std::size_t i = 0; i < s.crossings[e].size(); ++i) {
      const int j = matching_crossing(meta, int(e), int(i));
      if (j < 0)
        return {edge_name(s, 1, int(e)) + ": a crossing that " +
                    edge_name(d, 0, s.crossings[e][i].edge) + " does not record",
                {}};
      crossing_id[1][e].push_back(ids.crossing(s.crossings[e][i].edge, j));
      ++matched;
    }
  if (matched != ids.offset.back())
    return {std::string("M¹ records crossings that M² does not"), {}};

  for (int m = 0; m < 2; ++m) {
    const MetaSide& side = meta.side[m];
    const MetaSide& other = meta.side[1 - m];
    std::vector<Arrangement> cells(side.faces.size());
    std::vector<std::array<Vec2, 3>> layout(side.faces.size());
    for (std::size_t f = 0; f < side.faces.size(); ++f) {
      layout[f] = meta_face_layout(side.lengths[f]);
      auto& cell = cells[f];
      for (int k = 0; k < 3; ++k) {
        // Corner k, then the crossings along edge k -> k+1, as segments.
        const int e = side.face_edges[f][k];
        const bool forward = side.faces[f][k] == side.edges[e][0];
        const Vec2 &p = layout[f][k], &q = layout[f][(k + 1) % 3];
        int previous = ids.vertex(meta, m, side.faces[f][k]);
        cell.nodes.push_back({previous, p});
        const auto& list = side.crossings[e];
        for (std::size_t i = 0; i < list.size(); ++i) {
          const std::size_t n = forward ? i : list.size() - 1 - i;
          const double t = forward ? list[n].here : 1 - list[n].here;
          const int node = crossing_id[m][e][n];
          cell.nodes.push_back({node, p + t * (q - p)});
          cell.segments.push_back({previous, node});
          previous = node;
        }
        cell.segments.push_back({previous, ids.vertex(meta, m, side.faces[f][(k + 1) % 3])});
      }
    }
    for (std::size_t v = 0; v < other.n_vertices(); ++v) {
      const MetaLocation& loc = other.location[v];
      if (!used[1 - m][v] || loc.face < 0) continue;
      const auto& l = layout[loc.face];
      cells[loc.face].nodes.push_back(
          {ids.vertex(meta, 1 - m, int(v)),
           loc.bary[0] * l[0] + loc.bary[1] * l[1] + loc.bary[2] * l[2]});
    }
    if ((result.error = route_edges(meta, m, ids, crossing_id[1 - m], cells))) return result;
    for (std::size_t f = 0; f < side.faces.size(); ++f) {
      const auto& l = side.lengths[f];
      if ((result.error = trace_cells(cells[f], m, int(f), triangle_area({l[0], l[1], l[2]}),
                                      result.pieces[m])))
        return result;
      cells[f] = {};
    }
  }
  // The same cells from both sides, each once.
  for (auto& list : result.pieces)
    std::sort(list.begin(), list.end(),
              [](const Piece& a, const Piece& b) { return a.nodes < b.nodes; });
  if (result.pieces[0].size() != result.pieces[1].size())
    return {"M¹ is cut into " + std::to_string(result.pieces[0].size()) + " pieces, M² into " +
                std::to_string(result.pieces[1].size()),
            {}};
  for (std::size_t i = 0; i < result.pieces[0].size(); ++i) {
    if (result.pieces[0][i].nodes != result.pieces[1][i].nodes)
      return {"a piece of " + face_name(0, result.pieces[0][i].face) + " is no piece of M²", {}};
    if (i > 0 && result.pieces[0][i].nodes == result.pieces[0][i - 1].nodes)
      return {"a piece of " + face_name(0, result.pieces[0][i].face) + " is covered twice", {}};
  }
  return result;
}

}  // namespace

std::array<Vec2, 3> meta_face_layout(const FaceLengths& l) {
  // l[k] is edge k -> k+1; triangle_layout wants the edge opposite each corner.
  return triangle_layout({l[1], l[2], l[0]});
}

std::optional<std::vector<MetaPiece>> meta_pieces(const MetaMesh& meta) {
  Cut c = cut(meta);
  if (c.error) return std::nullopt;
  std::vector<MetaPiece> pieces(c.pieces[0].size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    MetaPiece& p = pieces[i];
    p.nodes = std::move(c.pieces[0][i].nodes);
    for (int m = 0; m < 2; ++m) {
      p.face[m] = c.pieces[m][i].face;
      p.corner[m] = std::move(c.pieces[m][i].position);
      p.area[m] = c.pieces[m][i].area;
    }
  }
  return pieces;
}

std::optional<std::string> validate(const MetaMesh& meta) {
  return cut(meta).error;
}

std::optional<MapMeasures> measures(const MetaMesh& meta) {
  const auto pieces = meta_pieces(meta);
  if (!pieces) return std::nullopt;
  return measures(*pieces);
}

MapMeasures measures(std::span<const MetaPiece> all) {
  std::vector<StretchPiece> pieces;
  pieces.reserve(all.size());
  auto lengths = [](const Vec2& a, const Vec2& b, const Vec2& x, double scale) {
    return TriangleLengths{scale * (x - b).norm(), scale * (a - x).norm(), scale * (b - a).norm()};
  };
  for (const MetaPiece& piece : all) {
    // One affine map per piece: the fan triangle of largest area stands for
    // it, scaled to the piece's area.
    const auto& p = piece.corner[0];
    const auto& q = piece.corner[1];
    std::size_t best = 1;
    for (std::size_t j = 1; j + 1 < p.size(); ++j)
      if (orient(p[0], p[j], p[j + 1]) > orient(p[0], p[best], p[best + 1])) best = j;
    const double scale = std::sqrt(2 * piece.area[0] / orient(p[0], p[best], p[best + 1]));
    pieces.push_back(
        {lengths(p[0], p[best], p[best + 1], scale), lengths(q[0], q[best], q[best + 1], scale)});
  }
  const SymmetricStretch s = symmetric_stretch(pieces);
  return MapMeasures{s.efficiency, s.forward_efficiency, s.backward_efficiency};
}

MetaMeshSize meta_mesh_size(const MetaMesh& meta) {
  return meta_mesh_size(meta, cut(meta).pieces[0].size());
}

MetaMeshSize meta_mesh_size(const MetaMesh& meta, std::size_t pieces) {
  MetaMeshSize size;
  size.pieces = pieces;
  for (const auto& list : meta.side[0].crossings) size.crossings += list.size();
  for (const MetaSide& side : meta.side)
    for (const MetaLocation& loc : side.location) size.vertices_inside += loc.face >= 0;
  for (const MetaLocation& loc : meta.side[0].location) size.shared_vertices += loc.vertex >= 0;
  return size;
}

}  // namespace ism
