#include "partition/network_surface.hpp"

#include "mesh/boundary.hpp"

#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace ism::partition_detail {

NetworkSurface::NetworkSurface(const TriangleMesh& surface,
                               const std::vector<std::vector<int>>& loops)
    : class_(surface.n_vertices(), VertexClass::interior), input_vertices_(surface.n_vertices()) {
  const double area = surface_area(surface);
  scale_ = area > 0 ? 1.0 / std::sqrt(area) : 1.0;
  const CappedMesh capped = cap_boundary_loops(surface, loops);
  positions_ = capped.mesh.positions;
  for (const auto& loop : loops)
    for (int v : loop) class_[v] = VertexClass::boundary;
  class_.resize(positions_.size(), VertexClass::centre);
  for (const Vec3& p : positions_) mesh_.add_vertex({p.x(), p.y(), p.z()});
  using VH = Mesh::VertexHandle;
  for (std::size_t f = 0; f < capped.mesh.n_faces(); ++f) {
    const Triangle& t = capped.mesh.triangles[f];
    if (mesh_.add_face(VH(t[0]), VH(t[1]), VH(t[2])).is_valid()) continue;
    if (!capped.is_cap_face(f)) throw PartitionError("the surface is not a manifold triangle mesh");
    throw PartitionError("boundary loop " + std::to_string(t[2] - int(input_vertices_)) +
                         " cannot be capped");
  }
  on_network_.assign(mesh_.n_vertices(), 0);
  for (std::size_t l = 0; l < loops.size(); ++l) on_network_[centre(l)] = 1;
}

bool NetworkSurface::is_network_edge(int a, int b) const {
  return network_edges_.count(undirected_edge_key(a, b)) != 0;
}

bool NetworkSurface::adjacent(int a, int b) const {
  return mesh_.find_halfedge(Mesh::VertexHandle(a), Mesh::VertexHandle(b)).is_valid();
}

std::vector<int> NetworkSurface::ring(int v) const {
  std::vector<int> out;
  const Mesh::HalfedgeHandle start = mesh_.halfedge_handle(Mesh::VertexHandle(v));
  if (!start.is_valid()) return out;
  Mesh::HalfedgeHandle h = start;
  do {
    out.push_back(mesh_.to_vertex_handle(h).idx());
    h = mesh_.ccw_rotated_halfedge_handle(h);
  } while (h != start && out.size() <= mesh_.n_vertices());
  return out;
}

std::vector<int> NetworkSurface::ring_between(int v, int from, int to) const {
  const std::vector<int> all = ring(v);
  if (from < 0) return all;
  const auto at = std::find(all.begin(), all.end(), from);
  if (at == all.end()) return {};
  const std::size_t n = all.size(), k = std::size_t(at - all.begin());
  std::vector<int> out;
  for (std::size_t t = 1; t < n; ++t) {
    const int w = all[(k + t) % n];
    if (w == to) break;
    out.push_back(w);
  }
  return out;
}

bool NetworkSurface::may_leave_through(int feature, int w) const {
  if (on_network_[w]) return false;
  return class_[feature] == VertexClass::centre ? class_[w] == VertexClass::boundary
                                                : class_[w] == VertexClass::interior;
}

void NetworkSurface::flag_path(const std::vector<int>& path, char on) {
  // (As the keys do: every edge between the two vertices.)
  if (network_edge_.size() < mesh_.n_edges()) network_edge_.resize(mesh_.n_edges(), 0);
  for (std::size_t k = 1; k < path.size(); ++k)
    for (const auto h : mesh_.voh_range(Mesh::VertexHandle(path[k - 1])))
      if (mesh_.to_vertex_handle(h).idx() == path[k])
        network_edge_[std::size_t(mesh_.edge_handle(h).idx())] = on;
}

void NetworkSurface::add_path(const std::vector<int>& path) {
  for (std::size_t k = 1; k + 1 < path.size(); ++k) on_network_[path[k]] = 1;
  for (std::size_t k = 1; k < path.size(); ++k)
    network_edges_.insert(undirected_edge_key(path[k - 1], path[k]));
  flag_path(path, 1);
}

void NetworkSurface::remove_path(const std::vector<int>& path) {
  for (std::size_t k = 1; k + 1 < path.size(); ++k) on_network_[path[k]] = 0;
  for (std::size_t k = 1; k < path.size(); ++k)
    network_edges_.erase(undirected_edge_key(path[k - 1], path[k]));
  flag_path(path, 0);
}

