// Tracing the consistent path network (paper §4, after Praun et al. 2001 and
// Kraevoy et al. 2003).
//
// Greedy by length: candidate paths wait in a queue; the shortest is checked
// (still free of the network, leaving and entering its features in the right
// sectors) and recomputed when stale. The first k-1+2g paths must not
// separate the surface (a spanning tree of the features first, then the 2g
// non-separating cycles); every later path must split one region in two. This
// ordering is what guarantees that the network can be completed.
//
// Steiner vertices are inserted eagerly: after each path, every edge that
// joins two network vertices without being a path edge is split at its
// midpoint, so each sector between two paths keeps a free vertex and no later
// path is ever blocked by an edge it cannot cross.
#include "mesh/union_find.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"
#include "partition/region_count.hpp"
#include "partition/tracer_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <set>

namespace ism {
namespace {

using namespace partition_detail;

using Mesh = TracerMesh;

// The tracer gives up when its mesh grows beyond this many times the
// surface's vertices (plus 20000): see NetworkTracer::run().
constexpr std::size_t kMaxSteinerFactor = 3;
// Cost factor of a step next to a given edge's end (NetworkTracer::given_end_).
constexpr double kNearGivenPenalty = 10.0;
using VH = Mesh::VertexHandle;
using HH = Mesh::HalfedgeHandle;

struct Candidate {
  double length;
  int edge;
  std::vector<int> vertices;
  bool wrong_side = false;    // passes a neighbouring feature on the other side than M¹
  bool side_checked = false;  // wrong_side is known
  double priority = 0;        // queue key: shorter first, extremities earlier
  bool operator>(const Candidate& o) const {
    if (wrong_side != o.wrong_side) return wrong_side;
    return priority != o.priority ? priority > o.priority : edge > o.edge;
  }
};

class NetworkTracer {
 public:
  NetworkTracer(const TriangleMesh& surface, const TriangleMesh& domain,
                const std::vector<int>& features, const PartitionOptions& options)
      : domain_(domain), features_(features) {
    if (!options.surface_torus_points.empty()) {
      torus_points_ = options.surface_torus_points;
      for (auto& p : torus_points_) p = p.array() - p.array().floor();
      domain_torus_points_ = options.domain_torus_points;
    }
    swirl_heuristics_ = options.swirl_heuristics;
    for (const Vec3& p : surface.positions) mesh_.add_vertex({p.x(), p.y(), p.z()});
    mesh_.add_property(origin_);
    for (std::size_t f = 0; f < surface.n_faces(); ++f) {
      const Triangle& t = surface.triangles[f];
      const auto face = mesh_.add_face(VH(t[0]), VH(t[1]), VH(t[2]));
      if (!face.is_valid()) throw PartitionError("the surface is not a manifold triangle mesh");
      mesh_.property(origin_, face) = int(f);
    }
    original_vertices_ = surface.n_vertices();
    on_network_.assign(mesh_.n_vertices(), 0);
    for (int f : features_) on_network_[f] = 1;
    build_domain_rings();
    direct_.assign(domain_edges_.size(), 0);
    for (const auto& [a, b] : options.direct_edges) {
      const auto it = edge_index_.find({std::min(a, b), std::max(a, b)});
      if (it == edge_index_.end())
        throw PartitionError("direct path " + std::to_string(a) + "-" + std::to_string(b) +
                             " is not a domain edge");
      const VH fa(features_[a]), fb(features_[b]);
      if (!mesh_.find_halfedge(fa, fb).is_valid())
        throw PartitionError("direct path " + std::to_string(a) + "-" + std::to_string(b) +
                             ": surface vertices " + std::to_string(fa.idx()) + " and " +
                             std::to_string(fb.idx()) + " are not joined by an edge");
      direct_[it->second] = 1;
      reserved_.insert(undirected_edge_key(fa.idx(), fb.idx()));
      if (given_end_.size() < mesh_.n_vertices()) given_end_.resize(mesh_.n_vertices(), 0);
      given_end_[fa.idx()] = given_end_[fb.idx()] = 1;
    }
    std::size_t used = 0;  // vertices that faces use: isolated ones do not count
    for (VH v : mesh_.vertices()) used += !mesh_.is_isolated(v);
    long chi = long(used) - long(mesh_.n_edges()) + long(surface.n_faces());
    genus_ = int((2 - chi) / 2);
    non_separating_paths_ = int(features_.size()) - 1 + 2 * genus_;
    find_extremities();
  }

