// Flat-torus layouts of the map: on a domain that is the unit square with
// opposite sides identified (no cones), the map at any level is a
// parametrisation of M² over R²/Z²: a point per vertex and, per face, the
// lift of its corners into the plane. Reading the map as such a layout and
// installing a layout (new vertex locations, straight walks between the
// lifted corners) let a global solver move every vertex at once.
#include "map/surface_map.hpp"

#include <cmath>

namespace ism {

std::optional<std::vector<std::array<Vec2, 3>>> unit_square_layouts(const DomainGeometry& domain) {
  if (std::abs(domain.total_area() - 1.0) > 1e-9) return std::nullopt;
  const TriangleMesh& mesh = domain.mesh();
  for (std::size_t x = 0; x < domain.n_vertices(); ++x) {
    if (domain.is_cone(int(x))) return std::nullopt;
    const Vec3& p = mesh.positions[x];
    if (!(p.x() >= 0 && p.x() < 1 && p.y() >= 0 && p.y() < 1)) return std::nullopt;
  }
  std::vector<std::array<Vec2, 3>> out(domain.n_faces());
  for (std::size_t f = 0; f < domain.n_faces(); ++f) {
    const Triangle& t = mesh.triangles[f];
    const Vec2 p0 = mesh.positions[t[0]].head<2>();
    out[f][0] = p0;
    for (int k = 1; k < 3; ++k) {
      Vec2 d = mesh.positions[t[k]].head<2>() - p0;
      d -= d.array().round().matrix();  // the nearest copy of the corner
      out[f][k] = p0 + d;
    }
    if (!(orient(out[f][0], out[f][1], out[f][2]) > 0)) return std::nullopt;
    for (int k = 0; k < 3; ++k) {
      const double length = (out[f][(k + 1) % 3] - out[f][k]).norm();
      if (std::abs(length - domain.lengths(int(f))[k]) > 1e-9) return std::nullopt;
    }
  }
  return out;
}

bool SurfaceMap::is_free_flat_torus() const {
  if (!unit_square_layouts(domain_)) return false;
  for (std::size_t v = 0; v < pinned_.size(); ++v)
    if (pinned_[v] && !vertex_faces_[v].empty()) return false;
  return true;
}

std::optional<FlatTorusLayout> SurfaceMap::flat_layout() const {
  const auto square = unit_square_layouts(domain_);
  if (!square || !is_free_flat_torus()) return std::nullopt;
  FlatTorusLayout out;
  out.position.assign(positions_.size(), Vec2::Zero());
  out.shift.resize(faces_.size());
  for (std::size_t v = 0; v < positions_.size(); ++v) {
    if (vertex_faces_[v].empty()) continue;
    const int x = at_domain_vertex_[v];
    Vec2 p;
    if (x >= 0) {
      p = domain_.mesh().positions[x].head<2>();
    } else {
      const auto& layout = (*square)[location_[v].face];
      const Eigen::Vector3d& b = location_[v].bary;
      p = from_barycentric(b, layout);
    }
    out.position[v] = p - p.array().floor().matrix();
  }
  FaceChart chart;
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    if (!face_chart(int(t), chart)) return std::nullopt;
    // The rigid motion taking the chart's start face onto its place in the
    // unit square (both are congruent copies of the face).
    const auto& s = (*square)[chart.start_face];
    const Vec2 a = chart.start_layout[1] - chart.start_layout[0], b = s[1] - s[0];
    const double scale = a.norm() * b.norm();
    const double cos = a.dot(b) / scale, sin = (a.x() * b.y() - a.y() * b.x()) / scale;
    Eigen::Matrix2d rotation;
    rotation << cos, -sin, sin, cos;
    const Vec2 translation = s[0] - rotation * chart.start_layout[0];
    for (int c = 0; c < 3; ++c) {
      const Vec2 q = rotation * chart.corner[c] + translation;
      const Vec2 d = q - out.position[faces_[t][c]];
      const Vec2 n = d.array().round().matrix();
      if ((d - n).norm() > 1e-6) return std::nullopt;
      out.shift[t][c] = n.cast<int>();
    }
  }
  return out;
}

