#include "map/meta_cut.hpp"

#include "map/piece_cdt.hpp"
#include "map/surface_map.hpp"  // kernel_centroid
#include "metrics/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

namespace ism {

namespace {

const char* side_name(int s) {
  return s == 0 ? "M¹" : "M²";
}
std::string face_name(int s, int f) {
  return std::string(side_name(s)) + " face " + std::to_string(f);
}
std::string edge_name(const MetaSide& side, int s, int e) {
  return std::string(side_name(s)) + " edge " + std::to_string(side.edges[e][0]) + "-" +
         std::to_string(side.edges[e][1]);
}

}  // namespace

// ---------------------------------------------------------------- index

MetaIndex build_index(const MetaMesh& meta) {
  MetaIndex index;
  for (int s = 0; s < 2; ++s) {
    const MetaSide& side = meta.side[s];
    MetaSideIndex& ix = index[s];
    ix.edge_faces.assign(side.edges.size(), {-1, -1});
    ix.vertex_edges.assign(side.n_vertices(), {});
    ix.vertex_faces.assign(side.n_vertices(), {});
    ix.residents.assign(side.faces.size(), {});
    ix.lodgers.assign(side.n_vertices(), {});
    ix.edge_of.reserve(side.edges.size());
    for (std::size_t e = 0; e < side.edges.size(); ++e) {
      const auto [u, v] = side.edges[e];
      ix.edge_of[undirected_edge_key(u, v)] = int(e);
      ix.vertex_edges[u].push_back(int(e));
      ix.vertex_edges[v].push_back(int(e));
    }
    for (std::size_t f = 0; f < side.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int e = side.face_edges[f][k];
        ix.edge_faces[e][side.faces[f][k] == side.edges[e][0] ? 0 : 1] = int(f);
        ix.vertex_faces[side.faces[f][k]].push_back(int(f));
      }
    for (const auto& faces : ix.edge_faces) ix.open = ix.open || faces[0] < 0 || faces[1] < 0;
  }
  for (int s = 0; s < 2; ++s)
    if (index[s].open) index[s].on_edge.assign(meta.side[s].edges.size(), {});
  for (int s = 0; s < 2; ++s) {
    const MetaSide& other = meta.side[1 - s];
    for (std::size_t v = 0; v < other.n_vertices(); ++v) {
      const int f = other.location[v].face, x = other.location[v].vertex;
      if (const int e = other.location[v].edge; e >= 0) {  // (validate refuses it if not open)
        if (std::size_t(e) < index[s].on_edge.size()) index[s].on_edge[e].push_back(int(v));
      } else if (f >= 0 && std::size_t(f) < index[s].residents.size())
        index[s].residents[f].push_back(int(v));
      else if (f < 0 && x >= 0 && std::size_t(x) < index[s].lodgers.size())
        index[s].lodgers[x].push_back(int(v));
    }
    for (auto& list : index[s].on_edge)
      std::stable_sort(list.begin(), list.end(),
                       [&](int a, int b) { return other.location[a].t < other.location[b].t; });
  }
  return index;
}

void add_resident(MetaIndex& index, int side, int v, int face) {
  // `side` is the side of v; its residents live in the other side's index.
  index[1 - side].residents[face].push_back(v);
}

void remove_resident(MetaIndex& index, int side, int v, int face) {
  // Order kept (charts list a face's residents in it); a face of an
  // abstract domain holds thousands, so one search and one block move.
  auto& list = index[1 - side].residents[face];
  if (auto it = std::find(list.begin(), list.end(), v); it != list.end()) list.erase(it);
}

void add_on_edge(MetaIndex& index, const MetaMesh& meta, int side, int v, int e) {
  auto& list = index[1 - side].on_edge[e];
  const auto& location = meta.side[side].location;
  const double t = location[v].t;
  list.insert(std::upper_bound(list.begin(), list.end(), t,
                               [&](double x, int w) { return x < location[w].t; }),
              v);
}

void remove_on_edge(MetaIndex& index, int side, int v, int e) {
  auto& list = index[1 - side].on_edge[e];
  if (auto it = std::find(list.begin(), list.end(), v); it != list.end()) list.erase(it);
}

void add_lodger(MetaIndex& index, int side, int v, int x) {
  index[1 - side].lodgers[x].push_back(v);
}

void remove_lodger(MetaIndex& index, int side, int v, int x) {
  auto& list = index[1 - side].lodgers[x];
  if (auto it = std::find(list.begin(), list.end(), v); it != list.end()) list.erase(it);
}

// ---------------------------------------------------------------- nodes

MetaNode vertex_node(const MetaMesh& meta, int side, int v) {
  MetaNode n;
  const MetaLocation& loc = meta.side[side].location[v];
  n.place[side] = {Place::vertex, v, 0, Eigen::Vector3d::Zero()};
  if (loc.vertex >= 0) {
    n.key = {0, 0, side == 0 ? v : loc.vertex, 0};
    n.place[1 - side] = {Place::vertex, loc.vertex, 0, Eigen::Vector3d::Zero()};
  } else if (loc.on_edge()) {
    n.key = {0, side, v, 0};
    n.place[1 - side] = {Place::edge, loc.edge, loc.t, Eigen::Vector3d::Zero()};
  } else {
    n.key = {0, side, v, 0};
    n.place[1 - side] = {Place::face, loc.face, 0, loc.bary};
  }
  return n;
}

namespace {

// The index in `list` (the list of the other edge of crossing c, which lies
// on edge e) of the same crossing: the record naming e with the parameters
// exchanged; -1 if there is none.
int mirror_record(const std::vector<MetaCrossing>& list, int e, const MetaCrossing& c) {
  int index = -1;
  auto it = std::lower_bound(list.begin(), list.end(), c.there,
                             [](const MetaCrossing& a, double h) { return a.here < h; });
  for (auto j = it; j != list.end() && j->here <= c.there; ++j)
    if (j->edge == e && j->there == c.here) index = int(j - list.begin());
  if (index < 0)
    for (std::size_t j = 0; j < list.size(); ++j)
      if (list[j].edge == e && std::abs(list[j].here - c.there) <= 1e-12 &&
          std::abs(list[j].there - c.here) <= 1e-12)
        index = int(j);
  return index;
}

}  // namespace

std::optional<MetaNode> break_node(const MetaMesh& meta, int side, int e, int i) {
  const auto& list = meta.side[side].crossings[e];
  const MetaCrossing& c = list[i];
  MetaNode n;
  n.place[side] = {Place::edge, e, c.here, Eigen::Vector3d::Zero()};
  if (c.is_kink()) {
    int occurrence = 0;
    for (int j = 0; j < i; ++j) occurrence += list[j].is_kink();
    n.key = {2, side, e, occurrence};
    n.place[1 - side] = {Place::face, c.face, 0, c.bary};
    return n;
  }
  n.place[1 - side] = {Place::edge, c.edge, c.there, Eigen::Vector3d::Zero()};
  const int e0 = side == 0 ? e : c.edge, e1 = side == 0 ? c.edge : e;
  const auto& list0 = meta.side[0].crossings[e0];
  int index0 = side == 0 ? i : -1;
  if (side == 1) {
    index0 = mirror_record(list0, e1, c);
    if (index0 < 0) return std::nullopt;
  }
  // The crossing's rank among the crossings of e0 with e1, along e0: both
  // edges' lists record each of them (e1's with the parameter on e0 as
  // `there`), so it is counted in the shorter list (a domain edge's list
  // holds thousands where a surface edge's holds a few). Two crossings of
  // the same edges closer than 1e-12 along e0 do not occur (the
  // transactions keep crossings clear of each other).
  const double at0 = side == 0 ? c.here : list0[index0].here;
  const auto& list1 = meta.side[1].crossings[e1];
  int occurrence = 0;
  if (list0.size() <= list1.size()) {
    for (const MetaCrossing& r : list0) {
      if (!(r.here < at0 - 1e-12)) break;
      occurrence += r.edge == e1;
    }
  } else {
    for (const MetaCrossing& r : list1) occurrence += r.edge == e0 && r.there < at0 - 1e-12;
  }
  n.key = {1, e0, e1, occurrence};
  return n;
}

void place_faces(const MetaMesh& meta, const MetaIndex& index, int side, const Place& place,
                 std::vector<int>& faces) {
  (void)meta;
  faces.clear();
  switch (place.kind) {
    case Place::vertex:
      faces = index[side].vertex_faces[place.index];
      break;
    case Place::edge:
      for (int f : index[side].edge_faces[place.index])
        if (f >= 0) faces.push_back(f);
      break;
    case Place::face:
      faces.push_back(place.index);
      break;
  }
}

namespace {

std::optional<Vec2> place_in_layout(const MetaSide& side, int f, const std::array<Vec2, 3>& l,
                                    const Place& place) {
  const Triangle& t = side.faces[f];
  switch (place.kind) {
    case Place::vertex:
      for (int k = 0; k < 3; ++k)
        if (t[k] == place.index) return l[k];
      return std::nullopt;
    case Place::edge:
      for (int k = 0; k < 3; ++k)
        if (side.face_edges[f][k] == place.index) {
          const int k1 = (k + 1) % 3;
          return t[k] == side.edges[place.index][0] ? Vec2(l[k] + place.t * (l[k1] - l[k]))
                                                    : Vec2(l[k1] + place.t * (l[k] - l[k1]));
        }
      return std::nullopt;
    case Place::face:
      if (place.index != f) return std::nullopt;
      return from_barycentric(place.bary, l);
  }
  return std::nullopt;
}

bool place_on_face(const MetaSide& side, int f, const Place& place) {
  switch (place.kind) {
    case Place::vertex: {
      const Triangle& t = side.faces[f];
      return t[0] == place.index || t[1] == place.index || t[2] == place.index;
    }
    case Place::edge: {
      const auto& fe = side.face_edges[f];
      return fe[0] == place.index || fe[1] == place.index || fe[2] == place.index;
    }
    case Place::face:
      return place.index == f;
  }
  return false;
}

/// The segment between two places of face f lies along one of its edges
/// (both on one edge, or a vertex and an edge through it).
bool along_an_edge(const MetaSide& side, const Place& a, const Place& b) {
  if (a.kind == Place::edge && b.kind == Place::edge) return a.index == b.index;
  if (a.kind == Place::edge && b.kind == Place::vertex)
    return side.edges[a.index][0] == b.index || side.edges[a.index][1] == b.index;
  if (a.kind == Place::vertex && b.kind == Place::edge) return along_an_edge(side, b, a);
  return false;
}

}  // namespace

std::optional<Vec2> place_in_face(const MetaMesh& meta, int side, int f, const Place& place) {
  return place_in_layout(meta.side[side], f, meta_face_layout(meta.side[side].lengths[f]), place);
}

std::optional<Vec2> place_in_face(const MetaMesh& meta, int side, int f,
                                  const std::array<Vec2, 3>& layout, const Place& place) {
  return place_in_layout(meta.side[side], f, layout, place);
}

// ---------------------------------------------------------------- cutting a face

namespace {

int best_fan(std::span<const Vec2> P, std::span<const Vec2> Q);

/// A face of one side lying inside one face of the other (its corners in
/// that face, no break on its edges, nothing of the other side inside): the
/// one piece the general cut finds, its corners counter-clockwise from the
/// smallest key (the smallest vertex).
struct WholeFace {
  int face = -1;  // the face of the other side holding it
  std::array<NodeKey, 3> nodes;
  std::array<std::array<Vec2, 3>, 2> corner;  // on side 0, on side 1
};

bool whole_face(const MetaMesh& meta, const MetaIndex& index, int s, int f,
                const std::array<Vec2, 3>& L, WholeFace& out) {
  const MetaSide& S = meta.side[s];
  const Triangle& tri = S.faces[f];
  const int h = S.location[tri[0]].face;
  if (!(h >= 0 && S.location[tri[1]].face == h && S.location[tri[2]].face == h &&
        index[s].residents[f].empty() && S.crossings[S.face_edges[f][0]].empty() &&
        S.crossings[S.face_edges[f][1]].empty() && S.crossings[S.face_edges[f][2]].empty()))
    return false;
  if (index[s].open)
    for (int e : S.face_edges[f])
      if (!index[s].on_edge[e].empty()) return false;
  const MetaSide& T = meta.side[1 - s];
  const std::array<Vec2, 3> Lh = meta_face_layout(T.lengths[h]);
  const int first = tri[0] < tri[1] ? (tri[0] < tri[2] ? 0 : 2) : (tri[1] < tri[2] ? 1 : 2);
  out.face = h;
  for (int i = 0; i < 3; ++i) {
    const int k = (first + i) % 3;
    const MetaNode node = vertex_node(meta, s, tri[k]);
    out.nodes[i] = node.key;
    out.corner[s][i] = L[k];
    out.corner[1 - s][i] = *place_in_layout(T, h, Lh, node.place[1 - s]);
  }
  return true;
}

/// Ids of the meta-vertices met while cutting one face, by key: open
/// addressing in one array kept between calls (a face of a coarse side
/// meets thousands, most meet a handful).
class NodeIds {
 public:
  void clear() {
    slots_.assign(64, {NodeKey{}, -1});
    used_ = 0;
  }
  /// The id of `key`, given `id` (and true) if it is new.
  std::pair<int, bool> try_emplace(const NodeKey& key, int id) {
    if (2 * (used_ + 1) > slots_.size()) grow();
    std::size_t i = find(key);
    if (slots_[i].second >= 0) return {slots_[i].second, false};
    slots_[i] = {key, id};
    ++used_;
    return {id, true};
  }

