#include "partition/bounded_base.hpp"

#include "partition/partition.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ism {
namespace {

using P2 = Eigen::Vector2d;

double cross2(const P2& a, const P2& b, const P2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// Smallest angle of the triangle (a, b, c).
double smallest_angle(const P2& a, const P2& b, const P2& c) {
  auto angle = [](const P2& o, const P2& u, const P2& v) {
    const P2 x = u - o, y = v - o;
    return std::atan2(std::abs(x.x() * y.y() - x.y() * y.x()), x.dot(y));
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

// A triangulation of a simple polygon (counter-clockwise) whose sides may
// carry collinear points, with no degenerate triangle and no new point:
// ears clipped best-shaped first, an ear being a convex corner whose
// triangle holds no other corner, never leaving an all-collinear rest.
std::vector<std::array<int, 3>> clip_ears(const std::vector<P2>& p) {
  const double scale = [&] {
    double s = 0;
    for (const P2& x : p) s = std::max(s, x.norm());
    return s * s;
  }();
  const double eps = 1e-12 * std::max(scale, 1e-300);
  std::vector<int> poly(p.size());
  std::iota(poly.begin(), poly.end(), 0);
  auto turns = [&](const std::vector<int>& q, std::size_t i) {
    const std::size_t n = q.size();
    return cross2(p[q[(i + n - 1) % n]], p[q[i]], p[q[(i + 1) % n]]) > eps;
  };
  auto corners = [&](const std::vector<int>& q) {
    int count = 0;
    for (std::size_t i = 0; i < q.size(); ++i) count += turns(q, i);
    return count;
  };
  // No other corner of q inside or on the triangle (a, b, c).
  auto empty = [&](const std::vector<int>& q, int a, int b, int c) {
    for (int v : q) {
      if (v == a || v == b || v == c) continue;
      if (cross2(p[a], p[b], p[v]) >= -eps && cross2(p[b], p[c], p[v]) >= -eps &&
          cross2(p[c], p[a], p[v]) >= -eps)
        return false;
    }
    return true;
  };
  std::vector<std::array<int, 3>> out;
  while (poly.size() > 3) {
    const std::size_t n = poly.size();
    std::size_t best = n;
    double best_angle = -1;
    for (std::size_t i = 0; i < n; ++i) {
      if (!turns(poly, i)) continue;
      const int a = poly[(i + n - 1) % n], b = poly[i], c = poly[(i + 1) % n];
      if (!empty(poly, a, b, c)) continue;
      std::vector<int> rest = poly;
      rest.erase(rest.begin() + std::ptrdiff_t(i));
      if (corners(rest) < 3) continue;
      const double angle = smallest_angle(p[a], p[b], p[c]);
      if (angle > best_angle) best_angle = angle, best = i;
    }
    if (best == n) throw std::logic_error("bounded_base: no ear to clip");
    out.push_back({poly[(best + n - 1) % n], poly[best], poly[(best + 1) % n]});
    poly.erase(poly.begin() + std::ptrdiff_t(best));
  }
  if (!turns(poly, 1)) throw std::logic_error("bounded_base: degenerate last triangle");
  out.push_back({poly[0], poly[1], poly[2]});
  return out;
}

// The unit equilateral layout of a base face: corner k at corner_point(k).
P2 corner_point(int k) {
  static const P2 c[3] = {P2(0, 0), P2(1, 0), P2(0.5, std::sqrt(3.0) / 2)};
  return c[k];
}

P2 point_of(const Eigen::Vector3d& bary) {
  return bary[0] * corner_point(0) + bary[1] * corner_point(1) + bary[2] * corner_point(2);
}

// A boundary edge of the base with this many surface boundary points
// between its ends gets an inner point fanning to them.
constexpr std::size_t kInnerFanPoints = 2;
// The inner point's place in the base face: this fraction of the way from
// the edge's middle to the opposite corner.
constexpr double kInnerDepth = 0.3;

// Surface vertices for inner points: an interior vertex of the surface a
// few rings in from a boundary vertex, not yet any domain vertex's.
class InnerPointPicker {
 public:
  InnerPointPicker(const TriangleMesh& surface, const CappedMesh& capped,
                   const std::vector<int>& features)
      : surface_(surface),
        neighbours_(capped.input_vertices),
        used_(surface.n_vertices(), 0),
        boundary_(surface.n_vertices(), 0) {
    for (std::size_t f = 0; f < capped.input_faces; ++f) {
      const Triangle& t = surface.triangles[f];
      for (int k = 0; k < 3; ++k) neighbours_[t[k]].push_back(t[(k + 1) % 3]);
    }
    for (const auto& loop : capped.loops)
      for (int v : loop) boundary_[v] = 1;
    for (int v : features) used_[v] = 1;
  }

  /// An unused interior vertex at kRings rings from boundary vertex b (or
  /// the deepest reachable), the one of its ring nearest to b; -1 if none.
  /// The vertex is then used.
  int pick(int b) {
    std::vector<int> layer{b}, seen{b};
    int best = -1;
    for (int ring = 1; ring <= kRings && !layer.empty(); ++ring) {
      std::vector<int> next;
      for (int v : layer)
        for (int w : neighbours_[v])
          if (!boundary_[w] && std::find(seen.begin(), seen.end(), w) == seen.end())
            next.push_back(w), seen.push_back(w);
      double nearest = HUGE_VAL;
      int chosen = -1;
      for (int w : next) {
        const double d = (surface_.positions[w] - surface_.positions[b]).norm();
        if (!used_[w] && d < nearest) nearest = d, chosen = w;
      }
      if (chosen >= 0) best = chosen;
      layer = std::move(next);
    }
    if (best >= 0) used_[best] = 1;
    return best;
  }

 private:
  static constexpr int kRings = 2;
  const TriangleMesh& surface_;
  std::vector<std::vector<int>> neighbours_;
  std::vector<char> used_, boundary_;
};

}  // namespace

std::vector<std::array<int, 2>> BoundedBase::cap_edges() const {
  std::vector<std::array<int, 2>> out;
  for (std::size_t f = 0; f < domain.n_faces(); ++f)
    if (cap_face[f]) {
      const Triangle& t = domain.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        out.push_back({std::min(a, b), std::max(a, b)});
      }
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::pair<int, Eigen::Vector3d> BoundedBase::locate(int f, const Eigen::Vector3d& bary) const {
  const P2 x = point_of(bary);
  int best = -1;
  double best_min = -HUGE_VAL;
  Eigen::Vector3d best_bary = Eigen::Vector3d::Zero();
  for (const Piece& piece : pieces.at(std::size_t(f))) {
    const P2 a = point_of(piece.corners[0]), b = point_of(piece.corners[1]),
             c = point_of(piece.corners[2]);
    const double area = cross2(a, b, c);
    const Eigen::Vector3d w(cross2(x, b, c) / area, cross2(a, x, c) / area, cross2(a, b, x) / area);
    if (w.minCoeff() > best_min) best_min = w.minCoeff(), best = piece.face, best_bary = w;
  }
  if (best < 0) throw std::logic_error("bounded_base: a base face without pieces");
  best_bary = best_bary.cwiseMax(0.0);
  best_bary /= best_bary.sum();
  return {best, best_bary};
}

BoundedBase bounded_base(const TriangleMesh& base, const std::vector<int>& features,
                         const CappedMesh& capped) {
  const std::size_t nb = base.n_vertices();
  const TriangleMesh& surface = capped.mesh;
  if (features.size() != nb)
    throw PartitionError(std::to_string(features.size()) + " features for a base of " +
                         std::to_string(nb) + " vertices");
  for (int v : features)
    if (v < 0 || std::size_t(v) >= capped.input_vertices)
      throw PartitionError("a base vertex's surface vertex " + std::to_string(v) +
                           " is out of range");
  std::vector<std::vector<int>> base_loops;
  try {
    base_loops = boundary_loops(base);
  } catch (const std::invalid_argument& e) {
    throw PartitionError(std::string("the base's boundary: ") + e.what());
  }
  const std::size_t nloops = capped.loops.size();
  auto loops_word = [](std::size_t n) {
    return std::to_string(n) + (n == 1 ? " boundary loop" : " boundary loops");
  };
  if (base_loops.size() != nloops)
    throw PartitionError("the base has " + loops_word(base_loops.size()) + ", the surface " +
                         loops_word(nloops));

  // Where each surface vertex is on the surface's loops.
  std::vector<int> loop_of(surface.n_vertices(), -1), position(surface.n_vertices(), -1);
  for (std::size_t j = 0; j < nloops; ++j)
    for (std::size_t k = 0; k < capped.loops[j].size(); ++k)
      loop_of[capped.loops[j][k]] = int(j), position[capped.loops[j][k]] = int(k);
  std::vector<char> on_base_boundary(nb, 0);
  for (const auto& loop : base_loops)
    for (int v : loop) on_base_boundary[v] = 1;
  for (std::size_t i = 0; i < nb; ++i) {
    const bool on_surface_boundary = loop_of[features[i]] >= 0;
    if (on_surface_boundary != bool(on_base_boundary[i]))
      throw PartitionError("base vertex " + std::to_string(i) + " is " +
                           (on_base_boundary[i] ? "on the base's boundary but its surface vertex " +
                                                      std::to_string(features[i]) + " is not on "
                                                : "inside the base but its surface vertex " +
                                                      std::to_string(features[i]) + " is on ") +
                           "the surface's boundary");
  }

  BoundedBase out;
  out.domain.positions = base.positions;
  out.features = features;
  out.fixed.assign(nb, 0);
  for (std::size_t i = 0; i < nb; ++i) out.fixed[i] = on_base_boundary[i];
  // Per surface loop, its domain vertices in loop order and the length (in
  // the base's metric) of the loop edge after each.
  std::vector<std::vector<int>> domain_loop(nloops);
  std::vector<std::vector<double>> edge_after(nloops);
  // Boundary half-edge (a, b) of the base (loop direction) -> the domain
  // vertices between a and b and their fractions of the way from a.
  std::map<std::pair<int, int>, std::vector<std::pair<int, double>>> edge_points;
  std::vector<int> surface_loop_used(nloops, -1);
  // Input edges joining two vertices of one loop that are not neighbours
  // along it: a base boundary edge spanning both ends would put the faces
  // between them on one straight line of the domain.
  std::vector<std::pair<int, int>> bridges;
  for (std::size_t f = 0; f < capped.input_faces; ++f) {
    const Triangle& t = surface.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a > b || loop_of[a] < 0 || loop_of[a] != loop_of[b]) continue;
      const int n = int(capped.loops[std::size_t(loop_of[a])].size());
      const int d = (position[b] - position[a] + n) % n;
      if (d != 1 && d != n - 1) bridges.emplace_back(a, b);
    }
  }
  for (std::size_t bl = 0; bl < base_loops.size(); ++bl) {
    const std::vector<int>& L = base_loops[bl];
    const int j = loop_of[features[L[0]]];
    for (int v : L)
      if (loop_of[features[v]] != j)
        throw PartitionError("base boundary loop " + std::to_string(bl) +
                             " runs over two of the surface's boundary loops");
    if (surface_loop_used[j] >= 0)
      throw PartitionError("base boundary loops " + std::to_string(surface_loop_used[j]) + " and " +
                           std::to_string(bl) + " both lie on surface boundary loop " +
                           std::to_string(j));
    surface_loop_used[j] = int(bl);
    const std::vector<int>& S = capped.loops[j];
    const std::size_t n = S.size(), m = L.size();
    std::size_t total = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const int pa = position[features[L[k]]], pb = position[features[L[(k + 1) % m]]];
      total += std::size_t((pb - pa + int(n)) % int(n));
    }
    if (total != n)
      throw PartitionError("base boundary loop " + std::to_string(bl) +
                           " follows the surface's boundary loop " + std::to_string(j) +
                           " in another order or direction");
    domain_loop[j].assign(n, -1);
    edge_after[j].assign(n, 0.0);
    for (std::size_t k = 0; k < m; ++k) {
      const int a = L[k], b = L[(k + 1) % m];
      const int pa = position[features[a]];
      const int steps = (position[features[b]] - pa + int(n)) % int(n);
      for (const auto& [u, w] : bridges)
        if (loop_of[u] == j && (position[u] - pa + int(n)) % int(n) <= steps &&
            (position[w] - pa + int(n)) % int(n) <= steps)
          throw PartitionError("the base's boundary edge from surface vertex " +
                               std::to_string(features[a]) + " to " + std::to_string(features[b]) +
                               " spans the surface edge " + std::to_string(u) + "-" +
                               std::to_string(w) +
                               " across its boundary loop: the faces between would have no "
                               "area; give the base a boundary vertex between them");
      std::vector<double> arc(std::size_t(steps) + 1, 0.0);
      for (int s = 1; s <= steps; ++s)
        arc[s] =
            arc[s - 1] +
            (surface.positions[S[(pa + s) % n]] - surface.positions[S[(pa + s - 1) % n]]).norm();
      const double length = arc.back() > 0 ? arc.back() : 1.0;
      auto& points = edge_points[{a, b}];
      domain_loop[j][pa] = a;
      for (int s = 1; s < steps; ++s) {
        const int id = int(out.domain.positions.size());
        const int sv = S[(pa + s) % n];
        out.domain.positions.push_back(surface.positions[sv]);
        out.features.push_back(sv);
        out.fixed.push_back(1);
        points.emplace_back(id, arc[s] / length);
        domain_loop[j][(pa + s) % n] = id;
      }
      for (int s = 0; s < steps; ++s) edge_after[j][(pa + s) % n] = (arc[s + 1] - arc[s]) / length;
    }
  }
  out.boundary_points = out.domain.positions.size() - nb;

  // Base faces, triangulated over the points on their boundary edges. An
  // edge with kInnerFanPoints or more points gets an inner point: a domain
  // vertex inside the face, a few rings in from the surface boundary's
  // middle between the edge's ends, which fans to the edge's points. Fanned
  // from the opposite corner instead, the paths from that corner to
  // consecutive boundary vertices run side by side over most of the patch,
  // each splitting the faces the previous ones left (venus_loop2: tracer
  // meshes of 4x the surface, and maps too thin for double precision).
  InnerPointPicker picker(surface, capped, out.features);
  out.pieces.resize(base.n_faces());
  for (std::size_t f = 0; f < base.n_faces(); ++f) {
    const Triangle& t = base.triangles[f];
    // The face's points: its corners first, then boundary and inner points;
    // triangles index them.
    std::vector<int> ids(t.begin(), t.end());
    std::vector<Eigen::Vector3d> barys(3, Eigen::Vector3d::Zero());
    for (int k = 0; k < 3; ++k) barys[k][k] = 1;
    auto add = [&](int id, const Eigen::Vector3d& b) {
      ids.push_back(id), barys.push_back(b);
      return int(ids.size()) - 1;
    };
    std::vector<std::array<int, 3>> fans;
    std::vector<int> rest;  // the polygon left after the inner points' fans
    for (int k = 0; k < 3; ++k) {
      const int x = t[k], y = t[(k + 1) % 3];
      rest.push_back(k);
      // The face holds x -> y, so the boundary runs y -> x.
      const auto it = edge_points.find({y, x});
      if (it == edge_points.end()) continue;
      std::vector<int> run{k};  // x, the points from x to y, y
      std::size_t middle = 0;   // the point of the run nearest the edge's middle
      double off_middle = HUGE_VAL;
      for (auto q = it->second.rbegin(); q != it->second.rend(); ++q) {
        const double s = 1.0 - q->second;  // fraction from x
        if (std::abs(s - 0.5) < off_middle) off_middle = std::abs(s - 0.5), middle = run.size();
        run.push_back(add(q->first, (1 - s) * barys[k] + s * barys[(k + 1) % 3]));
      }
      run.push_back((k + 1) % 3);
      const std::size_t points = run.size() - 2;
      const int inner =
          points >= kInnerFanPoints ? picker.pick(out.features[ids[run[middle]]]) : -1;
      if (inner < 0) {
        rest.insert(rest.end(), run.begin() + 1, run.end() - 1);
        continue;
      }
      // Above the edge's middle, picked from the boundary point nearest to
      // it (by arc length): picked from the middle point by count instead,
      // the fan, and the map, were sheared along the boundary by the
      // distance between the two (a quarter of the edge on bunny_open).
      const Eigen::Vector3d mid = 0.5 * (barys[k] + barys[(k + 1) % 3]);
      const int d =
          add(int(out.domain.positions.size()), mid + kInnerDepth * (barys[(k + 2) % 3] - mid));
      out.domain.positions.push_back(surface.positions[inner]);
      out.features.push_back(inner);
      out.fixed.push_back(0);
      ++out.inner_points;
      for (std::size_t i = 0; i + 1 < run.size(); ++i) fans.push_back({run[i], run[i + 1], d});
      rest.push_back(d);
    }
    auto emit = [&](const std::array<int, 3>& e) {
      const int id = int(out.domain.triangles.size());
      out.domain.triangles.push_back({ids[e[0]], ids[e[1]], ids[e[2]]});
      std::array<double, 3> l;
      for (int k = 0; k < 3; ++k)
        l[k] = (point_of(barys[e[(k + 1) % 3]]) - point_of(barys[e[k]])).norm();
      out.lengths.push_back(l);
      out.cap_face.push_back(0);
      out.pieces[f].push_back({id, {barys[e[0]], barys[e[1]], barys[e[2]]}});
    };
    for (const auto& tri : fans) emit(tri);
    if (rest.size() == 3) {
      emit({rest[0], rest[1], rest[2]});
      continue;
    }
    std::vector<P2> polygon;
    for (int i : rest) polygon.push_back(point_of(barys[i]));
    for (const auto& e : clip_ears(polygon)) emit({rest[e[0]], rest[e[1]], rest[e[2]]});
  }

  // Caps: a fan with equal spokes R per loop, R such that the angles at the
  // centre sum to 2π when the boundary lengths allow it.
  for (std::size_t j = 0; j < nloops; ++j) {
    const int centre = int(out.domain.positions.size());
    out.domain.positions.push_back(surface.positions[capped.centre(j)]);
    out.features.push_back(capped.centre(j));
    out.fixed.push_back(1);
    const std::vector<double>& l = edge_after[j];
    const double longest = *std::max_element(l.begin(), l.end());
    auto centre_angle = [&](double R) {
      double sum = 0;
      for (double x : l) sum += 2 * std::asin(std::min(1.0, x / (2 * R)));
      return sum;
    };
    double R = 0.5 * longest * 1.05;
    if (centre_angle(R) > 2 * std::numbers::pi) {
      double lo = R, hi = R;
      while (centre_angle(hi) > 2 * std::numbers::pi) hi *= 2;
      for (int it = 0; it < 100; ++it) {
        const double mid = 0.5 * (lo + hi);
        (centre_angle(mid) > 2 * std::numbers::pi ? lo : hi) = mid;
      }
      R = hi;
    }
    const std::vector<int>& dl = domain_loop[j];
    for (std::size_t k = 0; k < dl.size(); ++k) {
      out.domain.triangles.push_back({dl[k], dl[(k + 1) % dl.size()], centre});
      out.lengths.push_back({l[k], R, R});
      out.cap_face.push_back(1);
    }
  }
  return out;
}

}  // namespace ism