  PathNetwork run(const std::function<void(double)>& progress);

 private:
  void build_domain_rings();
  int traced_neighbour_before(int i, int j, int direction) const;
  VH first_step(int e, int i) const;
  std::vector<char> allowed_ring(int i, int j);
  std::optional<Candidate> shortest_path(int e);
  std::optional<Candidate> shortest_path_in_class(int e);
  bool still_valid(const Candidate& c);
  bool near_given_end(VH w, VH source, VH target) const;
  int side_of(const std::vector<int>& path, int feature);
  bool on_wrong_side(const Candidate& c);
  void find_extremities();
  int count_regions() const;
  void insert(const Candidate& c);
  void split_edges_between_network_vertices();
  PathNetwork result() const;

  Mesh mesh_;
  OpenMesh::FPropHandleT<int> origin_;  // face of the input surface each face lies in
  const TriangleMesh& domain_;
  std::vector<int> features_;
  std::size_t original_vertices_ = 0;
  int genus_ = 0, non_separating_paths_ = 0;
  std::vector<std::array<int, 2>> domain_edges_;
  std::map<std::pair<int, int>, int> edge_index_;
  std::vector<std::vector<int>> ring_;  // ccw domain neighbours of each domain vertex
  std::vector<std::vector<int>> paths_;
  std::vector<char> direct_;                    // per domain edge: its path is one given edge
  std::unordered_set<std::uint64_t> reserved_;  // those surface edges: never split
  // Surface vertices at the ends of given edges (a boundary and its cap):
  // traced paths pay kNearGivenPenalty for a step onto a vertex next to one
  // of them other than their own ends, so that they leave the boundary
  // instead of running along it (a path hugging the boundary cuts the
  // boundary points beyond it off, and each next path then runs beside it
  // at twice the Steiner density).
  std::vector<char> given_end_;
  bool swirl_heuristics_ = false;
  std::vector<char> extremity_;  // per feature: far from its nearest features
  // Homotopy guide (empty without one): torus points in [0, 1)² per mesh
  // vertex (Steiner vertices included) and per domain vertex.
  std::vector<Eigen::Vector2d> torus_points_, domain_torus_points_;
  std::vector<char> on_network_;
  std::unordered_set<std::uint64_t> network_edges_;
  mutable partition_detail::RegionCount region_count_;  // remembers the regions between counts
  int traced_ = 0;
  // Dijkstra scratch, reused across searches.
  std::vector<double> distance_;
  std::vector<int> parent_;
  std::vector<unsigned> stamp_;
  unsigned search_ = 0;
  std::vector<double> cover_distance_;  // the same for the covering search
  std::vector<std::size_t> cover_parent_;
  std::vector<unsigned> cover_stamp_;
};

void NetworkTracer::build_domain_rings() {
  const int n = int(domain_.n_vertices());
  std::vector<std::map<int, int>> next(n);  // ccw successor around each vertex
  for (const Triangle& t : domain_.triangles)
    for (int k = 0; k < 3; ++k) next[t[k]][t[(k + 1) % 3]] = t[(k + 2) % 3];
  ring_.assign(n, {});
  for (int i = 0; i < n; ++i) {
    if (next[i].empty())
      throw PartitionError("domain vertex " + std::to_string(i) + " has no faces");
    int start = next[i].begin()->first, a = start;
    do {
      ring_[i].push_back(a);
      auto it = next[i].find(a);
      if (it == next[i].end() || ring_[i].size() > next[i].size())
        throw PartitionError("the domain is not a closed manifold mesh");
      a = it->second;
    } while (a != start);
    if (ring_[i].size() != next[i].size())
      throw PartitionError("the domain is not a closed manifold mesh");
    for (int b : ring_[i])
      if (i < b) {
        edge_index_[{i, b}] = int(domain_edges_.size());
        domain_edges_.push_back({i, b});
      }
  }
  paths_.assign(domain_edges_.size(), {});
}

int edge_of(const std::map<std::pair<int, int>, int>& index, int a, int b) {
  return index.at({std::min(a, b), std::max(a, b)});
}

// The nearest traced neighbour of i before (direction -1) or after (+1) j in
// i's ccw ring; -1 if none.
int NetworkTracer::traced_neighbour_before(int i, int j, int direction) const {
  const auto& ring = ring_[i];
  const int n = int(ring.size());
  const int k = int(std::find(ring.begin(), ring.end(), j) - ring.begin());
  for (int t = 1; t < n; ++t) {
    int b = ring[((k + direction * t) % n + n) % n];
    if (!paths_[edge_of(edge_index_, i, b)].empty()) return b;
  }
  return -1;
}

// The surface vertex after feature i on the traced path of domain edge e.
VH NetworkTracer::first_step(int e, int i) const {
  const auto& path = paths_[e];
  return VH(path.front() == features_[i] ? path[1] : path[path.size() - 2]);
}

// Ring vertices of feature i through which a path to domain neighbour j may
// leave: those strictly inside the sector between the traced paths that
// surround j in the domain's cyclic order.
std::vector<char> NetworkTracer::allowed_ring(int i, int j) {
  std::vector<char> allowed(mesh_.n_vertices(), 0);
  const VH f(features_[i]);
  const int before = traced_neighbour_before(i, j, -1);
  if (before < 0) {
    for (VH w : mesh_.vv_range(f)) allowed[w.idx()] = 1;
    return allowed;
  }
  const int after = traced_neighbour_before(i, j, +1);
  const VH from = first_step(edge_of(edge_index_, i, before), i);
  const VH to = first_step(edge_of(edge_index_, i, after), i);
  HH h = mesh_.find_halfedge(f, from);
  for (h = mesh_.ccw_rotated_halfedge_handle(h); mesh_.to_vertex_handle(h) != to;
       h = mesh_.ccw_rotated_halfedge_handle(h))
    allowed[mesh_.to_vertex_handle(h).idx()] = 1;
  return allowed;
}

bool NetworkTracer::near_given_end(VH w, VH source, VH target) const {
  for (VH u : mesh_.vv_range(w))
    if (u != source && u != target && std::size_t(u.idx()) < given_end_.size() &&
        given_end_[u.idx()])
      return true;
  return false;
}

// A* (Euclidean heuristic) from feature a to feature b of domain edge e,
// through free vertices only, leaving and entering in the right sectors.
std::optional<Candidate> NetworkTracer::shortest_path(int e) {
  const auto [a, b] = domain_edges_[e];
  if (direct_[e]) {
    // Given: the surface edge itself, ahead of every traced path, once the
    // order at both features allows it.
    if (!allowed_ring(a, b)[features_[b]] || !allowed_ring(b, a)[features_[a]]) return std::nullopt;
    Candidate c{0.0, e, {features_[a], features_[b]}};
    c.priority = -1.0;
    c.side_checked = true;
    return c;
  }
  if (!torus_points_.empty()) return shortest_path_in_class(e);
  const VH source(features_[a]), target(features_[b]);
  const std::vector<char> leave = allowed_ring(a, b), enter = allowed_ring(b, a);
  const std::size_t n = mesh_.n_vertices();
  if (distance_.size() < n) {
    distance_.resize(n);
    parent_.resize(n);
    stamp_.resize(n, 0);
  }
  ++search_;
  const auto& goal = mesh_.point(target);
  auto heuristic = [&](VH v) { return (mesh_.point(v) - goal).norm(); };
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  stamp_[source.idx()] = search_;
  distance_[source.idx()] = 0.0;
  parent_[source.idx()] = -1;
  open.push({heuristic(source), source.idx()});
  while (!open.empty()) {
    const auto [key, vi] = open.top();
    open.pop();
    const VH v(vi);
    const double dv = distance_[vi];
    if (key > dv + heuristic(v) + 1e-12 * (1 + key)) continue;  // stale entry
    if (v == target) break;
    for (VH w : mesh_.vv_range(v)) {
      const int wi = w.idx();
      if (v == source && !leave[wi]) continue;
      if (w == target) {
        if (!enter[vi]) continue;
      } else if (on_network_[wi]) {
        continue;
      }
      double step = (mesh_.point(w) - mesh_.point(v)).norm();
      if (!given_end_.empty() && w != target && near_given_end(w, source, target))
        step *= kNearGivenPenalty;
      const double dw = dv + step;
      if (stamp_[wi] != search_ || dw < distance_[wi]) {
        stamp_[wi] = search_;
        distance_[wi] = dw;
        parent_[wi] = vi;
        open.push({dw + heuristic(w), wi});
      }
    }
  }
  if (stamp_[target.idx()] != search_) return std::nullopt;
  Candidate c{distance_[target.idx()], e, {}};
  // Paths at the surface's extremities go first (paper §4, swirls).
  c.priority = swirl_heuristics_ && (extremity_[a] || extremity_[b]) ? 0.5 * c.length : c.length;
  for (int v = target.idx(); v >= 0; v = parent_[v]) c.vertices.push_back(v);
  std::reverse(c.vertices.begin(), c.vertices.end());
  return c;
}

// The shortest displacement between two torus points (each coordinate in
// [-1/2, 1/2)).
Eigen::Vector2d torus_step(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d d = to - from;
  return (d.array() - (d.array() + 0.5).floor()).matrix();
}

// A* in the covering plane of the torus guide: a state is a surface vertex
// together with the lattice cell its lift is in (a small window around the
// start), so the search finds the shortest path of the wanted homotopy class
// even when a path winding around a thin handle is shorter.
std::optional<Candidate> NetworkTracer::shortest_path_in_class(int e) {
  constexpr int reach = 2, side = 2 * reach + 1, cells = side * side;
  const auto [a, b] = domain_edges_[e];
  const VH source(features_[a]), target(features_[b]);
  const std::vector<char> leave = allowed_ring(a, b), enter = allowed_ring(b, a);
  // Lift of the target: the source's point plus the domain edge's step.
  const Eigen::Vector2d goal_lift =
      torus_points_[source.idx()] + torus_step(domain_torus_points_[a], domain_torus_points_[b]);
  const Eigen::Vector2d goal_cell = (goal_lift - torus_points_[target.idx()]).array().round();
  if (goal_cell.cwiseAbs().maxCoeff() > reach) return std::nullopt;
  auto state = [&](int v, int cx, int cy) {
    return std::size_t(v) * cells + std::size_t((cx + reach) * side + (cy + reach));
  };
  const std::size_t goal_state = state(target.idx(), int(goal_cell.x()), int(goal_cell.y()));

  const std::size_t n = mesh_.n_vertices() * cells;
  if (cover_distance_.size() < n) {
    cover_distance_.resize(n);
    cover_parent_.resize(n);
    cover_stamp_.resize(n, 0);
  }
  ++search_;
  const auto& goal = mesh_.point(target);
  auto heuristic = [&](VH v) { return (mesh_.point(v) - goal).norm(); };
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const std::size_t start = state(source.idx(), 0, 0);
  cover_stamp_[start] = search_;
  cover_distance_[start] = 0.0;
  cover_parent_[start] = SIZE_MAX;
  open.push({heuristic(source), start});
  while (!open.empty()) {
    const auto [key, si] = open.top();
    open.pop();
    const VH v(int(si / cells));
    const int cell = int(si % cells), cx = cell / side - reach, cy = cell % side - reach;
    const double dv = cover_distance_[si];
    if (key > dv + heuristic(v) + 1e-12 * (1 + key)) continue;  // stale entry
    if (si == goal_state) break;
    if (v == target) continue;  // the target in another cell: a wrong class
    const Eigen::Vector2d& pv = torus_points_[v.idx()];
    for (VH w : mesh_.vv_range(v)) {
      const int wi = w.idx();
      if (v == source && !leave[wi]) continue;
      if (w == target) {
        if (!enter[v.idx()]) continue;
      } else if (on_network_[wi]) {
        continue;
      }
      // The lift moves by the short step; it changes cell where it wraps.
      const Eigen::Vector2d& pw = torus_points_[wi];
      const Eigen::Vector2d jump = (pv + torus_step(pv, pw) - pw).array().round();
      const int wx = cx + int(jump.x()), wy = cy + int(jump.y());
      if (std::abs(wx) > reach || std::abs(wy) > reach) continue;
      const std::size_t sw = state(wi, wx, wy);
      const double dw = dv + (mesh_.point(w) - mesh_.point(v)).norm();
      if (cover_stamp_[sw] != search_ || dw < cover_distance_[sw]) {
        cover_stamp_[sw] = search_;
        cover_distance_[sw] = dw;
        cover_parent_[sw] = si;
        open.push({dw + heuristic(w), sw});
      }
    }
  }
  if (cover_stamp_[goal_state] != search_) return std::nullopt;
  Candidate c{cover_distance_[goal_state], e, {}};
  c.priority = c.length;
  for (std::size_t si = goal_state; si != SIZE_MAX; si = cover_parent_[si])
    c.vertices.push_back(int(si / cells));
  std::reverse(c.vertices.begin(), c.vertices.end());
  // A path through one vertex twice (in two cells) is no simple path.
  std::vector<int> sorted = c.vertices;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
  c.side_checked = true;  // the class is exact: no side heuristic needed
  return c;
}

bool NetworkTracer::still_valid(const Candidate& c) {
  for (std::size_t k = 1; k + 1 < c.vertices.size(); ++k)
    if (on_network_[c.vertices[k]]) return false;
  for (std::size_t k = 1; k < c.vertices.size(); ++k)
    if (!mesh_.find_halfedge(VH(c.vertices[k - 1]), VH(c.vertices[k])).is_valid()) return false;
  const auto [a, b] = domain_edges_[c.edge];
  return allowed_ring(a, b)[c.vertices[1]] && allowed_ring(b, a)[c.vertices[c.vertices.size() - 2]];
}

// Features whose mean distance to their (up to) 8 nearest features is among
// the largest quarter: the tips of the surface, connected early so that
// later paths do not wind around them.
void NetworkTracer::find_extremities() {
  const std::size_t n = features_.size();
  extremity_.assign(n, 0);
  if (n < 4) return;
  std::vector<double> spread(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> d;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i)
        d.push_back((mesh_.point(VH(features_[i])) - mesh_.point(VH(features_[j]))).norm());
    const std::size_t k = std::min<std::size_t>(8, d.size());
    std::partial_sort(d.begin(), d.begin() + k, d.end());
    spread[i] = std::accumulate(d.begin(), d.begin() + k, 0.0) / double(k);
  }
  std::vector<double> sorted = spread;
  std::sort(sorted.begin(), sorted.end());
  const double threshold = sorted[n - std::max<std::size_t>(1, n / 4)];
  for (std::size_t i = 0; i < n; ++i) extremity_[i] = spread[i] >= threshold;
}

// Which side of `path` (vertices from its first to its last feature) the
// feature lies on: +1 left, -1 right (seen from outside the surface), 0 when
// its shortest route meets the path only at an end. The route ignores the
// network: sides are local to where it meets the path.
int NetworkTracer::side_of(const std::vector<int>& path, int feature) {
  const std::size_t n = mesh_.n_vertices();
  if (distance_.size() < n) {
    distance_.resize(n);
    parent_.resize(n);
    stamp_.resize(n, 0);
  }
  std::map<int, std::size_t> index;  // interior path vertex -> its position
  for (std::size_t k = 1; k + 1 < path.size(); ++k) index[path[k]] = k;
  if (index.empty()) return 0;
  ++search_;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  stamp_[feature] = search_;
  distance_[feature] = 0.0;
  parent_[feature] = -1;
  open.push({0.0, feature});
  while (!open.empty()) {
    const auto [dv, vi] = open.top();
    open.pop();
    if (dv > distance_[vi]) continue;
    if (const auto it = index.find(vi); it != index.end()) {
      const int from = parent_[vi];
      const VH p(vi), next(path[it->second + 1]), prev(path[it->second - 1]);
      // Counter-clockwise from the next path vertex, the left side comes
      // before the previous one.
      HH h = mesh_.find_halfedge(p, next);
      for (h = mesh_.ccw_rotated_halfedge_handle(h); mesh_.to_vertex_handle(h) != prev;
           h = mesh_.ccw_rotated_halfedge_handle(h))
        if (mesh_.to_vertex_handle(h).idx() == from) return +1;
      return -1;
    }
    if (vi == path.front() || vi == path.back()) continue;  // around the ends: no side
    const VH v(vi);
    for (VH w : mesh_.vv_range(v)) {
      const int wi = w.idx();
      const double dw = dv + (mesh_.point(w) - mesh_.point(v)).norm();
      if (stamp_[wi] != search_ || dw < distance_[wi]) {
        stamp_[wi] = search_;
        distance_[wi] = dw;
        parent_[wi] = vi;
        open.push({dw, wi});
      }
    }
  }
  return 0;
}

// The path of domain edge (a, b) should have the third corner of the domain
// face left of a -> b on its left and that of the face on the right on its
// right (Praun et al. 2001); a path that does not is likely a swirl.
bool NetworkTracer::on_wrong_side(const Candidate& c) {
  const auto [a, b] = domain_edges_[c.edge];
  const auto& ring = ring_[a];
  const int n = int(ring.size());
  const int k = int(std::find(ring.begin(), ring.end(), b) - ring.begin());
  const int left = ring[(k + 1) % n], right = ring[(k + n - 1) % n];
  if (left != b && left != a && side_of(c.vertices, features_[left]) < 0) return true;
  if (right != b && right != a && right != left && side_of(c.vertices, features_[right]) > 0)
    return true;
  return false;
}

int NetworkTracer::count_regions() const {
  return region_count_(mesh_, network_edges_);
}

void NetworkTracer::insert(const Candidate& c) {
  paths_[c.edge] = c.vertices;
  for (std::size_t k = 0; k < c.vertices.size(); ++k) {
    on_network_[c.vertices[k]] = 1;
    if (k) network_edges_.insert(undirected_edge_key(c.vertices[k - 1], c.vertices[k]));
  }
  ++traced_;
}

void NetworkTracer::split_edges_between_network_vertices() {
  std::vector<Mesh::EdgeHandle> to_split;
  for (auto e : mesh_.edges()) {
    const VH a = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 0));
    const VH b = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 1));
    if (on_network_[a.idx()] && on_network_[b.idx()] &&
        !network_edges_.count(undirected_edge_key(a.idx(), b.idx())) &&
        !reserved_.count(undirected_edge_key(a.idx(), b.idx())))
      to_split.push_back(e);
  }
  for (auto e : to_split) {
    const VH a = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 0));
    const VH b = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 1));
    const VH m = mesh_.add_vertex((mesh_.point(a) + mesh_.point(b)) * 0.5);
    mesh_.split_copy(e, m);  // the halves keep their face's origin
    on_network_.push_back(0);
    if (!torus_points_.empty()) {
      const Eigen::Vector2d& pa = torus_points_[a.idx()];
      const Eigen::Vector2d mid = pa + 0.5 * torus_step(pa, torus_points_[b.idx()]);
      torus_points_.push_back((mid.array() - mid.array().floor()).matrix());
    }
  }
}