 private:
  std::size_t find(const NodeKey& key) const {
    std::uint64_t h = std::uint64_t(std::uint32_t(key.kind)) * 0x9E3779B97F4A7C15ull;
    for (int x : {key.a, key.b, key.c})
      h = (h ^ std::uint32_t(x)) * 0xBF58476D1CE4E5B9ull, h ^= h >> 29;
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = h & mask;; i = (i + 1) & mask)
      if (slots_[i].second < 0 || slots_[i].first == key) return i;
  }
  void grow() {
    std::vector<std::pair<NodeKey, int>> old(2 * slots_.size(), {NodeKey{}, -1});
    old.swap(slots_);
    for (const auto& slot : old)
      if (slot.second >= 0) slots_[find(slot.first)] = slot;
  }
  std::vector<std::pair<NodeKey, int>> slots_;
  std::size_t used_ = 0;
};

/// cut_face's work: each piece of face f of side s to `visit` (one
/// MetaPiece reused, valid during the call), in order; the error naming
/// the face, if any (pieces visited before it are then void).
template <class Visit>
std::optional<std::string> visit_pieces(const MetaMesh& meta, const MetaIndex& index, int s, int f,
                                        Visit&& visit) {
  const MetaSide& S = meta.side[s];
  const MetaSide& T = meta.side[1 - s];
  const std::array<Vec2, 3> L = meta_face_layout(S.lengths[f]);
  const double face_area = 0.5 * orient(L[0], L[1], L[2]);
  const double scale = std::sqrt(std::max(face_area, 1e-300));
  auto fail = [&](const std::string& why) {
    return std::optional<std::string>(face_name(s, f) + ": " + why);
  };
  thread_local MetaPiece piece;
  // An open map: both sides have boundaries (a map with one open side does
  // not validate: its boundary vertices find no boundary to lie on).
  const bool open = index[s].open && index[1 - s].open;

  if (WholeFace whole; whole_face(meta, index, s, f, L, whole)) {
    piece.nodes.assign(whole.nodes.begin(), whole.nodes.end());
    for (int side = 0; side < 2; ++side)
      piece.corner[side].assign(whole.corner[side].begin(), whole.corner[side].end());
    piece.face[s] = f;
    piece.face[1 - s] = whole.face;
    piece.area[s] = polygon_area(piece.corner[s]);
    piece.area[1 - s] = polygon_area(piece.corner[1 - s]);
    if (!(piece.area[s] > 0)) return fail("a piece with no area");
    if (!(piece.area[1 - s] > 0)) return fail("a piece that is folded or torn on the other mesh");
    visit(piece);
    return std::nullopt;
  }

  // Work arrays kept per thread.
  thread_local std::vector<MetaNode> nodes;
  thread_local std::vector<Vec2> position, other;
  thread_local NodeIds local;
  thread_local std::vector<std::array<int, 2>> segments;
  thread_local std::vector<int> candidates, cell, faces, common, starts;
  thread_local std::vector<std::pair<int, int>> meets;
  thread_local PlanarCells cells;
  nodes.clear(), position.clear(), local.clear(), segments.clear(), candidates.clear();
  std::string error;
  auto add = [&](const MetaNode& n, const Vec2& p) {
    const auto [id, added] = local.try_emplace(n.key, int(nodes.size()));
    if (added) {
      nodes.push_back(n);
      position.push_back(p);
    } else if ((position[id] - p).norm() > 1e-9 * scale && error.empty()) {
      error = "a meta-vertex at two places";
    }
    return id;
  };
  // The boundary: corners and the break points of the edges between them.
  for (int k = 0; k < 3; ++k) {
    const int e = S.face_edges[f][k];
    const bool forward = S.faces[f][k] == S.edges[e][0];
    const Vec2 &p = L[k], &q = L[(k + 1) % 3];
    int previous = add(vertex_node(meta, s, S.faces[f][k]), p);
    // The other side's vertices on a boundary edge (an open map's; such an
    // edge has no break points).
    if (open) {
      const auto& lying = index[s].on_edge[e];
      for (std::size_t i = 0; i < lying.size(); ++i) {
        const MetaNode node = vertex_node(meta, 1 - s, lying[forward ? i : lying.size() - 1 - i]);
        const int id = add(node, *place_in_layout(S, f, L, node.place[s]));
        segments.push_back({previous, id});
        previous = id;
      }
    }
    const auto& list = S.crossings[e];
    for (std::size_t i = 0; i < list.size(); ++i) {
      const int n = int(forward ? i : list.size() - 1 - i);
      const std::optional<MetaNode> node = break_node(meta, s, e, n);
      if (!node)
        return fail("a crossing that " + edge_name(T, 1 - s, list[n].edge) + " does not record");
      // The same arithmetic as every other use of this place (both cuts of
      // a piece give bit-identical corners, so the same triangulation).
      const int id = add(*node, *place_in_layout(S, f, L, node->place[s]));
      segments.push_back({previous, id});
      previous = id;
    }
    segments.push_back({previous, add(vertex_node(meta, s, S.faces[f][(k + 1) % 3]), q)});
  }
  const std::size_t boundary_segments = segments.size();

  // The other side's edges that can enter the face.
  for (int k = 0; k < 3; ++k)
    for (const MetaCrossing& c : S.crossings[S.face_edges[f][k]])
      if (!c.is_kink()) candidates.push_back(c.edge);
  for (int x : index[s].residents[f])
    candidates.insert(candidates.end(), index[1 - s].vertex_edges[x].begin(),
                      index[1 - s].vertex_edges[x].end());
  for (int v : S.faces[f])
    if (const int x = S.location[v].vertex; x >= 0)
      candidates.insert(candidates.end(), index[1 - s].vertex_edges[x].begin(),
                        index[1 - s].vertex_edges[x].end());
  if (open) {
    for (int e : S.face_edges[f])
      for (int x : index[s].on_edge[e])
        candidates.insert(candidates.end(), index[1 - s].vertex_edges[x].begin(),
                          index[1 - s].vertex_edges[x].end());
    // The other side's boundary edges lie on this side's boundary (validate
    // checks the locations that make it so), which the loop above holds.
    std::erase_if(candidates, [&](int g) { return index[1 - s].is_boundary(g); });
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

  // Where the other side's edges meet f's boundary: (edge g, index of the
  // point in g's chain, -1 when g's list does not hold the record), from
  // the records of f's edges. Only the segments of g's chain next to these
  // points, to its end vertices on f and across its kinks inside f can lie
  // on f: a domain edge's chain holds thousands of points, a surface face
  // meets a few.
  meets.clear();
  for (int k = 0; k < 3; ++k) {
    const int e = S.face_edges[f][k];
    for (const MetaCrossing& c : S.crossings[e]) {
      if (c.is_kink()) continue;
      const int i = mirror_record(T.crossings[c.edge], e, c);
      meets.push_back({c.edge, i < 0 ? -1 : i + 1});
    }
  }
  std::sort(meets.begin(), meets.end());
  auto vertex_on_f = [&](int x) {
    return place_on_face(S, f, vertex_node(meta, 1 - s, x).place[s]);
  };

  for (int g : candidates) {
    const auto& list = T.crossings[g];
    const int n = int(list.size());
    // Chain point j: 0 is g's first vertex, 1..n its break points, n + 1 its
    // second vertex. starts: the first points of the segments to look at.
    auto kink_on_f = [&](int j) {
      return j >= 1 && j <= n && list[j - 1].is_kink() && list[j - 1].face == f;
    };
    starts.clear();
    auto near = [&](int j) {
      for (int a = j - 1; a >= 0; --a) {
        starts.push_back(a);
        if (!kink_on_f(a)) break;
      }
      for (int a = j; a <= n; ++a) {
        starts.push_back(a);
        if (!kink_on_f(a + 1)) break;
      }
    };
    bool whole = false;
    const auto from = std::lower_bound(meets.begin(), meets.end(), std::pair<int, int>{g, -1});
    for (auto it = from; it != meets.end() && it->first == g; ++it) {
      if (it->second < 0)
        whole = true;
      else
        near(it->second);
    }
    if (whole) {
      starts.resize(n + 1);
      for (int j = 0; j <= n; ++j) starts[j] = j;
    } else {
      if (vertex_on_f(T.edges[g][0])) near(0);
      if (vertex_on_f(T.edges[g][1])) near(n + 1);
      std::sort(starts.begin(), starts.end());
      starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
    }
    // Chain point j (consecutive starts share one: the last end is kept).
    auto point = [&](int j) -> std::optional<MetaNode> {
      if (j == 0 || j == n + 1) return vertex_node(meta, 1 - s, T.edges[g][j == 0 ? 0 : 1]);
      return break_node(meta, 1 - s, g, j - 1);
    };
    std::optional<MetaNode> pa, pb;
    int pb_index = -1;
    for (int j : starts) {
      pa = j == pb_index ? pb : point(j);
      pb = pa ? point(j + 1) : std::nullopt;
      pb_index = j + 1;
      if (!pa || !pb) {
        const int i = pa ? j : j - 1;
        return fail("a crossing that " + edge_name(S, s, list[i].edge) + " does not record");
      }
      const Place &a = pa->place[s], &b = pb->place[s];
      if (!place_on_face(S, f, a) || !place_on_face(S, f, b)) continue;
      if (a.kind == Place::vertex && b.kind == Place::vertex) continue;  // along an edge of f
      if (along_an_edge(S, a, b))
        return fail(edge_name(T, 1 - s, g) + " runs along one of its edges");
      const int u = add(*pa, *place_in_layout(S, f, L, a));
      const int v = add(*pb, *place_in_layout(S, f, L, b));
      segments.push_back({u, v});
    }
  }
  if (!error.empty()) return fail(error);
  (void)boundary_segments;

  std::string why;
  if (!planar_cells(position, segments, cells, &why)) return fail(why);
  double total = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    cell.assign(cells[i].begin(), cells[i].end());
    piece.nodes.clear();
    piece.corner[s].clear();
    for (int c : cell) piece.corner[s].push_back(position[c]);
    const double area = polygon_area(piece.corner[s]);
    total += area;
    // Smallest key first.
    std::size_t first = 0;
    for (std::size_t i = 1; i < cell.size(); ++i)
      if (nodes[cell[i]].key < nodes[cell[first]].key) first = i;
    std::rotate(cell.begin(), cell.begin() + first, cell.end());
    std::rotate(piece.corner[s].begin(), piece.corner[s].begin() + first, piece.corner[s].end());
    for (int c : cell) piece.nodes.push_back(nodes[c].key);
    piece.face[s] = f;
    piece.area[s] = area;
    // The face of the other side holding the piece: the one all corners
    // touch in which it is positive.
    place_faces(meta, index, 1 - s, nodes[cell[0]].place[1 - s], common);
    for (std::size_t i = 1; i < cell.size() && common.size() > 1; ++i) {
      place_faces(meta, index, 1 - s, nodes[cell[i]].place[1 - s], faces);
      std::erase_if(common,
                    [&](int h) { return std::find(faces.begin(), faces.end(), h) == faces.end(); });
    }
    int found = -1;
    for (int h : common) {
      const std::array<Vec2, 3> Lh = meta_face_layout(T.lengths[h]);
      other.clear();
      bool ok = true;
      for (int c : cell) {
        const std::optional<Vec2> p = place_in_layout(T, h, Lh, nodes[c].place[1 - s]);
        if (!p) {
          ok = false;
          break;
        }
        other.push_back(*p);
      }
      if (!ok) continue;
      const double a = polygon_area(other);
      if (!(a > 0)) continue;
      if (found >= 0) return fail("a piece that lies in two faces of the other mesh");
      found = h;
      piece.face[1 - s] = h;
      piece.corner[1 - s] = other;
      piece.area[1 - s] = a;
    }
    if (found < 0) return fail("a piece that is folded or torn on the other mesh");
    visit(piece);
  }
  if (std::abs(total - face_area) > 1e-9 * face_area)
    return fail("its pieces cover " + std::to_string(total / face_area) + " of it");
  return std::nullopt;
}

}  // namespace

