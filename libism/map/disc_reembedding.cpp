// Local re-embedding of a disc of M² (paper §5.1): several vertices placed
// at once. The faces around the free vertices are laid out in one chart by
// gluing their face charts along shared edges (rigid motions: each chart is
// an isometric unfolding of M¹); an optimiser (refine/) moves the free
// vertices in that chart; then they are located in M¹ and their edges
// re-traced as straight segments of the chart.
#include "map/surface_map.hpp"
#include "mesh/edge_key.hpp"
#include "mesh/face_adjacency.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <unordered_map>

namespace ism {

namespace {

// A rotation and translation of the plane.
struct RigidMotion {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Vec2 translation = Vec2::Zero();
  Vec2 operator()(const Vec2& p) const { return rotation * p + translation; }
  std::array<Vec2, 3> operator()(const std::array<Vec2, 3>& t) const {
    return {(*this)(t[0]), (*this)(t[1]), (*this)(t[2])};
  }
};

// The motion taking a to A and b to B (|b − a| = |B − A| up to rounding).
RigidMotion aligning(const Vec2& a, const Vec2& b, const Vec2& A, const Vec2& B) {
  const Vec2 d = b - a, D = B - A;
  const double angle = std::atan2(D.y(), D.x()) - std::atan2(d.y(), d.x());
  RigidMotion m;
  m.rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  m.translation = A - m.rotation * a;
  return m;
}

// Local half-edges (a, b) -> (local face, corner of a).
std::unordered_map<std::uint64_t, std::pair<int, int>> half_edges(
    const std::vector<Triangle>& faces) {
  std::unordered_map<std::uint64_t, std::pair<int, int>> out;
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k)
      out[directed_edge_key(faces[i][k], faces[i][(k + 1) % 3])] = {int(i), k};
  return out;
}

}  // namespace

std::optional<DiscLayout> SurfaceMap::disc_layout(const std::vector<int>& vertices) const {
  DiscLayout disc;
  std::unordered_map<int, int> local;  // map vertex -> local vertex
  local.reserve(8 * vertices.size());
  auto local_vertex = [&](int v, bool is_free) {
    const auto [it, inserted] = local.try_emplace(v, int(disc.vertex.size()));
    if (inserted) {
      disc.vertex.push_back(v);
      disc.free.push_back(is_free);
      disc.position.push_back(Vec2::Zero());
    }
    return it->second;
  };
  for (int v : vertices) {
    if (vertex_faces_[v].empty() || pinned_[v]) continue;
    const int x = at_domain_vertex_[v];
    if (x < 0 || !domain_.is_cone(x)) local_vertex(v, true);
  }
  if (disc.vertex.empty()) return std::nullopt;
  for (std::size_t i = 0, n = disc.vertex.size(); i < n; ++i)
    disc.face.insert(disc.face.end(), vertex_faces_[disc.vertex[i]].begin(),
                     vertex_faces_[disc.vertex[i]].end());
  std::sort(disc.face.begin(), disc.face.end());
  disc.face.erase(std::unique(disc.face.begin(), disc.face.end()), disc.face.end());
  const std::size_t n = disc.face.size();
  for (int f : disc.face)
    disc.local.push_back({local_vertex(faces_[f][0], false), local_vertex(faces_[f][1], false),
                          local_vertex(faces_[f][2], false)});

  // One chart for all faces: glue the face charts along shared edges.
  std::vector<FaceChart> chart(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!face_chart(disc.face[i], chart[i])) return std::nullopt;
  const std::vector<std::array<FaceAcross, 3>> across = faces_across(disc.local);
  std::vector<RigidMotion> motion(n);
  std::vector<char> placed(n, 0);
  for (std::size_t root = 0; root < n; ++root) {
    if (placed[root]) continue;
    placed[root] = 1;  // each connected part keeps its root's chart
    std::deque<int> queue{int(root)};
    while (!queue.empty()) {
      const int i = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const auto [j, kj] = across[std::size_t(i)][std::size_t(k)];
        if (j < 0 || placed[j]) continue;
        motion[j] =
            aligning(chart[j].corner[(kj + 1) % 3], chart[j].corner[kj],
                     motion[i](chart[i].corner[k]), motion[i](chart[i].corner[(k + 1) % 3]));
        placed[j] = 1;
        queue.push_back(j);
      }
    }
  }
  // Every vertex must land at one place from all its faces: otherwise the
  // region wraps around a cone and has no flat chart.
  double scale = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      scale = std::max(scale, (chart[i].corner[(k + 1) % 3] - chart[i].corner[k]).norm());
  std::vector<char> seen(disc.vertex.size(), 0);
  disc.walk_face.resize(n);
  disc.walk_layout.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const int u = disc.local[i][k];
      const Vec2 p = motion[i](chart[i].corner[k]);
      if (seen[u] && (disc.position[u] - p).norm() > 1e-8 * scale) return std::nullopt;
      seen[u] = 1;
      disc.position[u] = p;
      disc.walk_face[i][k] = walks_[disc.face[i]][k].start_face;
      disc.walk_layout[i][k] = motion[i](chart[i].walk_layout[k]);
    }
  return disc;
}