PathNetwork NetworkTracer::run(const std::function<void(double)>& progress) {
  const int total = int(domain_edges_.size());
  UnionFind joined(features_.size());
  int components = int(features_.size());
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue;
  std::vector<int> waiting;  // edges to (re)compute before the next choice
  for (int e = 0; e < total; ++e) waiting.push_back(e);
  // Cycles met before the features are all connected: computed again only
  // once they are (recomputing them every round costs quadratic time on
  // large domains).
  std::vector<int> postponed_cycles;

  while (traced_ < total) {
    // An edge without a path now (its feature's free sectors are all
    // network vertices) waits for the next path's Steiner vertices.
    std::vector<int> deferred;
    for (int e : waiting)
      if (auto c = shortest_path(e))
        queue.push(std::move(*c));
      else
        deferred.push_back(e);
    waiting.clear();
    bool inserted = false;
    while (!queue.empty() && !inserted) {
      Candidate c = queue.top();
      queue.pop();
      if (!paths_[c.edge].empty()) continue;
      const auto [a, b] = domain_edges_[c.edge];
      const bool joins_components = joined.find(a) != joined.find(b);
      // A cycle waits until the features are all connected (tree first).
      if (!joins_components && components > 1) {
        postponed_cycles.push_back(c.edge);
        continue;
      }
      if (!still_valid(c)) {
        if (auto fresh = shortest_path(c.edge))
          queue.push(std::move(*fresh));
        else
          deferred.push_back(c.edge);
        continue;
      }
      // A path on the wrong side of a neighbouring feature waits until only
      // such paths are left (paper §4, swirls).
      if (swirl_heuristics_ && !c.side_checked) {
        c.side_checked = true;
        c.wrong_side = on_wrong_side(c);
        if (c.wrong_side) {
          queue.push(std::move(c));
          continue;
        }
      }
      insert(c);
      const int expected =
          traced_ <= non_separating_paths_ ? 1 : traced_ - non_separating_paths_ + 1;
      if (count_regions() != expected) {
        // Separating too early, or not splitting a region: undo, try others.
        paths_[c.edge].clear();
        --traced_;
        on_network_.assign(on_network_.size(), 0);
        network_edges_.clear();
        for (int f : features_) on_network_[f] = 1;
        for (const auto& p : paths_) {
          for (std::size_t k = 0; k < p.size(); ++k) {
            on_network_[p[k]] = 1;
            if (k) network_edges_.insert(undirected_edge_key(p[k - 1], p[k]));
          }
        }
        deferred.push_back(c.edge);
        continue;
      }
      if (joins_components) {
        joined.unite(a, b);
        if (--components == 1) {
          deferred.insert(deferred.end(), postponed_cycles.begin(), postponed_cycles.end());
          postponed_cycles.clear();
        }
      }
      split_edges_between_network_vertices();
      // Paths that wind around each other need Steiner vertices without
      // end (each one runs beside the last at twice its density): stop
      // cleanly instead of exhausting memory.
      if (mesh_.n_vertices() > kMaxSteinerFactor * original_vertices_ + 20000)
        throw PartitionError(
            "the network needed over " + std::to_string(mesh_.n_vertices() - original_vertices_) +
            " Steiner vertices (paths winding around each other) after " + std::to_string(traced_) +
            " of " + std::to_string(total) + " paths; try another base");
      inserted = true;
      if (progress) progress(double(traced_) / total);
    }
    if (!inserted) {
      const auto [a, b] = domain_edges_[!deferred.empty()           ? deferred.front()
                                        : !postponed_cycles.empty() ? postponed_cycles.front()
                                                                    : 0];
      throw PartitionError("cannot trace the path between features " + std::to_string(a) + " and " +
                           std::to_string(b) +
                           ": the features' order cannot be realised on the surface");
    }
    // Everything deferred gets another chance now that the network changed;
    // queued candidates are re-checked lazily when they come up.
    waiting = std::move(deferred);
  }
  return result();
}