FaceCut cut_face(const MetaMesh& meta, const MetaIndex& index, int s, int f) {
  FaceCut out;
  out.error = visit_pieces(meta, index, s, f, [&](const MetaPiece& p) { out.pieces.push_back(p); });
  if (out.error) out.pieces.clear();
  return out;
}

std::optional<std::string> add_face_sums(const MetaMesh& meta, const MetaIndex& index, int s, int f,
                                         const EnergyTerms& terms, StretchSums& sums) {
  {
    WholeFace whole;
    if (whole_face(meta, index, s, f, meta_face_layout(meta.side[s].lengths[f]), whole)) {
      const auto &P = whole.corner[0], &Q = whole.corner[1];
      if (polygon_area(P) > 0 && polygon_area(Q) > 0) {
        // A triangle whose fan is valid is its own (add_piece's) triangulation.
        if (best_fan(P, Q) < 0)
          sums.set_invalid();
        else
          sums.add_triangle(P, Q, terms,
                            terms.forward_weight(meta.side[1], s == 1 ? f : whole.face));
        return std::nullopt;
      }
    }
  }
  return visit_pieces(meta, index, s, f, [&](const MetaPiece& p) {
    sums.add_piece(p, terms, terms.forward_weight(meta.side[1], p.face[1]));
  });
}