bool NetworkSurface::is_loop_edge(Mesh::EdgeHandle e) const {
  for (int side = 0; side < 2; ++side) {
    const auto h = mesh_.halfedge_handle(e, side);
    const int opposite = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)).idx();
    if (class_[opposite] == VertexClass::centre) return true;
  }
  return false;
}

std::size_t NetworkSurface::split_blocked_edges(const std::vector<std::array<int, 2>>& finished) {
  // Faces of the finished regions: a flood fill across edges off the network.
  std::vector<char> frozen(mesh_.n_faces(), 0);
  std::vector<Mesh::FaceHandle> stack;
  for (const auto& [a, b] : finished) {
    const auto h = mesh_.find_halfedge(Mesh::VertexHandle(a), Mesh::VertexHandle(b));
    if (!h.is_valid() || !mesh_.face_handle(h).is_valid()) continue;
    if (frozen[mesh_.face_handle(h).idx()]) continue;
    frozen[mesh_.face_handle(h).idx()] = 1;
    stack.push_back(mesh_.face_handle(h));
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (const auto g : mesh_.fh_range(f)) {
        if (flagged(mesh_.edge_handle(g))) continue;
        const auto next = mesh_.face_handle(mesh_.opposite_halfedge_handle(g));
        if (next.is_valid() && !frozen[next.idx()]) {
          frozen[next.idx()] = 1;
          stack.push_back(next);
        }
      }
    }
  }
  std::size_t added = 0;
  for (;;) {
    std::vector<std::pair<Mesh::EdgeHandle, bool>> to_split;  // edge, on a loop
    for (auto e : mesh_.edges()) {
      const int a = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 0)).idx();
      const int b = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 1)).idx();
      const auto f = mesh_.face_handle(mesh_.halfedge_handle(e, 0));
      if (f.is_valid() && std::size_t(f.idx()) < frozen.size() && frozen[f.idx()]) continue;
      if (class_[a] == VertexClass::centre || class_[b] == VertexClass::centre) continue;
      // Off the network between two blocked vertices; on a loop, between
      // two vertices on the network.
      if (flagged(e) || !(blocked(a) && blocked(b))) continue;
      const bool loop = is_loop_edge(e);
      if (!loop || (on_network_[a] && on_network_[b])) to_split.push_back({e, loop});
    }
    if (to_split.empty()) {
      near_network_.assign(mesh_.n_vertices(), 0);
      for (auto e : mesh_.edges()) {
        const int a = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 0)).idx();
        const int b = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 1)).idx();
        near_network_[a] |= on_network_[b];
        near_network_[b] |= on_network_[a];
      }
      return added;
    }
    for (const auto& [e, loop] : to_split) {
      const auto a = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 0));
      const auto b = mesh_.to_vertex_handle(mesh_.halfedge_handle(e, 1));
      const Vec3 mid = 0.5 * (positions_[a.idx()] + positions_[b.idx()]);
      const auto m = mesh_.add_vertex({mid.x(), mid.y(), mid.z()});
      mesh_.split(e, m);
      frozen.resize(mesh_.n_faces(), 0);  // faces split off a live region are live
      positions_.push_back(mid);
      class_.push_back(loop ? VertexClass::boundary : VertexClass::interior);
      on_network_.push_back(0);
      ++added;
    }
  }
}

int NetworkSurface::count_regions() const {
  return region_count_(mesh_, network_edges_);
}

void NetworkSurface::next_search(std::size_t n) {
  if (distance_.size() < 2 * n) {
    distance_.resize(2 * n);
    parent_.resize(2 * n);
    stamp_.resize(2 * n, 0);
  }
  if (++search_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    search_ = 1;
  }
}

double NetworkSurface::length(const std::vector<int>& path) const {
  double sum = 0;
  for (std::size_t k = 1; k < path.size(); ++k)
    sum += (positions_[path[k]] - positions_[path[k - 1]]).norm();
  return sum * scale_;
}

