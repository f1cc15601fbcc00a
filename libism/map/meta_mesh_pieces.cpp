// The pieces of a whole meta-mesh: every face of both sides cut (cut_face),
// the two sides compared (validate: the same pieces, each once), the
// measures read from the pieces' triangulations.
#include "map/meta_cut.hpp"
#include "metrics/metrics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

/// Per edge of a side, whether it has one face (a boundary edge); per
/// vertex, whether it lies on one.
void boundary_flags(const MetaSide& side, std::vector<char>& edge, std::vector<char>& vertex) {
  std::vector<int> uses(side.edges.size(), 0);
  for (const auto& fe : side.face_edges)
    for (int e : fe)
      if (e >= 0 && std::size_t(e) < uses.size()) ++uses[e];
  edge.assign(side.edges.size(), 0);
  vertex.assign(side.n_vertices(), 0);
  for (std::size_t e = 0; e < uses.size(); ++e)
    if (uses[e] == 1) {
      edge[e] = 1;
      for (int v : side.edges[e])
        if (v >= 0 && std::size_t(v) < vertex.size()) vertex[v] = 1;
    }
}

/// The records of one side on their own: sizes, locations, break points,
/// and on an open map the boundaries' correspondence.
/// (`open`: boundary_flags of both sides, edges then vertices.)
struct BoundaryFlags {
  std::array<std::vector<char>, 2> edge, vertex;
};
std::optional<std::string> check_side(const MetaMesh& meta, int m, const BoundaryFlags& open,
                                      std::vector<char>& used) {
  const MetaSide& side = meta.side[m];
  const MetaSide& other = meta.side[1 - m];
  if (side.lengths.size() != side.faces.size() || side.face_edges.size() != side.faces.size() ||
      side.crossings.size() != side.edges.size())
    return std::string(mesh_name(m)) + ": inconsistent sizes";
  const std::vector<char>&edge_open = open.edge[m], &vertex_open = open.vertex[m],
        &other_edge_open = open.edge[1 - m], &other_vertex_open = open.vertex[1 - m];
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
  auto bad_bary = [](const Eigen::Vector3d& b) {
    return !(b.minCoeff() >= 0) || std::abs(b.sum() - 1) > 1e-9;
  };
  for (std::size_t v = 0; v < side.n_vertices(); ++v) {
    if (!used[v]) continue;
    const MetaLocation& loc = side.location[v];
    if ((loc.vertex >= 0) == (loc.face >= 0))
      return vertex_name(m, int(v)) + ": not located on the other mesh";
    if (loc.vertex >= 0) {
      if (std::size_t(loc.vertex) >= other.n_vertices() ||
          other.location[loc.vertex].vertex != int(v))
        return vertex_name(m, int(v)) + ": on a vertex that is not on it";
      if (vertex_open[v] != other_vertex_open[loc.vertex])
        return vertex_name(m, int(v)) + (vertex_open[v] ? ": a boundary vertex" : ": a vertex") +
               " on " + (vertex_open[v] ? "an interior" : "a boundary") +
               " vertex of the other mesh";
    } else if (std::size_t(loc.face) >= other.faces.size() || bad_bary(loc.bary)) {
      return vertex_name(m, int(v)) + ": bad location";
    } else if (loc.on_edge()) {
      if (std::size_t(loc.edge) >= other.edges.size() || !other_edge_open[loc.edge])
        return vertex_name(m, int(v)) +
               ": on an edge of the other mesh that is not a boundary edge";
      if (!vertex_open[v])
        return vertex_name(m, int(v)) + ": an interior vertex on the other mesh's boundary";
      if (!(loc.t > 0 && loc.t < 1))
        return vertex_name(m, int(v)) + ": on a boundary edge at parameter " +
               std::to_string(loc.t) + ", outside (0, 1)";
      MetaLocation expected;
      const auto& fe = other.face_edges[loc.face];
      if (fe[0] != loc.edge && fe[1] != loc.edge && fe[2] != loc.edge)
        return vertex_name(m, int(v)) + ": on a boundary edge of another face";
      set_edge_location(expected, other, loc.face, loc.edge, loc.t);
      if ((expected.bary - loc.bary).cwiseAbs().maxCoeff() > 1e-12)
        return vertex_name(m, int(v)) + ": its barycentric coordinates are off its boundary edge";
    } else if (vertex_open[v]) {
      return vertex_name(m, int(v)) + ": a boundary vertex inside a face of the other mesh";
    }
  }
  for (std::size_t e = 0; e < side.edges.size(); ++e) {
    if (edge_open[e] && !side.crossings[e].empty())
      return edge_name(side, m, int(e)) + ": a boundary edge with break points";
    double last = 0;
    for (const MetaCrossing& c : side.crossings[e]) {
      const bool bad_other =
          c.is_kink() ? c.face < 0 || std::size_t(c.face) >= other.faces.size() || bad_bary(c.bary)
                      : std::size_t(c.edge) >= other.edges.size() || !(c.there > 0 && c.there < 1);
      if (!(c.here > last && c.here < 1) || bad_other)
        return edge_name(side, m, int(e)) + ": break points out of order or off the edges";
      last = c.here;
    }
  }
  return std::nullopt;
}