bool planar_cells(const std::vector<Vec2>& position,
                  const std::vector<std::array<int, 2>>& segments, PlanarCells& cells,
                  std::string* error) {
  cells.nodes.clear();
  cells.start.assign(1, 0);
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  const std::size_t n = position.size();
  // Neighbours of each node, counter-clockwise from the direction -pi: by
  // a pseudo-angle in [-2, 2] that orders directions as atan2 does over
  // [-pi, pi] (signed zeros included), at a division's cost.
  auto pseudo_angle = [](const Vec2& d) {
    const double x = d.x(), y = d.y(), t = std::abs(x) + std::abs(y);
    const bool lower = y < 0 || (y == 0 && std::signbit(y) && x < 0);
    if (t == 0) return 0.0;  // no direction (atan2 says 0)
    if (x >= 0) return y / t;
    return lower ? -2 - y / t : 2 - y / t;
  };
  // Work arrays kept per thread (charts call this thousands of times).
  thread_local std::vector<int> first, fill, cell, twin, place;
  // (Each directed segment: its direction's pseudo-angle, its far end, and
  // its slot as made: 2k and 2k + 1 for segment k's two ways.)
  struct Way {
    double angle;
    int to, slot;
    // (As std::pair orders (angle, to).)
    bool operator<(const Way& o) const {
      return angle < o.angle || (!(o.angle < angle) && to < o.to);
    }
  };
  thread_local std::vector<Way> around;
  thread_local std::vector<char> done;
  // All neighbour lists in one array: node u's at [first[u], first[u + 1]).
  first.assign(n + 1, 0);
  for (const auto& [u, v] : segments) {
    if (u == v) return fail("an edge of the other mesh has no length in it");
    ++first[u + 1], ++first[v + 1];
  }
  for (std::size_t u = 0; u < n; ++u) first[u + 1] += first[u];
  around.resize(2 * segments.size());
  {
    fill.assign(first.begin(), first.end() - 1);
    int slot = 0;
    for (const auto& [u, v] : segments) {
      const Vec2 d = position[v] - position[u];
      around[fill[u]++] = {pseudo_angle(d), v, slot++};
      around[fill[v]++] = {pseudo_angle(-d), u, slot++};
    }
  }
  for (std::size_t u = 0; u < n; ++u) {
    const int b = first[u], e = first[u + 1];
    if (b == e) continue;
    // (Mostly two to six neighbours: sorted by insertion, the same order.)
    if (e - b > 16)
      std::sort(around.begin() + b, around.begin() + e);
    else
      for (int i = b + 1; i < e; ++i)
        for (int k = i; k > b && around[k] < around[k - 1]; --k)
          std::swap(around[k], around[k - 1]);
    for (int i = b + 1; i < e; ++i)
      if (around[i].to == around[i - 1].to) return fail("two segments join the same meta-vertices");
    if (e - b < 2) return fail("a meta-vertex on fewer than two segments");
  }
  // Where each slot went, then each way's way back (u -> v: v -> u).
  place.resize(around.size());
  for (std::size_t j = 0; j < around.size(); ++j) place[around[j].slot] = int(j);
  twin.resize(around.size());
  for (std::size_t j = 0; j < around.size(); ++j) twin[j] = place[around[j].slot ^ 1];
  // Each directed segment bounds the cell on its left; the next one turns
  // as far right as possible (the first neighbour clockwise of the way back).
  done.assign(around.size(), 0);
  int outer = 0;
  for (std::size_t u0 = 0; u0 < n; ++u0)
    for (int j0 = first[u0]; j0 < first[u0 + 1]; ++j0) {
      if (done[j0]) continue;
      cell.clear();
      int u = int(u0), j = j0;
      while (!done[j]) {
        done[j] = 1;
        cell.push_back(u);
        const int v = around[j].to, back = twin[j];
        j = back == first[v] ? first[v + 1] - 1 : back - 1;
        u = v;
        if (cell.size() > 2 * n) return fail("its arrangement is not planar");
      }
      if (u != int(u0)) return fail("its arrangement is not planar");
      const double area = polygon_area(position, cell);
      if (area < 0) {
        ++outer;
        continue;
      }
      if (!(area > 0)) return fail("a piece with no area");
      cells.nodes.insert(cells.nodes.end(), cell.begin(), cell.end());
      cells.start.push_back(int(cells.nodes.size()));
    }
  if (outer != 1) return fail("the other mesh's edges in it are not connected to its boundary");
  return true;
}