std::optional<TracedPath> NetworkSurface::shortest_path(const SearchEnd& from, const SearchEnd& to,
                                                        const ParityRule* parity, double bound,
                                                        bool allow_repeats) {
  next_search(mesh_.n_vertices());
  constexpr int kStart = -1;
  const int source = from.vertex, target = to.vertex;
  const bool loop = source == target;
  const bool source_centre = class_[source] == VertexClass::centre;
  const bool target_centre = class_[target] == VertexClass::centre;
  const Vec3 goal = positions_[target];
  auto heuristic = [&](int v) { return (positions_[v] - goal).norm() * scale_; };
  auto step = [&](int a, int b) { return (positions_[a] - positions_[b]).norm() * scale_; };
  auto crosses = [&](int a, int b) {
    return parity && parity->crossing->count(undirected_edge_key(a, b)) ? 1 : 0;
  };
  auto enter_sector = [&](int v) {
    for (std::size_t k = 0; k < to.ring.size(); ++k)
      if (to.ring[k] == v) return to.sector[k];
    return -1;
  };

  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  for (int w : from.ring) {
    const int s = 2 * w + crosses(source, w);
    const double d = step(source, w);
    if (stamp_[s] == search_ && distance_[s] <= d) continue;
    stamp_[s] = search_;
    distance_[s] = d;
    parent_[s] = kStart;
    open.push({d + heuristic(w), s});
  }
  double best = bound;
  int best_state = -1, best_sector = -1;
  while (!open.empty()) {
    const auto [key, s] = open.top();
    open.pop();
    if (key >= best) break;
    const int v = s / 2, bit = s % 2;
    const double dv = distance_[s];
    if (key > dv + heuristic(v) + 1e-12 * (1 + key)) continue;  // stale entry
    // Into the target.
    if (const int k = enter_sector(v); k >= 0 && !(loop && parent_[s] == kStart)) {
      const int final_bit = bit ^ crosses(v, target);
      if (!parity || !parity->odd[k] || final_bit == 1) {
        const double total = dv + step(v, target);
        if (total < best) best = total, best_state = s, best_sector = k;
      }
    }
    // A loop vertex other than the first step from a centre leads to the target only.
    const bool first_from_centre = source_centre && parent_[s] == kStart;
    if (class_[v] == VertexClass::boundary && !first_from_centre) continue;
    for (const auto w_handle : mesh_.vv_range(Mesh::VertexHandle(v))) {
      const int w = w_handle.idx();
      if (on_network_[w]) continue;
      if (class_[w] == VertexClass::boundary) {
        if (!target_centre || enter_sector(w) < 0) continue;
      } else if (class_[w] != VertexClass::interior) {
        continue;
      }
      const bool near = std::size_t(w) < near_network_.size() && near_network_[w];
      const double dw = dv + (near ? 2 : 1) * step(v, w);
      const int t = 2 * w + (bit ^ crosses(v, w));
      if (stamp_[t] != search_ || dw < distance_[t]) {
        stamp_[t] = search_;
        distance_[t] = dw;
        parent_[t] = s;
        open.push({dw + heuristic(w), t});
      }
    }
  }
  if (best_state < 0) return std::nullopt;
  TracedPath out;
  out.length = best;
  out.enter_sector = best_sector;
  out.vertices.push_back(target);
  out.sheet.push_back(char(best_state % 2 ^ crosses(best_state / 2, target)));
  for (int s = best_state; s != kStart; s = parent_[s]) {
    out.vertices.push_back(s / 2);
    out.sheet.push_back(char(s % 2));
  }
  out.vertices.push_back(source);
  out.sheet.push_back(0);
  std::reverse(out.vertices.begin(), out.vertices.end());
  std::reverse(out.sheet.begin(), out.sheet.end());
  // A path of the cover that passes a vertex on both sheets is not simple.
  std::vector<int> inner(out.vertices.begin() + 1, out.vertices.end() - 1);
  std::sort(inner.begin(), inner.end());
  out.simple = std::adjacent_find(inner.begin(), inner.end()) == inner.end();
  if (!out.simple && !allow_repeats) return std::nullopt;
  for (std::size_t k = 0; k < from.ring.size(); ++k)
    if (from.ring[k] == out.vertices[1]) out.leave_sector = from.sector[k];
  return out;
}