struct Cut {
  std::optional<std::string> error;
  std::array<std::vector<MetaPiece>, 2> pieces;
};

bool by_nodes(const MetaPiece& a, const MetaPiece& b) {
  return a.nodes < b.nodes;
}

Cut cut(const MetaMesh& meta) {
  Cut result;
  std::array<std::vector<char>, 2> used;
  BoundaryFlags open;  // computed once for both sides' checks
  for (int m = 0; m < 2; ++m) boundary_flags(meta.side[m], open.edge[m], open.vertex[m]);
  for (int m = 0; m < 2; ++m)
    if ((result.error = check_side(meta, m, open, used[m]))) return result;
  // Every crossing recorded by both of its edges.
  std::size_t count[2] = {0, 0};
  for (int m = 0; m < 2; ++m)
    for (const auto& list : meta.side[m].crossings)
      for (const MetaCrossing& c : list) count[m] += !c.is_kink();
  if (count[0] != count[1]) {
    result.error = std::string("M¹ and M² record ") + std::to_string(count[0]) + " and " +
                   std::to_string(count[1]) + " crossings";
    return result;
  }
  const MetaIndex index = build_index(meta);
  // An edge whose ends are vertices of the other mesh and that crosses
  // nothing lies on an edge of the other mesh.
  for (int m = 0; m < 2; ++m) {
    const MetaSide& side = meta.side[m];
    for (std::size_t e = 0; e < side.edges.size(); ++e) {
      if (!side.crossings[e].empty() || (index[m].open && !index[m].on_edge[e].empty())) continue;
      const int a = side.location[side.edges[e][0]].vertex,
                b = side.location[side.edges[e][1]].vertex;
      if (a >= 0 && b >= 0 && index[1 - m].edge(a, b) < 0)
        result.error =
            edge_name(side, m, int(e)) + ": joins two vertices of an edge the other mesh lacks";
      if (result.error) return result;
    }
  }
  // The faces of each side cut in parallel, then taken in face order: the
  // first error and the pieces' order do not depend on the schedule.
  for (int m = 0; m < 2; ++m) {
    std::vector<FaceCut> faces(meta.side[m].faces.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t f = range.begin(); f != range.end(); ++f)
                          faces[f] = cut_face(meta, index, m, int(f));
                      });
    for (FaceCut& c : faces) {
      if (c.error) {
        result.error = c.error;
        return result;
      }
      for (MetaPiece& p : c.pieces) result.pieces[m].push_back(std::move(p));
    }
    std::sort(result.pieces[m].begin(), result.pieces[m].end(), by_nodes);
  }
  // The same cells from both sides, each once.
  if (result.pieces[0].size() != result.pieces[1].size()) {
    result.error = "M¹ is cut into " + std::to_string(result.pieces[0].size()) +
                   " pieces, M² into " + std::to_string(result.pieces[1].size());
    return result;
  }
  for (std::size_t i = 0; i < result.pieces[0].size(); ++i) {
    const MetaPiece &a = result.pieces[0][i], &b = result.pieces[1][i];
    if (a.nodes != b.nodes || a.face != b.face) {
      result.error = "a piece of " + face_name(0, a.face[0]) + " is no piece of M²";
      return result;
    }
    if (i > 0 && a.nodes == result.pieces[0][i - 1].nodes) {
      result.error = "a piece of " + face_name(0, a.face[0]) + " is covered twice";
      return result;
    }
  }
  return result;
}

}  // namespace

std::array<Vec2, 3> meta_face_layout(const FaceLengths& l) {
  // The local operations ask for the same few faces' layouts thousands of
  // times; a small per-thread table keyed by the lengths' bits returns the
  // very same numbers without recomputing them (Kahan's area: a sort and a
  // square root).
  struct Entry {
    FaceLengths key{-1, -1, -1};
    std::array<Vec2, 3> layout;
  };
  constexpr std::size_t kSlots = 1024;
  thread_local std::array<Entry, kSlots> table;
  std::uint64_t h = 0;
  for (double x : l) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = (h ^ bits) * 0x9E3779B97F4A7C15ull;
  }
  Entry& e = table[(h >> 40) % kSlots];
  if (std::memcmp(e.key.data(), l.data(), sizeof(FaceLengths)) != 0) {
    // l[k] is edge k -> k+1; triangle_layout wants the edge opposite each corner.
    e.layout = triangle_layout({l[1], l[2], l[0]});
    e.key = l;
  }
  return e.layout;
}