// ---------------------------------------------------------------- triangulation

namespace {

// The centre of a star triangulation on one side: the centroid of the
// polygon's kernel (the mean of the corners if it has none).
Vec2 star_centre(const std::vector<Vec2>& c) {
  if (const std::optional<Vec2> k = kernel_centroid(c)) return *k;
  Vec2 sum = Vec2::Zero();
  for (const Vec2& p : c) sum += p;
  return sum / double(c.size());
}

// A compatible triangulation of two polygons with corresponding corners
// through a common convex drawing: each polygon's constrained Delaunay
// triangulation is drawn on one strictly convex polygon C with the same
// corners (any triangulation of a convex polygon on its corners is valid
// there), the two drawings are overlaid, and every cell of the overlay (the
// convex intersection of a triangle of each) is mapped back affinely
// through its triangle on each side. The added points are the crossings of
// a diagonal of one triangulation with one of the other, placed on each side
// at the crossing's parameter along that side's own diagonal; cells are
// fanned. Empty if either polygon has no triangulation.
PieceTriangulation overlay_triangulation(const std::vector<Vec2>& P, const std::vector<Vec2>& Q) {
  PieceTriangulation out;
  const int n = int(P.size());
  const auto tp = polygon_cdt(P), tq = polygon_cdt(Q);
  if (!tp || !tq) return out;
  // Corners of C on the unit circle at irregular angles: diagonals of a
  // regular polygon can meet three at a point, these (generically) do not.
  std::vector<Vec2> C(n);
  for (int i = 0; i < n; ++i) {
    const double jitter = 0.35 * (std::fmod(0.6180339887498949 * (i + 1), 1.0) - 0.5);
    const double angle = 2 * M_PI * (i + jitter) / n;
    C[i] = Vec2(std::cos(angle), std::sin(angle));
  }
  out.points = {P, Q};
  // Crossings of a diagonal of tp's triangle edge (a, b) with one of tq's
  // (c, d): strictly interleaved ends.
  std::map<std::array<int, 4>, int> crossing;
  std::vector<Vec2> inC = C;                   // positions on C of all points, for ordering cells
  auto between = [n](int x, int lo, int hi) {  // x strictly inside the arc lo -> hi
    const int dx = (x - lo + n) % n, dh = (hi - lo + n) % n;
    return dx > 0 && dx < dh;
  };
  auto cross = [&](int a, int b, int c, int d) -> int {
    if (a == c || a == d || b == c || b == d) return -1;
    if (between(c, a, b) == between(d, a, b)) return -1;
    const std::array<int, 4> key{std::min(a, b), std::max(a, b), std::min(c, d), std::max(c, d)};
    if (const auto it = crossing.find(key); it != crossing.end()) return it->second;
    const int ea = key[0], eb = key[1], ec = key[2], ed = key[3];
    const Vec2 u = C[eb] - C[ea], v = C[ed] - C[ec], w = C[ec] - C[ea];
    const double den = u.x() * v.y() - u.y() * v.x();
    const double lambda = (w.x() * v.y() - w.y() * v.x()) / den;
    const double mu = (w.x() * u.y() - w.y() * u.x()) / den;
    const int id = int(out.points[0].size());
    out.points[0].push_back(P[ea] + lambda * (P[eb] - P[ea]));
    out.points[1].push_back(Q[ec] + mu * (Q[ed] - Q[ec]));
    inC.push_back(C[ea] + lambda * u);
    crossing.emplace(key, id);
    return id;
  };
  std::vector<std::pair<double, int>> around;  // a cell's corners with their angles
  for (const auto& a : *tp)
    for (const auto& b : *tq) {
      std::vector<int> cell;
      for (int i : a)
        if (i == b[0] || i == b[1] || i == b[2]) cell.push_back(i);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const int id = cross(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
          if (id < 0) continue;
          if (std::find(cell.begin(), cell.end(), id) == cell.end()) cell.push_back(id);
        }
      if (cell.size() < 3) continue;
      Vec2 centre = Vec2::Zero();
      for (int i : cell) centre += inC[i];
      centre /= double(cell.size());
      // Round the centre (angles computed once, not per comparison).
      around.clear();
      for (int i : cell)
        around.push_back({std::atan2(inC[i].y() - centre.y(), inC[i].x() - centre.x()), i});
      std::sort(around.begin(), around.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      for (std::size_t k = 1; k + 1 < around.size(); ++k)
        out.triangles.push_back({around[0].second, around[k].second, around[k + 1].second});
    }
  return out;
}

// How good triangle (a, b, c) of a piece's corners is on both sides (P on
// side 0, Q on side 1): the smaller of its two areas relative to the piece's
// area there (from the corners themselves: the result depends on nothing
// else); positive when it is positive on both.
struct PieceQuality {
  std::span<const Vec2> P, Q;
  double ap, aq;
  PieceQuality(std::span<const Vec2> p, std::span<const Vec2> q)
      : P(p), Q(q), ap(std::max(polygon_area(p), 1e-300)), aq(std::max(polygon_area(q), 1e-300)) {}
  double operator()(int a, int b, int c) const {
    return std::min(orient(P[a], P[b], P[c]) / ap, orient(Q[a], Q[b], Q[c]) / aq);
  }
};

// The apex of the fan of the piece (corners P on side 0, Q on side 1) whose
// worst triangle is best (relative to the piece's areas on each side), or
// -1 if every fan has a triangle that is not positive on both sides. Fans
// often tie (their worst triangle is an ear they share): the first such
// apex from the corner with the smallest side-0 position on, so the winner
// does not depend on how the corners are keyed (a meta-mesh file read back
// numbers its edges, so its keys, anew). A triangle is its own fan (apex 0).
int best_fan(std::span<const Vec2> P, std::span<const Vec2> Q) {
  const int n = int(P.size());
  // (A triangle's quality is positive exactly where it is on both sides:
  // the areas it is divided by are positive.)
  if (n == 3) return orient(P[0], P[1], P[2]) > 0 && orient(Q[0], Q[1], Q[2]) > 0 ? 0 : -1;
  const PieceQuality quality(P, Q);
  int first = 0;
  for (int a = 1; a < n; ++a)
    if (P[a].x() < P[first].x() || (P[a].x() == P[first].x() && P[a].y() < P[first].y())) first = a;
  int best = -1;
  double best_quality = 1e-12;
  for (int i = 0; i < n; ++i) {
    const int a = (first + i) % n;
    double worst = HUGE_VAL;
    for (int j = 1; j + 1 < n && worst > best_quality; ++j)
      worst = std::min(worst, quality(a, (a + j) % n, (a + j + 1) % n));
    if (worst > best_quality) best_quality = worst, best = a;
  }
  return best;
}

}  // namespace

PieceTriangulation triangulate_piece(const MetaPiece& piece) {
  PieceTriangulation out;
  const auto& P = piece.corner[0];
  const auto& Q = piece.corner[1];
  const int n = int(P.size());
  if (n < 3) return out;
  out.points = {P, Q};
  const int best = best_fan(P, Q);
  if (best >= 0) {
    for (int j = 1; j + 1 < n; ++j)
      out.triangles.push_back({best, (best + j) % n, (best + j + 1) % n});
    return out;
  }
  if (n == 3) return out;
  const PieceQuality quality(P, Q);
  const double ap = quality.ap, aq = quality.aq;
  // A star around one point of the piece (on each side the centroid of the
  // polygon's kernel, the two mapped to each other): pieces with runs of
  // collinear corners on both sides, where no fan is valid.
  {
    const Vec2 cp = star_centre(P), cq = star_centre(Q);
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) {
      const int j = (i + 1) % n;
      ok = orient(cp, P[i], P[j]) / ap > 1e-12 && orient(cq, Q[i], Q[j]) / aq > 1e-12;
    }
    if (ok) {
      out.points[0].push_back(cp);
      out.points[1].push_back(cq);
      for (int i = 0; i < n; ++i) out.triangles.push_back({n, i, (i + 1) % n});
      out.added = true;
      return out;
    }
  }
  out.cdt = true;
  for (int side = 0; side < 2; ++side) {
    const auto triangles = polygon_cdt(piece.corner[side]);
    if (!triangles) continue;
    bool ok = true;
    for (const auto& t : *triangles)
      if (!(quality(t[0], t[1], t[2]) > 0)) ok = false;
    if (ok) {
      out.triangles = *triangles;
      return out;
    }
  }
  // Of all triangulations on the corners, the one whose worst triangle (on
  // either side) is best, by dynamic programming over the polygon's
  // sub-chains (O(n³)). All triangles positive on both sides makes it a
  // valid triangulation of both polygons (a locally injective map of a disc
  // whose boundary goes round once).
  std::vector<double> best_q(std::size_t(n) * n, -HUGE_VAL);
  std::vector<int> split(std::size_t(n) * n, -1);
  auto at = [&](int i, int j) { return std::size_t(i) * n + j; };
  for (int i = 0; i + 1 < n; ++i) best_q[at(i, i + 1)] = HUGE_VAL;
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      for (int k = i + 1; k < j; ++k) {
        // A split whose sub-chains are no better than the best so far
        // cannot win: its triangle's quality is not needed.
        const double sub = std::min(best_q[at(i, k)], best_q[at(k, j)]);
        if (!(sub > best_q[at(i, j)])) continue;
        const double q = std::min(sub, quality(i, k, j));
        if (q > best_q[at(i, j)]) best_q[at(i, j)] = q, split[at(i, j)] = k;
      }
    }
  if (best_q[at(0, n - 1)] > 0) {
    std::vector<std::array<int, 2>> stack{{0, n - 1}};
    while (!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      if (j - i < 2) continue;
      const int k = split[at(i, j)];
      out.triangles.push_back({i, k, j});
      stack.push_back({i, k});
      stack.push_back({k, j});
    }
    return out;
  }
  // Last: a compatible triangulation with points added inside the piece.
  PieceTriangulation overlay = overlay_triangulation(P, Q);
  for (const auto& t : overlay.triangles) {
    const auto& p = overlay.points[0];
    const auto& q = overlay.points[1];
    if (!(orient(p[t[0]], p[t[1]], p[t[2]]) / ap > 0 && orient(q[t[0]], q[t[1]], q[t[2]]) / aq > 0))
      return PieceTriangulation{{}, {P, Q}, false, true};
  }
  if (overlay.triangles.empty()) return PieceTriangulation{{}, {P, Q}, false, true};
  overlay.added = true;
  overlay.cdt = true;
  return overlay;
}