PathNetwork NetworkTracer::result() const {
  PathNetwork net;
  for (VH v : mesh_.vertices()) {
    const auto& p = mesh_.point(v);
    net.surface.positions.push_back({p[0], p[1], p[2]});
  }
  for (auto f : mesh_.faces()) {
    Triangle t;
    int k = 0;
    for (VH v : mesh_.fv_range(f)) t[k++] = v.idx();
    net.surface.triangles.push_back(t);
    net.face_origin.push_back(mesh_.property(origin_, f));
  }
  net.original_vertices = original_vertices_;
  net.features = features_;
  net.domain_edges = domain_edges_;
  net.paths = paths_;

  // Label patches: the face left of each path edge belongs to the domain
  // face left of the domain edge, and labels spread across non-path edges.
  std::map<std::pair<int, int>, int> left_face;
  for (std::size_t f = 0; f < domain_.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      left_face[{domain_.triangles[f][k], domain_.triangles[f][(k + 1) % 3]}] = int(f);
  int count = 0;
  const std::vector<int> region = regions(net.surface, network_edges_, &count);
  const DirectedEdgeFaces faces(net.surface);
  std::vector<int> label(count, -1);
  for (std::size_t e = 0; e < paths_.size(); ++e) {
    const auto [a, b] = domain_edges_[e];
    const auto& path = paths_[e];
    const int l = faces(path[0], path[1]), r = faces(path[1], path[0]);
    if (l < 0 || r < 0) throw std::logic_error("trace_path_network: a path left the surface");
    label[region[std::size_t(l)]] = left_face.at({a, b});
    label[region[std::size_t(r)]] = left_face.at({b, a});
  }
  net.face_patch.resize(net.surface.n_faces());
  for (std::size_t f = 0; f < net.surface.n_faces(); ++f) net.face_patch[f] = label[region[f]];
  return net;
}

}  // namespace

