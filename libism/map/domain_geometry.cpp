#include "map/domain_geometry.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

namespace ism {

namespace {

std::array<Vec2, 3> canonical_layout(const FaceLengths& l) {
  const double a = l[0], b = l[1], c = l[2];
  const double x = (a * a + c * c - b * b) / (2 * a);
  return {Vec2(0, 0), Vec2(a, 0), Vec2(x, std::sqrt(std::max(0.0, c * c - x * x)))};
}

// The point at distances rp from p and rq from q, left of p -> q.
Vec2 apex_left_of(const Vec2& p, const Vec2& q, double rp, double rq) {
  const Vec2 d = q - p;
  const double len = d.norm();
  const double x = (len * len + rp * rp - rq * rq) / (2 * len);
  const double y = std::sqrt(std::max(0.0, rp * rp - x * x));
  const Vec2 u = d / len;
  return p + x * u + y * Vec2(-u.y(), u.x());
}

}  // namespace

DomainGeometry::DomainGeometry(TriangleMesh connectivity, std::vector<FaceLengths> lengths)
    : mesh_(std::move(connectivity)), lengths_(std::move(lengths)) {
  const std::size_t nf = mesh_.n_faces();
  if (lengths_.size() != nf) throw std::invalid_argument("one set of edge lengths per face needed");
  layout_.resize(nf);
  area_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    layout_[f] = canonical_layout(lengths_[f]);
    area_[f] = 0.5 * orient(layout_[f][0], layout_[f][1], layout_[f][2]);
    if (!(area_[f] > 0)) throw std::invalid_argument("degenerate domain face " + std::to_string(f));
    total_area_ += area_[f];
  }
  std::map<std::pair<int, int>, std::pair<int, int>> directed;  // (u, w) -> (face, edge)
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      directed[{mesh_.triangles[f][k], mesh_.triangles[f][(k + 1) % 3]}] = {int(f), k};
  neighbour_.resize(nf);
  neighbour_edge_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      auto it = directed.find({mesh_.triangles[f][(k + 1) % 3], mesh_.triangles[f][k]});
      if (it == directed.end()) throw std::invalid_argument("the domain must be a closed manifold");
      neighbour_[f][k] = it->second.first;
      neighbour_edge_[f][k] = it->second.second;
      const double other = lengths_[it->second.first][it->second.second];
      if (std::abs(other - lengths_[f][k]) > 1e-9 * (other + lengths_[f][k]))
        throw std::invalid_argument("edge lengths differ between the two faces of an edge");
    }

  // Fans: walk counter-clockwise around each vertex starting at any face.
  fan_.assign(mesh_.n_vertices(), {});
  total_angle_.assign(mesh_.n_vertices(), 0.0);
  std::vector<char> started(mesh_.n_vertices(), 0);
  for (std::size_t f0 = 0; f0 < nf; ++f0)
    for (int c0 = 0; c0 < 3; ++c0) {
      const int v = mesh_.triangles[f0][c0];
      if (started[v]) continue;
      started[v] = 1;
      int f = int(f0), c = c0;
      double sum = 0.0;
      do {
        const auto& q = layout_[f];
        const Vec2 e1 = q[(c + 1) % 3] - q[c], e2 = q[(c + 2) % 3] - q[c];
        const double angle = std::atan2(e1.x() * e2.y() - e1.y() * e2.x(), e1.dot(e2));
        fan_[v].push_back({f, c, angle, sum});
        sum += angle;
        const int k = (c + 2) % 3;  // edge from corner c+2 back to v
        const int g = neighbour_[f][k];
        c = neighbour_edge_[f][k];
        f = g;
      } while (!(f == int(f0) && c == c0) && fan_[v].size() <= nf);
      total_angle_[v] = sum;
    }
}

void DomainGeometry::set_fixed(std::vector<char> fixed) {
  if (!fixed.empty() && fixed.size() != n_vertices())
    throw std::invalid_argument("DomainGeometry::set_fixed: one entry per vertex");
  fixed_ = std::move(fixed);
}

bool DomainGeometry::is_cone(int v) const {
  return std::abs(total_angle_[v] - 2 * M_PI) > 1e-9;
}

std::array<Vec2, 3> DomainGeometry::fan_layout(int v, int i, double extra_angle) const {
  const FanEntry& e = fan_[v][i];
  const FaceLengths& l = lengths_[e.face];
  const double a0 = e.start + extra_angle, a1 = a0 + e.angle;
  std::array<Vec2, 3> out;
  out[e.corner] = Vec2::Zero();
  out[(e.corner + 1) % 3] = l[e.corner] * Vec2(std::cos(a0), std::sin(a0));
  out[(e.corner + 2) % 3] = l[(e.corner + 2) % 3] * Vec2(std::cos(a1), std::sin(a1));
  return out;
}

std::array<Vec2, 3> DomainGeometry::unfold(int f, const std::array<Vec2, 3>& layout, int k) const {
  const int g = neighbour_[f][k], kk = neighbour_edge_[f][k];
  std::array<Vec2, 3> out;
  out[kk] = layout[(k + 1) % 3];
  out[(kk + 1) % 3] = layout[k];
  const FaceLengths& l = lengths_[g];
  // Third corner of g: distance l[(kk+2)%3] from corner kk, l[(kk+1)%3] from corner kk+1.
  out[(kk + 2) % 3] = apex_left_of(out[kk], out[(kk + 1) % 3], l[(kk + 2) % 3], l[(kk + 1) % 3]);
  return out;
}

std::vector<FaceLengths> octahedron_lengths(const TriangleMesh& octahedron, DomainMetric metric) {
  std::vector<FaceLengths> out(octahedron.n_faces());
  for (std::size_t f = 0; f < octahedron.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = octahedron.triangles[f][k], b = octahedron.triangles[f][(k + 1) % 3];
      const bool touches_pole = a >= 4 || b >= 4;  // vertices 4, 5 are ±z
      out[f][k] = metric == DomainMetric::equilateral ? 1.0 : (touches_pole ? 1.0 : std::sqrt(2.0));
    }
  return out;
}

std::vector<FaceLengths> torus_3x3_lengths(const TriangleMesh& torus) {
  std::vector<FaceLengths> out(torus.n_faces());
  for (std::size_t f = 0; f < torus.n_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = torus.triangles[f][k], b = torus.triangles[f][(k + 1) % 3];
      const int dr = (b / 3 - a / 3 + 3) % 3, dc = (b % 3 - a % 3 + 3) % 3;
      // Grid edges change one of row and column; the diagonals change both.
      const bool diagonal = dr != 0 && dc != 0;
      out[f][k] = (diagonal ? std::sqrt(2.0) : 1.0) / 3.0;
    }
  return out;
}

std::optional<std::array<int, 2>> DomainGeometry::find_face(const Triangle& corners) const {
  for (std::size_t f = 0; f < n_faces(); ++f) {
    const Triangle& t = mesh_.triangles[f];
    for (int r = 0; r < 3; ++r)
      if (corners[0] == t[r] && corners[1] == t[(r + 1) % 3] && corners[2] == t[(r + 2) % 3])
        return std::array<int, 2>{int(f), r};
  }
  return std::nullopt;
}

std::vector<FaceLengths> equilateral_lengths(const TriangleMesh& domain) {
  return std::vector<FaceLengths>(domain.n_faces(), FaceLengths{1.0, 1.0, 1.0});
}

}  // namespace ism