StretchTerms triangle_stretch_terms(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q) {
  const double twice_d = orient(p[0], p[1], p[2]);
  const double twice_m = orient(q[0], q[1], q[2]);
  if (!(twice_d > 0) || !(twice_m > 0)) return {HUGE_VAL, HUGE_VAL, 0, 0};
  const double area_d = 0.5 * twice_d, area_m = 0.5 * twice_m;
  // |J|²_F by the cotangent formula (J: side 0 -> side 1): -(1/4A²) Σ_k
  // (d_{k+1}·d_{k+2}) |e_k|², d_k the side-0 edge opposite corner k, e_k
  // the side-1 one; |J⁻¹|²_F = |J|²_F / det² in 2D.
  const Vec2 d0 = p[2] - p[1], d1 = p[0] - p[2], d2 = p[1] - p[0];
  const double s0 = (q[2] - q[1]).squaredNorm(), s1 = (q[0] - q[2]).squaredNorm(),
               s2 = (q[1] - q[0]).squaredNorm();
  const double frob =
      -(d1.dot(d2) * s0 + d2.dot(d0) * s1 + d0.dot(d1) * s2) / (4 * area_d * area_d);
  const double det = area_m / area_d;
  return {area_m * 0.5 * frob, area_d * 0.5 * frob / (det * det), area_d, area_m};
}