double SurfaceMap::set_disc_layout(const DiscLayout& disc) {
  std::vector<int> moving;
  for (std::size_t u = 0; u < disc.vertex.size(); ++u)
    if (disc.free[u]) moving.push_back(disc.vertex[u]);
  const RegionState saved = save_region(moving);
  const double before = faces_energy(disc.face);
  auto restore = [&] {
    restore_region(saved);
    return 0.0;
  };
  // Where a walk from corner k of face i starts, in the chart: for a fixed
  // vertex where the face's old walk started (around an M¹ vertex,
  // trace_from turns to the new direction from there), for a free one where
  // it has been located. Free vertices are located breadth first from the
  // fixed ones along the new edges, which lie in the flat region.
  struct Start {
    int face = -1;
    std::array<Vec2, 3> layout;
  };
  std::vector<Start> located(disc.vertex.size());
  auto start_of = [&](int i, int k) {
    const int u = disc.local[i][k];
    return disc.free[u] ? located[u] : Start{disc.walk_face[i][k], disc.walk_layout[i][k]};
  };
  const auto half_edge = half_edges(disc.local);
  std::unordered_map<int, int> local;  // map vertex -> local vertex
  for (std::size_t u = 0; u < disc.vertex.size(); ++u) local[disc.vertex[u]] = int(u);
  std::deque<int> queue;
  for (std::size_t u = 0; u < disc.vertex.size(); ++u)
    if (!disc.free[u]) queue.push_back(int(u));
  std::size_t reached = 0;
  while (!queue.empty()) {
    const int u = queue.front();
    queue.pop_front();
    for (int w : neighbours(disc.vertex[u])) {
      const auto it = local.find(w);
      if (it == local.end()) continue;
      const int lw = it->second;
      if (!disc.free[lw] || located[lw].face >= 0) continue;
      const auto [i, k] = half_edge.at(directed_edge_key(u, lw));
      const Start s = start_of(i, k);
      EdgeWalk walk;
      WalkEnd end;
      if (!trace_from(disc.vertex[u], s.face, s.layout, disc.position[lw], walk, end))
        return restore();
      set_location(w, end.face, end.layout, disc.position[lw]);
      located[lw] = {end.face, end.layout};
      ++reached;
      queue.push_back(lw);
    }
  }
  if (reached != moving.size()) return restore();

  // Re-trace every edge with a free end, and its twin as the reverse walk.
  auto lands_on = [&](int u, int face) {
    const int x = at_domain_vertex_[u];
    if (x < 0) return face == location_[u].face;
    const Triangle& d = domain_.mesh().triangles[face];
    return d[0] == x || d[1] == x || d[2] == x;
  };
  std::vector<std::pair<std::pair<int, int>, EdgeWalk>> traced;
  for (std::size_t i = 0; i < disc.face.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int u = disc.local[i][k], w = disc.local[i][(k + 1) % 3];
      // Both faces of such an edge are in the disc: trace it once.
      if ((!disc.free[u] && !disc.free[w]) || u > w) continue;
      const Vec2 to = disc.free[w] ? position_in(disc.vertex[w], located[w].face, located[w].layout)
                                   : disc.position[w];
      const Start s = start_of(int(i), k);
      EdgeWalk walk;
      WalkEnd end;
      if (!trace_from(disc.vertex[u], s.face, s.layout, to, walk, end) ||
          !lands_on(disc.vertex[w], end.face))
        return restore();
      traced.push_back({{int(i), k}, walk});
    }
  for (const auto& [where, walk] : traced) {
    const auto [i, k] = where;
    walks_[disc.face[i]][k] = walk;
    const auto [j, kj] =
        half_edge.at(directed_edge_key(disc.local[i][(k + 1) % 3], disc.local[i][k]));
    walks_[disc.face[j]][kj] = reversed(walk);
  }
  if (!faces_are_valid(disc.face)) return restore();
  const double after = faces_energy(disc.face);
  // A drop within rounding (a layout put back where it was moves its
  // vertices' barycentric coordinates by an ulp) is no drop.
  if (!(after < before - 1e-12 * before)) return restore();
  return before - after;
}

}  // namespace ism