PathNetwork trace_path_network(const TriangleMesh& surface, const TriangleMesh& domain,
                               const std::vector<int>& features, const PartitionOptions& options) {
  if (features.size() != domain.n_vertices())
    throw PartitionError(std::to_string(features.size()) + " features given, the domain has " +
                         std::to_string(domain.n_vertices()) + " vertices");
  std::set<int> seen;
  for (std::size_t i = 0; i < features.size(); ++i) {
    if (features[i] < 0 || std::size_t(features[i]) >= surface.n_vertices())
      throw PartitionError("feature " + std::to_string(i) + ": vertex index " +
                           std::to_string(features[i]) + " out of range (the surface has " +
                           std::to_string(surface.n_vertices()) + " vertices)");
    if (!seen.insert(features[i]).second)
      throw PartitionError("features " + std::to_string(i) +
                           " and another one are the same vertex " + std::to_string(features[i]));
  }
  // Genus of both sides (closed surfaces: chi = V - E + F = 2 - 2g).
  const long chi_surface = euler_characteristic(surface), chi_domain = euler_characteristic(domain);
  if (chi_surface != chi_domain)
    throw PartitionError("the surface has genus " + std::to_string((2 - chi_surface) / 2) +
                         ", the domain genus " + std::to_string((2 - chi_domain) / 2));
  if (!options.surface_torus_points.empty() &&
      (options.surface_torus_points.size() != surface.n_vertices() ||
       options.domain_torus_points.size() != domain.n_vertices()))
    throw std::invalid_argument(
        "trace_path_network: a torus guide needs one point per surface and per domain vertex");
  NetworkTracer tracer(surface, domain, features, options);
  PathNetwork network = tracer.run(options.progress);
  if (auto problem = validate_network(network, domain))
    throw PartitionError("the traced network is invalid: " + *problem);
  return network;
}

}  // namespace ism