Eigen::Matrix2d affine_linear_part(const std::array<Vec2, 3>& from, const std::array<Vec2, 3>& to) {
  Eigen::Matrix2d C, D;
  C << from[1] - from[0], from[2] - from[0];
  D << to[1] - to[0], to[2] - to[0];
  return D * C.inverse();
}

bool StretchMoments::add(const std::array<Vec2, 3>& c, const std::array<Vec2, 3>& b) {
  const double det_c = orient(c[0], c[1], c[2]), det_d = orient(b[0], b[1], b[2]);
  if (!(det_c > 0) || !(det_d > 0)) return false;
  const Eigen::Matrix2d B = affine_linear_part(c, b), Bi = affine_linear_part(b, c);
  const double area_c = 0.5 * det_c, det_b = det_d / det_c;
  const Eigen::Matrix2d BtB = B.transpose() * B, BiBit = Bi * Bi.transpose();
  area += area_c;
  m[0] += area_c * det_b * BtB(0, 0), m[1] += area_c * det_b * BtB(0, 1);
  m[2] += area_c * det_b * BtB(1, 1);
  n[0] += area_c * BiBit(0, 0), n[1] += area_c * BiBit(0, 1), n[2] += area_c * BiBit(1, 1);
  return true;
}

void StretchMoments::add(const StretchMoments& other, double share, double m_weight) {
  area += share * other.area;
  for (int k = 0; k < 3; ++k) m[k] += share * m_weight * other.m[k], n[k] += share * other.n[k];
}

std::array<double, 2> StretchMoments::evaluate(const Eigen::Matrix2d& A) const {
  // X = ½ tr(M (AᵀA)⁻¹), Y = ½ det A · tr(AᵀA N).
  const Eigen::Matrix2d G = A.transpose() * A;
  const double det_g = G.determinant(), det_a = A.determinant();
  if (!(det_a > 0) || !(det_g > 0)) return {HUGE_VAL, HUGE_VAL};
  const double x = (m[0] * G(1, 1) - 2 * m[1] * G(0, 1) + m[2] * G(0, 0)) / det_g;
  const double y = n[0] * G(0, 0) + 2 * n[1] * G(0, 1) + n[2] * G(1, 1);
  return {0.5 * x, 0.5 * det_a * y};
}

double stretch_energy(double forward, double backward, const EnergyTerms& terms,
                      double forward_weight) {
  const double a0 = terms.area0, a1 = terms.area1;
  return forward_weight * (a0 / (a1 * a1)) * forward +
         terms.inverse_weight * (a1 / (a0 * a0)) * backward;
}

namespace {

/// |J|²_F / det J of a triangle's map 0 -> 1 (forward = a₁ |J|²_F / 2,
/// det J = a₁ / a₀): what EnergyTerms::anisotropy penalises.
double anisotropy_ratio(const StretchTerms& t) {
  return 2 * t.forward * t.area0 / (t.area1 * t.area1);
}

}  // namespace

double triangle_energy(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q,
                       const EnergyTerms& terms, double forward_weight) {
  const StretchTerms t = triangle_stretch_terms(p, q);
  if (!(t.forward < HUGE_VAL)) return HUGE_VAL;
  const double e = stretch_energy(t.forward, t.backward, terms, forward_weight);
  if (terms.anisotropy_weight == 0) return e;
  return e + terms.anisotropy(anisotropy_ratio(t), t.area1);
}

std::optional<CornerStretch> corner_stretch(const std::array<Vec2, 3>& p,
                                            const std::array<Vec2, 3>& q, int moving, int k,
                                            const EnergyTerms& terms, double forward_weight) {
  const std::array<Vec2, 3>& x = moving == 0 ? p : q;
  const std::array<Vec2, 3>& y = moving == 0 ? q : p;
  const double fixed_area = 0.5 * orient(y[0], y[1], y[2]);
  if (!(fixed_area > 0)) return std::nullopt;
  const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
  // forward = N a₁ / (8 a₀²), backward = N a₀ / (8 a₁²) (triangle_stretch_terms).
  const double cf = forward_weight * terms.area0 / (terms.area1 * terms.area1);
  const double cb = terms.inverse_weight * terms.area1 / (terms.area0 * terms.area0);
  CornerStretch c;
  c.a = x[k1], c.b = x[k2];
  c.l0 = (y[k2] - y[k1]).squaredNorm(), c.l1 = (y[k] - y[k2]).squaredNorm();
  c.l2 = (y[k1] - y[k]).squaredNorm();
  if (moving == 0) {
    c.alpha = cf * fixed_area, c.beta = cb / (fixed_area * fixed_area);
  } else {
    c.alpha = cb * fixed_area, c.beta = cf / (fixed_area * fixed_area);
  }
  if (terms.anisotropy_weight != 0) {
    // EnergyTerms::anisotropy over side 1's area: the fixed triangle's when
    // side 0 moves, the moving one's otherwise.
    c.fixed_area = fixed_area, c.onset = terms.anisotropy_onset;
    (moving == 0 ? c.kappa0 : c.kappa1) =
        terms.anisotropy_weight / terms.area1 * (moving == 0 ? fixed_area : 1.0);
  }
  return c;
}