double SurfaceMap::layout_energy(const FlatTorusLayout& layout) const {
  double sum = 0.0;
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    const Vec2 a = layout.corner(faces_, int(t), 0), b = layout.corner(faces_, int(t), 1),
               c = layout.corner(faces_, int(t), 2);
    sum += face_energy(int(t), a, b, c);
    if (sum == HUGE_VAL) return sum;
  }
  return sum;
}

bool SurfaceMap::set_flat_layout(const FlatTorusLayout& layout, double max_energy) {
  const auto square = unit_square_layouts(domain_);
  if (!square || !is_free_flat_torus()) return false;
  if (layout.position.size() != positions_.size() || layout.shift.size() != faces_.size())
    return false;
  for (std::size_t t = 0; t < faces_.size(); ++t)
    if (!(orient(layout.corner(faces_, int(t), 0), layout.corner(faces_, int(t), 1),
                 layout.corner(faces_, int(t), 2)) > 0))
      return false;

  const std::vector<DomainLocation> old_location = location_;
  const std::vector<int> old_at = at_domain_vertex_;
  const std::vector<std::array<EdgeWalk, 3>> old_walks = walks_;
  auto restore = [&] {
    location_ = old_location;
    at_domain_vertex_ = old_at;
    walks_ = old_walks;
    return false;
  };

  // Locate every vertex: the face (in some copy of the unit square near its
  // position) whose barycentric coordinates are least negative.
  std::vector<std::array<Vec2, 3>> placed(positions_.size());  // its face, near its position
  std::vector<Vec2> point(positions_.size(), Vec2::Zero());    // where it is after set_location
  for (std::size_t v = 0; v < positions_.size(); ++v) {
    if (vertex_faces_[v].empty()) continue;
    const Vec2 p = layout.position[v];
    if (!p.allFinite()) return restore();
    const Vec2 base = p.array().floor().matrix();
    int best_face = -1;
    double best = -HUGE_VAL;
    std::array<Vec2, 3> best_layout;
    for (std::size_t f = 0; f < square->size(); ++f)
      for (int sx = -1; sx <= 0; ++sx)
        for (int sy = -1; sy <= 0; ++sy) {
          std::array<Vec2, 3> l = (*square)[f];
          for (Vec2& q : l) q += base + Vec2(sx, sy);
          const double m = barycentric(p, l[0], l[1], l[2]).minCoeff();
          if (m > best) best = m, best_face = int(f), best_layout = l;
        }
    if (best < -1e-9) return restore();
    set_location(int(v), best_face, best_layout, p);
    placed[v] = best_layout;
    const Eigen::Vector3d& b = location_[v].bary;
    point[v] = from_barycentric(b, best_layout);
  }

  // Every M² edge as the straight segment between its lifted corners,
  // traced once from one side; the other half-edge is its reverse.
  std::vector<std::array<char, 3>> done(faces_.size(), {0, 0, 0});
  for (std::size_t t = 0; t < faces_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (done[t][k]) continue;
      const int u = faces_[t][k], w = faces_[t][(k + 1) % 3];
      // The lifts of u and w in this face, moved by whole periods from
      // where they were located.
      const Vec2 lift_u = layout.corner(faces_, int(t), k),
                 lift_w = layout.corner(faces_, int(t), (k + 1) % 3);
      const Vec2 shift_u = (lift_u - point[u]).array().round().matrix();
      const Vec2 shift_w = (lift_w - point[w]).array().round().matrix();
      std::array<Vec2, 3> start = placed[u];
      for (Vec2& q : start) q += shift_u;
      EdgeWalk walk;
      WalkEnd end;
      if (!trace(location_[u].face, start, point[u] + shift_u, point[w] + shift_w, walk, end) ||
          end.face != location_[w].face)
        return restore();
      walks_[t][k] = walk;
      done[t][k] = 1;
      const int twin = face_after(w, u);
      if (twin < 0) return restore();
      const int c = corner_of(twin, w);
      walks_[twin][c] = reversed(walk);
      done[twin][c] = 1;
    }
  if (validate() || !(energy() < max_energy)) return restore();
  return true;
}

}  // namespace ism