std::optional<std::vector<MetaPiece>> meta_pieces(const MetaMesh& meta) {
  Cut c = cut(meta);
  if (c.error) return std::nullopt;
  return std::move(c.pieces[0]);
}

std::optional<std::string> validate(const MetaMesh& meta) {
  return cut(meta).error;
}

std::optional<MapMeasures> measures(const MetaMesh& meta) {
  const auto pieces = meta_pieces(meta);
  if (!pieces) return std::nullopt;
  return measures(*pieces);
}

MapMeasures measures(std::span<const MetaPiece> all, const std::vector<char>& counted) {
  // From the pieces' triangles in both layouts, as the energy the map core
  // lowers (triangle_stretch_terms): the normalised L2 stretch of each
  // direction, L2n² = Σ A_to σ² / A_to · (A_from / A_to).
  double forward = 0, backward = 0, area0 = 0, area1 = 0;
  bool finite = !all.empty();
  bool any = false;
  for (const MetaPiece& piece : all) {
    if (!counted.empty() && !counted.at(std::size_t(piece.face[1]))) continue;
    any = true;
    const PieceTriangulation tri = triangulate_piece(piece);
    if (tri.triangles.empty()) finite = false;
    const auto& [p, q] = tri.points;
    for (const auto& t : tri.triangles) {
      const StretchTerms s =
          triangle_stretch_terms({p[t[0]], p[t[1]], p[t[2]]}, {q[t[0]], q[t[1]], q[t[2]]});
      if (!(s.forward < HUGE_VAL)) finite = false;
      forward += s.forward, backward += s.backward, area0 += s.area0, area1 += s.area1;
    }
  }
  if (!any) return {};
  if (!finite || !(area0 > 0) || !(area1 > 0)) return MapMeasures{0, 0, 0};
  const double l2_forward = forward / area1 * (area0 / area1);
  const double l2_backward = backward / area0 * (area1 / area0);
  return MapMeasures{2 / (l2_forward + l2_backward), 1 / l2_forward, 1 / l2_backward};
}

MetaMeshSize meta_mesh_size(const MetaMesh& meta) {
  return meta_mesh_size(meta, cut(meta).pieces[0]);
}

MetaMeshSize meta_mesh_size(const MetaMesh& meta, std::span<const MetaPiece> pieces) {
  MetaMeshSize size;
  size.pieces = pieces.size();
  for (const MetaPiece& piece : pieces) {
    if (piece.corner[0].size() <= 3) continue;
    const PieceTriangulation tri = triangulate_piece(piece);
    size.triangulated_pieces += tri.added || tri.cdt;
    size.points_inside_pieces += tri.points[0].size() - piece.corner[0].size();
  }
  for (const auto& list : meta.side[0].crossings)
    for (const MetaCrossing& c : list) size.crossings += !c.is_kink();
  for (const MetaSide& side : meta.side)
    for (const auto& list : side.crossings)
      for (const MetaCrossing& c : list) size.kinks += c.is_kink();
  for (const MetaSide& side : meta.side)
    for (const MetaLocation& loc : side.location) {
      size.vertices_inside += loc.face >= 0 && !loc.on_edge();
      size.on_boundary_edges += loc.on_edge();
    }
  for (const MetaLocation& loc : meta.side[0].location) size.shared_vertices += loc.vertex >= 0;
  return size;
}

std::optional<std::array<Vec2, 3>> layout_across(const std::array<Vec2, 3>& G, int ia, int ib,
                                                 const Vec2& pa, const Vec2& pb) {
  // The rotation (with scale |d| / |u|) taking u = G[ib] − G[ia] to d = pb − pa.
  const Vec2 u = G[ib] - G[ia], d = pb - pa;
  const double uu = u.squaredNorm();
  if (!(uu > 0)) return std::nullopt;
  const double cs = u.dot(d) / uu, sn = (u.x() * d.y() - u.y() * d.x()) / uu;
  std::array<Vec2, 3> out;
  for (int q = 0; q < 3; ++q) {
    const Vec2 r = G[q] - G[ia];
    out[q] = pa + Vec2(cs * r.x() - sn * r.y(), sn * r.x() + cs * r.y());
  }
  return out;
}

}  // namespace ism