double corners_energy(const std::vector<CornerStretch>& corners, const Vec2& x, Vec2* gradient,
                      Eigen::Matrix2d* hessian) {
  double sum = 0;
  if (!gradient) {
    for (const CornerStretch& c : corners) sum += c.value(x);
    return sum;
  }
  gradient->setZero(), hessian->setZero();
  for (const CornerStretch& c : corners) {
    Vec2 g;
    Eigen::Matrix2d h;
    sum += c.derivatives(x, g, h);
    *gradient += g, *hessian += h;
  }
  return sum;
}

[[gnu::always_inline]] inline double CornerStretch::cotangent_sum(const Vec2& e0, const Vec2& e1,
                                                                  const Vec2& e2) const {
  return -(e1.dot(e2) * l0 + e2.dot(e0) * l1 + e0.dot(e1) * l2);
}

double CornerStretch::value(const Vec2& x) const {
  const double area = 0.5 * orient(x, a, b);
  if (!(area > 0)) return HUGE_VAL;
  const double n = cotangent_sum(b - a, x - b, a - x);
  const double e = 0.125 * n * (alpha / (area * area) + beta * area);
  if (kappa0 == 0 && kappa1 == 0) return e;
  const double excess = std::max(0.0, ratio(n, 1 / area) - onset);
  return e + (kappa0 + kappa1 * area) * excess * excess;
}

double CornerStretch::derivatives(const Vec2& x, Vec2& gradient, Eigen::Matrix2d& hessian) const {
  const double area = 0.5 * orient(x, a, b);
  if (!(area > 0)) return HUGE_VAL;
  const Vec2 e0 = b - a, e1 = x - b, e2 = a - x;
  const double n = cotangent_sum(e0, e1, e2);
  const Vec2 dn = l0 * (e1 - e2) + (l1 - l2) * e0;           // ∇N; its Hessian is 2 l0 I
  const Vec2 da = 0.5 * Vec2(a.y() - b.y(), b.x() - a.x());  // ∇a (a is affine in x)
  const double inv = 1 / area;
  const double g = alpha / (area * area) + beta * area;
  const double dg = -2 * alpha * inv * inv * inv + beta, ddg = 6 * alpha * inv * inv * inv * inv;
  gradient = 0.125 * (g * dn + n * dg * da);
  const Eigen::Matrix2d cross = dn * da.transpose() + da * dn.transpose();
  hessian = 0.125 *
            (2 * l0 * g * Eigen::Matrix2d::Identity() + dg * cross + n * ddg * da * da.transpose());
  const double e = 0.125 * n * g;
  if (kappa0 == 0 && kappa1 == 0) return e;
  // r = N / (4 B a) and (κ₀ + κ₁ a) max(0, r − r₀)².
  const double s = 1 / (4 * fixed_area), excess = ratio(n, inv) - onset;
  if (!(excess > 0)) return e;
  const Vec2 dr = s * (dn * inv - n * inv * inv * da);
  const Eigen::Matrix2d hr = s * (2 * l0 * inv * Eigen::Matrix2d::Identity() - inv * inv * cross +
                                  2 * n * inv * inv * inv * da * da.transpose());
  const double w = kappa0 + kappa1 * area;
  gradient += kappa1 * excess * excess * da + 2 * w * excess * dr;
  hessian += 2 * kappa1 * excess * (da * dr.transpose() + dr * da.transpose()) +
             2 * w * (dr * dr.transpose() + excess * hr);
  return e + w * excess * excess;
}

namespace {

/// Calls fn(p, q) for each triangle of triangulate_piece(piece), the fan
/// straight from the corners (no copy) whenever one is valid; false if the
/// piece has no triangulation.
template <class Fn>
bool for_each_piece_triangle(const MetaPiece& piece, Fn&& fn) {
  const auto& P = piece.corner[0];
  const auto& Q = piece.corner[1];
  const int n = int(P.size());
  if (n >= 3) {
    const int a = best_fan(P, Q);
    if (a >= 0) {
      for (int j = 1; j + 1 < n; ++j) {
        const int b = (a + j) % n, c = (a + j + 1) % n;
        fn(std::array<Vec2, 3>{P[a], P[b], P[c]}, std::array<Vec2, 3>{Q[a], Q[b], Q[c]});
      }
      return true;
    }
  }
  const PieceTriangulation tri = triangulate_piece(piece);
  if (tri.triangles.empty()) return false;
  const auto& [p, q] = tri.points;
  for (const auto& t : tri.triangles)
    fn(std::array<Vec2, 3>{p[t[0]], p[t[1]], p[t[2]]},
       std::array<Vec2, 3>{q[t[0]], q[t[1]], q[t[2]]});
  return true;
}

}  // namespace

double piece_energy(const MetaPiece& piece, const EnergyTerms& terms, double forward_weight) {
  double sum = 0;
  const bool triangulated = for_each_piece_triangle(piece, [&](const auto& p, const auto& q) {
    sum += triangle_energy(p, q, terms, forward_weight);
  });
  return triangulated ? sum : HUGE_VAL;
}

void StretchSums::add_triangle(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q,
                               const EnergyTerms& terms, double forward_weight) {
  const StretchTerms t = triangle_stretch_terms(p, q);
  if (!(t.forward < HUGE_VAL)) return set_invalid();
  forward += forward_weight * t.forward;
  backward += t.backward;
  if (terms.anisotropy_weight == 0) return;
  const double excess = std::max(0.0, anisotropy_ratio(t) - terms.anisotropy_onset);
  anisotropy += t.area1 * excess * excess;
}

void StretchSums::add_piece(const MetaPiece& piece, const EnergyTerms& terms,
                            double forward_weight) {
  if (!for_each_piece_triangle(
          piece, [&](const auto& p, const auto& q) { add_triangle(p, q, terms, forward_weight); }))
    set_invalid();
}

double StretchSums::energy(const EnergyTerms& terms) const {
  if (!(forward < HUGE_VAL) || !(backward < HUGE_VAL)) return HUGE_VAL;
  const double e = stretch_energy(forward, backward, terms);
  return terms.anisotropy_weight == 0 ? e : e + terms.anisotropy_weight * anisotropy / terms.area1;
}

}  // namespace ism