std::vector<EdgeSet> NetworkSurface::complement_cycles() const {
  const std::size_t n = mesh_.n_vertices();
  // Primal forest: every free vertex hangs from the network.
  EdgeSet tree;
  std::vector<char> seen(n, 0);
  std::vector<int> queue;
  for (std::size_t v = 0; v < n; ++v)
    if (on_network_[v]) seen[v] = 1, queue.push_back(int(v));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int v = queue[head];
    for (const auto w : mesh_.vv_range(Mesh::VertexHandle(v)))
      if (!seen[w.idx()]) {
        seen[w.idx()] = 1;
        tree.insert(undirected_edge_key(v, w.idx()));
        queue.push_back(w.idx());
      }
  }
  // Dual spanning forest across the edges on neither the network nor the tree.
  auto crossable = [&](int a, int b) {
    const auto key = undirected_edge_key(a, b);
    return !network_edges_.count(key) && !tree.count(key);
  };
  const std::size_t nf = mesh_.n_faces();
  std::vector<int> parent_face(nf, -1), depth(nf, -1);
  std::vector<std::uint64_t> parent_edge(nf, 0);
  EdgeSet cotree;
  std::vector<int> faces;
  for (std::size_t f0 = 0; f0 < nf; ++f0) {
    if (depth[f0] >= 0) continue;
    depth[f0] = 0;
    faces.assign(1, int(f0));
    for (std::size_t head = 0; head < faces.size(); ++head) {
      const auto f = Mesh::FaceHandle(faces[head]);
      for (const auto h : mesh_.fh_range(f)) {
        const int a = mesh_.from_vertex_handle(h).idx(), b = mesh_.to_vertex_handle(h).idx();
        if (!crossable(a, b)) continue;
        const int g = mesh_.face_handle(mesh_.opposite_halfedge_handle(h)).idx();
        if (depth[g] >= 0) continue;
        depth[g] = depth[f.idx()] + 1;
        parent_face[g] = f.idx();
        parent_edge[g] = undirected_edge_key(a, b);
        cotree.insert(parent_edge[g]);
        faces.push_back(g);
      }
    }
  }
  // Each edge left over closes one dual cycle through the cotree.
  std::vector<EdgeSet> cycles;
  for (const auto e : mesh_.edges()) {
    const auto h = mesh_.halfedge_handle(e, 0);
    const int a = mesh_.from_vertex_handle(h).idx(), b = mesh_.to_vertex_handle(h).idx();
    if (!crossable(a, b) || cotree.count(undirected_edge_key(a, b))) continue;
    EdgeSet crossing{undirected_edge_key(a, b)};
    int f = mesh_.face_handle(h).idx();
    int g = mesh_.face_handle(mesh_.opposite_halfedge_handle(h)).idx();
    while (f != g) {
      int& deeper = depth[f] >= depth[g] ? f : g;
      crossing.insert(parent_edge[deeper]);
      deeper = parent_face[deeper];
    }
    cycles.push_back(std::move(crossing));
  }
  return cycles;
}

std::vector<int> NetworkSurface::sides_of(const std::vector<int>& path,
                                          const std::vector<int>& vertices) {
  next_search(mesh_.n_vertices());
  // parent_ holds the side (+1, -1, 0 from an end) each vertex is reached from.
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  auto reach = [&](int w, double d, int side) {
    if (stamp_[w] == search_ && distance_[w] <= d) return;
    stamp_[w] = search_;
    distance_[w] = d;
    parent_[w] = side;
    open.push({d, w});
  };
  const std::unordered_set<int> on_path(path.begin(), path.end());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const int p = path[k];
    const bool end = k == 0 || k + 1 == path.size();
    // Counter-clockwise from the next path vertex, the left side comes
    // before the previous one.
    const std::vector<int> left =
        end ? std::vector<int>{} : ring_between(p, path[k + 1], path[k - 1]);
    for (int w : ring(p)) {
      if (on_path.count(w)) continue;
      const int side = end ? 0 : std::find(left.begin(), left.end(), w) != left.end() ? +1 : -1;
      reach(w, (positions_[w] - positions_[p]).norm(), side);
    }
  }
  std::unordered_set<int> wanted(vertices.begin(), vertices.end());
  for (int v : vertices)
    if (on_path.count(v)) wanted.erase(v);
  while (!open.empty() && !wanted.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > distance_[u]) continue;
    wanted.erase(u);
    for (const auto w_handle : mesh_.vv_range(Mesh::VertexHandle(u))) {
      const int w = w_handle.idx();
      if (!on_path.count(w)) reach(w, d + (positions_[w] - positions_[u]).norm(), parent_[u]);
    }
  }
  std::vector<int> out;
  for (int v : vertices) out.push_back(!on_path.count(v) && stamp_[v] == search_ ? parent_[v] : 0);
  return out;
}

TriangleMesh NetworkSurface::triangle_mesh() const {
  TriangleMesh out;
  out.positions = positions_;
  out.triangles.reserve(mesh_.n_faces());
  for (const auto f : mesh_.faces()) {
    Triangle t;
    int k = 0;
    for (const auto v : mesh_.fv_range(f)) t[k++] = v.idx();
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace ism::partition_detail
