#include "map/surface_map.hpp"

#include "map/meta_cut.hpp"  // CornerStretch
#include "mesh/curvature.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <stdexcept>

namespace ism {

namespace {

constexpr double kInside = -1e-10;  // barycentric tolerance of point-in-face tests
// Vertices of M² are kept this far inside their M¹ face (in barycentric
// terms), so that no vertex lies on an M¹ edge and crossings stay distinct.
constexpr double kInteriorBary = 1e-9;

}  // namespace

// ---------------------------------------------------------------- set-up

SurfaceMap::SurfaceMap(const DomainGeometry& domain, const ProgressiveMesh& pm, MapOptions options)
    : domain_(domain), pm_(pm), options_(options) {
  const std::size_t n = pm.base.n_vertices();
  positions_ = pm.base.positions;
  vertex_faces_.assign(n, {});
  location_.assign(n, {});
  at_domain_vertex_.assign(n, -1);
  pinned_.assign(n, 0);
  if (pm.base_vertices.size() != domain.n_vertices())
    throw std::invalid_argument("the base mesh and the domain have different vertex counts");
  if (options_.curvature_weight > 0)
    forward_density_ = curvature_density(replay(pm), options_.curvature_weight);

  std::vector<int> domain_vertex_of(n, -1);
  for (std::size_t i = 0; i < pm.base_vertices.size(); ++i) {
    const int v = pm.base_vertices[i];
    domain_vertex_of[v] = int(i);
    at_domain_vertex_[v] = int(i);
    const auto& entry = domain.fan(int(i)).front();
    location_[v].face = entry.face;
    location_[v].bary = Eigen::Vector3d::Zero();
    location_[v].bary[entry.corner] = 1.0;
    pinned_[v] = domain.is_cone(int(i)) || is_fixed(int(i)) || !options_.release_features;
  }
  for (const Triangle& t : pm.base.triangles) {
    const auto found =
        domain.find_face({domain_vertex_of[t[0]], domain_vertex_of[t[1]], domain_vertex_of[t[2]]});
    if (!found) throw std::invalid_argument("base face is not a domain face");
    const int f = int(faces_.size());
    add_face(t);
    // Each base half-edge runs along a domain edge: it is kept in the domain
    // face on its left, the face it bounds.
    for (int k = 0; k < 3; ++k) walks_[f][k].start_face = (*found)[0];
  }
  active_vertices_ = pm.base_vertices.size();
}

double SurfaceMap::surface_face_area(int f) const {
  const Triangle& t = faces_[f];
  return 0.5 *
         (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]).norm();
}

void SurfaceMap::move_corner(int f, int corner, int to) {
  const int from = faces_[f][corner];
  surface_area_ -= surface_face_area(f);
  faces_[f][corner] = to;
  surface_area_ += surface_face_area(f);
  std::erase(vertex_faces_[from], f);
  vertex_faces_[to].push_back(f);
}

void SurfaceMap::add_face(const Triangle& t) {
  const int f = int(faces_.size());
  faces_.push_back(t);
  walks_.push_back({});
  for (int v : t) vertex_faces_[v].push_back(f);
  surface_area_ += surface_face_area(f);
}

int SurfaceMap::corner_of(int f, int v) const {
  const Triangle& t = faces_[f];
  return t[0] == v ? 0 : t[1] == v ? 1 : 2;
}

int SurfaceMap::face_after(int v, int x) const {
  for (int f : vertex_faces_[v])
    if (faces_[f][(corner_of(f, v) + 1) % 3] == x) return f;
  return -1;
}

std::vector<int> SurfaceMap::neighbours(int v) const {
  std::vector<int> out;
  if (vertex_faces_[v].empty()) return out;
  const int f0 = vertex_faces_[v].front();
  int f = f0;
  do {
    const int c = corner_of(f, v);
    out.push_back(faces_[f][(c + 1) % 3]);
    f = face_after(v, faces_[f][(c + 2) % 3]);
  } while (f != f0 && f >= 0 && out.size() <= vertex_faces_[v].size());
  return out;
}

int SurfaceMap::vertex_at_domain_vertex(int x) const {
  // Cones never leave M² vertices; the search is over the few candidates
  // that ever held a domain vertex: features and their successors.
  for (std::size_t v = 0; v < at_domain_vertex_.size(); ++v)
    if (at_domain_vertex_[v] == x && !vertex_faces_[v].empty()) return int(v);
  return -1;
}

// ---------------------------------------------------------------- walks

int SurfaceMap::fan_index(int x, int face) const {
  const auto& fan = domain_.fan(x);
  for (std::size_t i = 0; i < fan.size(); ++i)
    if (fan[i].face == face) return int(i);
  return -1;
}

std::array<Vec2, 3> SurfaceMap::start_layout_of(int v, int face) const {
  const int x = at_domain_vertex_[v];
  if (x < 0) return domain_.layout(face);
  return domain_.fan_layout(x, fan_index(x, face));
}

Vec2 SurfaceMap::position_in(int v, int face, const std::array<Vec2, 3>& layout) const {
  const int x = at_domain_vertex_[v];
  if (x >= 0) {
    const Triangle& t = domain_.mesh().triangles[face];
    return layout[t[0] == x ? 0 : t[1] == x ? 1 : 2];
  }
  const Eigen::Vector3d& b = location_[v].bary;
  return from_barycentric(b, layout);
}

SurfaceMap::WalkEnd SurfaceMap::follow(const EdgeWalk& walk,
                                       const std::array<Vec2, 3>& start_layout) const {
  WalkEnd end{walk.start_face, start_layout};
  for (int i = 0; i < walk.count; ++i) {
    const int k = walk.exit(i);
    end.layout = domain_.unfold(end.face, end.layout, k);
    end.face = domain_.neighbour(end.face, k);
  }
  return end;
}

EdgeWalk SurfaceMap::reversed(const EdgeWalk& walk) const {
  std::array<int, EdgeWalk::kMaxCrossings + 1> face;
  std::array<int, EdgeWalk::kMaxCrossings> entry;
  face[0] = walk.start_face;
  for (int i = 0; i < walk.count; ++i) {
    const int k = walk.exit(i);
    entry[i] = domain_.neighbour_edge(face[i], k);
    face[i + 1] = domain_.neighbour(face[i], k);
  }
  EdgeWalk out;
  out.start_face = face[walk.count];
  for (int i = walk.count - 1; i >= 0; --i) out.push(entry[i]);
  return out;
}

bool SurfaceMap::trace(int face, std::array<Vec2, 3> layout, const Vec2& from, const Vec2& to,
                       EdgeWalk& walk, WalkEnd& end) const {
  walk = EdgeWalk{};
  walk.start_face = face;
  int entry = -1;
  for (int guard = 0; guard <= EdgeWalk::kMaxCrossings; ++guard) {
    // A target at an M¹ vertex is in every face of its fan (tolerance); any
    // other target counts as inside only with all coordinates >= 0, so that
    // a vertex kept just inside its face is never found in the neighbour.
    const Eigen::Vector3d b = barycentric(to, layout[0], layout[1], layout[2]);
    if (b.minCoeff() >= (b.maxCoeff() > 1 - 1e-9 ? kInside : 0.0)) {
      end = {face, layout};
      return true;
    }
    int exit = -1;
    double most_outside = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (k == entry) continue;
      const Vec2 &a = layout[k], &b = layout[(k + 1) % 3];
      const double side = orient(a, b, to);
      if (side >= 0) continue;  // `to` is not beyond this edge
      const double sa = orient(from, to, a), sb = orient(from, to, b);
      if (sa * sb <= 0) {  // the segment passes between a and b
        exit = k;
        break;
      }
      if (exit < 0 || side < most_outside) most_outside = side, exit = k;  // numerical fallback
    }
    if (exit < 0 || !walk.push(exit)) return false;
    layout = domain_.unfold(face, layout, exit);
    entry = domain_.neighbour_edge(face, exit);
    face = domain_.neighbour(face, exit);
  }
  return false;
}

bool SurfaceMap::rotate_to(int x, int& face, std::array<Vec2, 3>& layout, int target,
                           bool clockwise) const {
  const std::size_t steps = domain_.fan(x).size();
  for (std::size_t i = 0; i <= steps; ++i) {
    if (face == target) return true;
    const Triangle& t = domain_.mesh().triangles[face];
    const int c = t[0] == x ? 0 : t[1] == x ? 1 : 2;
    const int k = clockwise ? c : (c + 2) % 3;
    layout = domain_.unfold(face, layout, k);
    face = domain_.neighbour(face, k);
  }
  return false;
}

bool SurfaceMap::wedge_containing(int x, int& face, std::array<Vec2, 3>& layout,
                                  const Vec2& p) const {
  for (std::size_t i = 0; i < domain_.fan(x).size(); ++i) {
    const Triangle& t = domain_.mesh().triangles[face];
    const int c = t[0] == x ? 0 : t[1] == x ? 1 : 2;
    if (orient(layout[c], layout[(c + 1) % 3], p) >= 0 &&
        orient(layout[c], p, layout[(c + 2) % 3]) >= 0)
      return true;
    layout = domain_.unfold(face, layout, (c + 2) % 3);
    face = domain_.neighbour(face, (c + 2) % 3);
  }
  return false;
}

bool SurfaceMap::trace_from(int u, int face, std::array<Vec2, 3> layout, const Vec2& p,
                            EdgeWalk& walk, WalkEnd& end) const {
  const Vec2 from = position_in(u, face, layout);
  const int x = at_domain_vertex_[u];
  if (x >= 0 && !wedge_containing(x, face, layout, p)) return false;
  if (x < 0 && face != location_[u].face) return false;
  return trace(face, layout, from, p, walk, end);
}

Vec2 SurfaceMap::interior_point(const std::array<Vec2, 3>& layout, const Vec2& p) {
  Eigen::Vector3d b = barycentric(p, layout[0], layout[1], layout[2]).cwiseMax(kInteriorBary);
  b /= b.sum();
  return from_barycentric(b, layout);
}

void SurfaceMap::set_location(int v, int face, const std::array<Vec2, 3>& layout, const Vec2& p) {
  Eigen::Vector3d b = barycentric(p, layout[0], layout[1], layout[2]);
  // Keep vertices strictly inside their face so that point-in-face tests
  // never hesitate between two faces.
  b = b.cwiseMax(kInteriorBary);
  b /= b.sum();
  location_[v] = {face, b};
  at_domain_vertex_[v] = -1;
}

// ---------------------------------------------------------------- charts

bool SurfaceMap::face_chart(int t, FaceChart& chart) const {
  const Triangle& tri = faces_[t];
  const auto& w = walks_[t];
  chart.start_face = w[0].start_face;
  if (at_domain_vertex_[tri[0]] < 0 ? location_[tri[0]].face != chart.start_face
                                    : fan_index(at_domain_vertex_[tri[0]], chart.start_face) < 0)
    return false;
  chart.start_layout = start_layout_of(tri[0], chart.start_face);
  chart.corner[0] = position_in(tri[0], chart.start_face, chart.start_layout);
  chart.walk_layout[0] = chart.start_layout;
  WalkEnd end = follow(w[0], chart.start_layout);
  auto scale = [&] {
    return (chart.corner[1] - chart.corner[0]).norm() + (chart.corner[2] - chart.corner[0]).norm();
  };
  for (int k = 1; k <= 3; ++k) {
    const int here = tri[k % 3];
    if (at_domain_vertex_[here] < 0 && location_[here].face != end.face) return false;
    const Vec2 p = position_in(here, end.face, end.layout);
    if (k == 3) {
      // Back at the first corner: the walks must close up.
      if ((p - chart.corner[0]).norm() > 1e-8 * (scale() + 1e-300)) return false;
      break;
    }
    chart.corner[k] = p;
    const int x = at_domain_vertex_[here];
    if (x < 0) {
      if (end.face != w[k].start_face) return false;
      chart.walk_layout[k] = end.layout;
      end = follow(w[k], end.layout);
      continue;
    }
    // At an M¹ vertex, turn clockwise (through the face's interior) to the
    // next walk's start face. Around a cone one face id can come up twice
    // within the turn, so the right copy is the one that puts the next
    // corner clockwise of the previous one, as seen from the vertex.
    int face = end.face;
    std::array<Vec2, 3> layout = end.layout;
    bool found = false;
    for (std::size_t step = 0; step <= 2 * domain_.fan(x).size() && !found; ++step) {
      if (face == w[k].start_face) {
        const WalkEnd next = follow(w[k], layout);
        const int after = tri[(k + 1) % 3];
        if (at_domain_vertex_[after] >= 0 || location_[after].face == next.face) {
          const Vec2 q = position_in(after, next.face, next.layout);
          const Vec2 a = chart.corner[k - 1] - p, b = q - p;
          if (a.x() * b.y() - a.y() * b.x() < 0) {
            chart.walk_layout[k] = layout;
            end = next;
            found = true;
            break;
          }
        }
      }
      const Triangle& d = domain_.mesh().triangles[face];
      const int c = d[0] == x ? 0 : d[1] == x ? 1 : 2;
      layout = domain_.unfold(face, layout, c);
      face = domain_.neighbour(face, c);
    }
    if (!found) return false;
  }
  // A first corner on an M¹ vertex: turning from the last walk's end to the
  // first walk's start must give back the start layout.
  const int x0 = at_domain_vertex_[tri[0]];
  if (x0 >= 0) {
    int face = end.face;
    std::array<Vec2, 3> layout = end.layout;
    for (std::size_t step = 0; step <= 2 * domain_.fan(x0).size(); ++step) {
      if (face == chart.start_face &&
          (layout[0] - chart.start_layout[0]).norm() + (layout[1] - chart.start_layout[1]).norm() <=
              1e-8 * (scale() + 1e-300))
        return true;
      const Triangle& d = domain_.mesh().triangles[face];
      const int c = d[0] == x0 ? 0 : d[1] == x0 ? 1 : 2;
      layout = domain_.unfold(face, layout, c);
      face = domain_.neighbour(face, c);
    }
    return false;
  }
  return true;
}

SurfaceMap::FaceTerms SurfaceMap::face_terms(int t) const {
  const Triangle& tri = faces_[t];
  const Vec3 &q0 = positions_[tri[0]], &q1 = positions_[tri[1]], &q2 = positions_[tri[2]];
  const double total_d = domain_.total_area(), total_m = surface_area_;
  FaceTerms k;
  k.area_m = 0.5 * (q1 - q0).cross(q2 - q0).norm();
  k.squared = {(q2 - q1).squaredNorm(), (q0 - q2).squaredNorm(), (q1 - q0).squaredNorm()};
  // Forward stretch weighted by range area, backward by domain area, each
  // normalised by the total areas (metrics.hpp, symmetric_piece_energy).
  k.forward = forward_weight(t) * k.area_m * (total_d / (total_m * total_m)) * 0.5;
  k.anisotropy = options_.anisotropy_weight * (k.area_m / total_m);
  return k;
}

namespace {

/// SurfaceMap::face_energy's arithmetic (backward_scale: SurfaceMap::
/// backward_scale()), inlined where a ring's faces are summed at every
/// line-search evaluation.
[[gnu::always_inline]] inline double face_stretch(const SurfaceMap::FaceTerms& k, const Vec2& a,
                                                  const Vec2& b, const Vec2& c,
                                                  const MapOptions& options,
                                                  double backward_scale) {
  const double twice_domain = orient(a, b, c);
  if (!(twice_domain > 0)) return HUGE_VAL;
  const double area_d = 0.5 * twice_domain;
  // |J|²_F by the cotangent formula: -(1/4A²) Σ_k (d_{k+1}·d_{k+2}) |e_k|²,
  // d_k the domain edge opposite corner k, e_k the surface one.
  const Vec2 d0 = c - b, d1 = a - c, d2 = b - a;
  const double frob =
      -(d1.dot(d2) * k.squared[0] + d2.dot(d0) * k.squared[1] + d0.dot(d1) * k.squared[2]) /
      (4 * area_d * area_d);
  const double det = k.area_m / area_d;  // Γγ
  double e = k.forward * frob +
             options.inverse_stretch_weight * area_d * backward_scale * 0.5 * frob / (det * det);
  if (options.anisotropy_weight > 0) {
    // Γ/γ + γ/Γ = (Γ² + γ²) / Γγ, past its onset.
    const double excess = std::max(0.0, frob / det - anisotropy_onset(options));
    e += k.anisotropy * excess * excess;
  }
  return e;
}

}  // namespace

double SurfaceMap::face_energy(int t, const Vec2& a, const Vec2& b, const Vec2& c) const {
  return face_energy(face_terms(t), a, b, c);
}

double SurfaceMap::face_energy(const FaceTerms& k, const Vec2& a, const Vec2& b,
                               const Vec2& c) const {
  return face_stretch(k, a, b, c, options_, backward_scale());
}

double SurfaceMap::forward_weight(int t) const {
  if (forward_density_.empty()) return 1.0;
  const Triangle& tri = faces_[t];
  const auto& d = forward_density_;
  return (d[tri[0]] + d[tri[1]] + d[tri[2]]) / 3;
}

double SurfaceMap::face_energy(int t) const {
  FaceChart chart;
  if (!face_chart(t, chart)) return HUGE_VAL;
  return face_energy(t, chart.corner[0], chart.corner[1], chart.corner[2]);
}

double SurfaceMap::energy() const {
  double sum = 0.0;
  for (std::size_t t = 0; t < faces_.size() && sum < HUGE_VAL; ++t) sum += face_energy(int(t));
  return sum;
}

double SurfaceMap::faces_energy(const std::vector<int>& faces) const {
  double sum = 0.0;
  for (std::size_t i = 0; i < faces.size() && sum < HUGE_VAL; ++i) sum += face_energy(faces[i]);
  return sum;
}

// ---------------------------------------------------------------- rings

void SurfaceMap::Ring::clear() {
  faces.clear(), corner.clear(), vertices.clear(), positions.clear();
  end_face.clear(), end_layout.clear(), terms.clear();
  centre = Vec2::Zero();
  centre_face = -1;
  centre_layout = {};
  single_face = true;
}

bool SurfaceMap::build_ring(int v, Ring& ring, int start_vertex) const {
  ring.clear();
  if (vertex_faces_[v].empty()) return false;
  const int f0 = start_vertex < 0 ? vertex_faces_[v].front() : face_after(v, start_vertex);
  if (f0 < 0) return false;
  int f = f0;
  do {
    const int c = corner_of(f, v);
    ring.faces.push_back(f);
    ring.corner.push_back(c);
    ring.vertices.push_back(faces_[f][(c + 1) % 3]);
    f = face_after(v, faces_[f][(c + 2) % 3]);
    if (f < 0 || ring.faces.size() > vertex_faces_[v].size()) return false;
  } while (f != f0);
  const int x = at_domain_vertex_[v];
  if (x < 0) {
    ring.centre_face = location_[v].face;
    ring.centre_layout = domain_.layout(ring.centre_face);
  }
  double previous = -HUGE_VAL, extra = 0.0;
  for (std::size_t i = 0; i < ring.faces.size(); ++i) {
    const EdgeWalk& w = walks_[ring.faces[i]][ring.corner[i]];
    std::array<Vec2, 3> start;
    if (x < 0) {
      if (w.start_face != ring.centre_face) return false;
      start = ring.centre_layout;
    } else {
      // Around an M¹ vertex: unwrap the fan so that consecutive walks leave
      // at increasing angles (exact all the way round for a flat vertex; a
      // contiguous part of the ring for a cone). The angle of a walk is that
      // of its straight segment, which leaves through its start face.
      const int idx = fan_index(x, w.start_face);
      if (idx < 0) return false;
      const WalkEnd probe = follow(w, domain_.fan_layout(x, idx, 0.0));
      const Vec2 q = position_in(ring.vertices[i], probe.face, probe.layout);
      double angle = std::atan2(q.y(), q.x());
      while (angle < domain_.fan(x)[idx].start - 1e-9) angle += 2 * M_PI;
      if (angle + extra <= previous + 1e-12) extra += domain_.total_angle(x);
      previous = angle + extra;
      start = domain_.fan_layout(x, idx, extra);
      if (i == 0) {
        ring.centre_face = w.start_face;
        ring.centre_layout = start;
      }
    }
    const WalkEnd end = follow(w, start);
    const int u = ring.vertices[i];
    if (at_domain_vertex_[u] < 0 && location_[u].face != end.face) return false;
    ring.positions.push_back(position_in(u, end.face, end.layout));
    ring.end_face.push_back(end.face);
    ring.end_layout.push_back(end.layout);
    if (w.count > 0 || x >= 0) ring.single_face = false;
  }
  ring.centre = x < 0 ? position_in(v, ring.centre_face, ring.centre_layout) : Vec2::Zero();
  for (int f : ring.faces) ring.terms.push_back(face_terms(f));
  return true;
}

double SurfaceMap::ring_energy(const Ring& ring, int v, const Vec2& p) const {
  (void)v;
  double sum = 0.0;
  const std::size_t m = ring.faces.size();
  const double scale = backward_scale();
  for (std::size_t i = 0; i < m; ++i) {
    std::array<Vec2, 3> corner;
    const int c = ring.corner[i];
    corner[c] = p;
    corner[(c + 1) % 3] = ring.positions[i];
    corner[(c + 2) % 3] = ring.positions[(i + 1) % m];
    sum += face_stretch(ring.terms[i], corner[0], corner[1], corner[2], options_, scale);
    if (sum == HUGE_VAL) return sum;
  }
  return sum;
}

// Kernel of a ring polygon by half-plane clipping, and its centroid: a point
// where every face (p, ring[i], ring[i+1]) is positive, if any.
std::optional<Vec2> kernel_centroid(const std::vector<Vec2>& ring) {
  thread_local std::vector<std::array<Vec2, 2>> edges;  // per-thread scratch
  edges.resize(ring.size());
  for (std::size_t i = 0; i < ring.size(); ++i) edges[i] = {ring[i], ring[(i + 1) % ring.size()]};
  return kernel_centroid(edges);
}

std::optional<Vec2> kernel_centroid(const std::vector<std::array<Vec2, 2>>& edges) {
  if (edges.empty()) return std::nullopt;
  Vec2 lo = edges[0][0], hi = edges[0][0];
  for (const auto& e : edges)
    for (const Vec2& q : e) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  // The polygon clipped edge by edge, between two lists kept per thread.
  thread_local std::vector<Vec2> poly, out;
  poly.assign({lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())});
  for (std::size_t i = 0; i < edges.size() && !poly.empty(); ++i) {
    const auto& [a, b] = edges[i];
    out.clear();
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Vec2& p = poly[k];
      const Vec2& q = poly[(k + 1) % poly.size()];
      const double sp = orient(p, a, b), sq = orient(q, a, b);
      if (sp > 0) out.push_back(p);
      if ((sp > 0) != (sq > 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    poly.swap(out);
  }
  if (poly.size() < 3) return std::nullopt;
  // The centroid relative to a corner of the kernel: in absolute coordinates
  // a kernel much smaller than its distance to the origin loses every digit
  // (a thin kernel's centroid then falls outside it).
  const Vec2 origin = poly[0];
  Vec2 c = Vec2::Zero();
  double area = 0;
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    const Vec2 p = poly[k] - origin, q = poly[k + 1] - origin;
    const double w = p.x() * q.y() - p.y() * q.x();
    area += w;
    c += w * (p + q);
  }
  if (!(area > 0)) return std::nullopt;
  c = origin + c / (3 * area);
  for (const auto& [a, b] : edges)
    if (!(orient(c, a, b) > 0)) return std::nullopt;
  return c;
}

namespace {

// Largest step along d from q that keeps every face (q, ring[i], ring[i+1])
// positive: the kernel of the ring polygon.
double max_kernel_step(const std::vector<Vec2>& ring, const Vec2& q, const Vec2& d) {
  const std::size_t m = ring.size();
  double t = HUGE_VAL;
  for (std::size_t i = 0; i < m; ++i) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[(i + 1) % m];
    const double o = orient(q, a, b);
    const double rate = d.x() * (a.y() - b.y()) - d.y() * (a.x() - b.x());  // d/dt orient
    if (rate < 0) t = std::min(t, -o / rate);
  }
  return t;
}

// Brent's minimisation of f over [lo, hi] (lo < 0 < hi) starting from the
// point 0 whose value f0 is known: each step fits a parabola through the
// three best points and takes its vertex when it lies inside the bracket
// and moves less than half the step before the last; otherwise a golden
// section of the larger part. Values of HUGE_VAL (invalid places) only
// ever take golden sections. With a finite `guess` (a predicted minimum)
// and `slope` (f'(0)), the first step goes to the guess and the first
// parabola has that slope at 0. Returns the best point and its value.
std::pair<double, double> parabolic_search(const std::function<double(double)>& f, double lo,
                                           double hi, double f0, double tolerance, int max_steps,
                                           double guess = NAN, double slope = NAN) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));  // 0.381966...
  double a = lo, b = hi;
  double x = 0, w = 0, u = 0;  // best, second best, previous second best
  double fx = f0, fw = f0, fu = f0;
  double step = 0, last = 0;  // this step and the one before
  int it = 0;
  bool seeded = false;
  if (std::isfinite(guess) && std::isfinite(slope) && std::abs(guess) >= tolerance &&
      b - a > 4 * tolerance) {
    guess = std::clamp(guess, a + 2 * tolerance, b - 2 * tolerance);  // (inside the kernel)
    const double fg = f(guess);
    ++it;
    if (fg <= fx) {
      (guess >= x ? a : b) = x;
      w = x, fw = fx;
      x = guess, fx = fg;
    } else {
      (guess < x ? a : b) = guess;
      w = guess, fw = fg;
    }
    // (A point just beside 0 on the tangent: the first parabola through
    // it, 0 and the guess has the slope at 0. It is replaced by the next
    // point evaluated that is better.)
    u = -1e-3 * guess, fu = f0 + slope * u;
    step = guess, last = hi - lo;  // (parabolic steps allowed at once)
    seeded = true;
  }
  for (; it < max_steps; ++it) {
    const double middle = 0.5 * (a + b);
    if (std::abs(x - middle) <= 2 * tolerance - 0.5 * (b - a)) break;
    bool parabola = false;
    if (std::abs(last) > tolerance && fx < HUGE_VAL && fw < HUGE_VAL && fu < HUGE_VAL) {
      // Vertex of the parabola through (x, fx), (w, fw), (u, fu).
      const double r = (x - w) * (fx - fu), q0 = (x - u) * (fx - fw);
      double num = (x - u) * q0 - (x - w) * r, den = 2 * (q0 - r);
      if (den > 0) num = -num;
      den = std::abs(den);
      if (std::abs(num) < std::abs(0.5 * den * last) && num > den * (a - x) &&
          num < den * (b - x)) {
        // (Seeded: a parabola whose vertex is the best point within the
        // tolerance ends the search.)
        if (seeded && std::abs(num) < tolerance * den) break;
        last = step;
        step = num / den;
        const double t = x + step;
        if (t - a < 2 * tolerance || b - t < 2 * tolerance)
          step = middle > x ? tolerance : -tolerance;
        parabola = true;
      }
    }
    if (!parabola) {
      last = x >= middle ? a - x : b - x;
      step = golden * last;
    }
    const double t =
        std::abs(step) >= tolerance ? x + step : x + (step > 0 ? tolerance : -tolerance);
    const double ft = f(t);
    if (ft <= fx) {
      (t >= x ? a : b) = x;
      u = w, fu = fw;
      w = x, fw = fx;
      x = t, fx = ft;
    } else {
      (t < x ? a : b) = t;
      if (ft <= fw || w == x) {
        u = w, fu = fw;
        w = t, fw = ft;
      } else if (ft <= fu || u == x || u == w) {
        u = t, fu = ft;
      }
    }
  }
  return {x, fx};
}

}  // namespace

double minimize_in_kernel(
    const std::vector<Vec2>& ring, Vec2& p, const std::function<double(const Vec2&)>& energy,
    LineSearch rule, double give_up_above, KernelSearch settings,
    const std::function<void(std::span<const Vec2> at, std::span<double> out)>& energies) {
  const double e0 = energy(p);
  if (!(e0 < HUGE_VAL)) return HUGE_VAL;
  double scale = 0.0;
  for (const Vec2& q : ring) scale = std::max(scale, (q - p).norm());
  double e = e0;
  // search(d, slope, curvature): along d, from the model's slope and
  // curvature there when given (settings.model_seed).
  auto search = [&](Vec2 d, double slope = NAN, double curvature = NAN) {
    const double norm = d.norm();
    if (!(norm > 0)) return;
    d /= norm;
    const double hi = 0.95 * std::min(max_kernel_step(ring, p, d), 2 * scale);
    const double lo = -0.95 * std::min(max_kernel_step(ring, p, -d), 2 * scale);
    if (!(hi > lo)) return;
    if (rule == LineSearch::parabolic) {
      if (!(hi > 0 && lo < 0)) return;
      const double guess = curvature > 0 ? -slope / curvature : NAN;
      const auto [t, ft] = parabolic_search([&](double t) { return energy(p + t * d); }, lo, hi, e,
                                            settings.tolerance * scale, 40, guess, slope);
      if (ft < e) {
        p += t * d;
        e = ft;
      }
      return;
    }
    // Golden-section search along the line, inside the kernel.
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = lo, b = hi;
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double f1 = energy(p + x1 * d), f2 = energy(p + x2 * d);
    for (int it = 0; it < 24 && b - a > 1e-9 * scale; ++it) {
      if (f1 < f2) {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - g * (b - a);
        f1 = energy(p + x1 * d);
      } else {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + g * (b - a);
        f2 = energy(p + x2 * d);
      }
    }
    const double t = f1 < f2 ? x1 : x2;
    const double ft = std::min(f1, f2);
    if (ft < e) {
      p += t * d;
      e = ft;
    }
  };
  for (int round = 0; round < settings.rounds; ++round) {
    // Central-difference gradient, then the perpendicular direction. Where
    // the differences are not valid (a vertex sitting on a vertex of the
    // other side, whose edges leave along the axes: a step onto one, or one
    // so small that it leaves pieces too small to keep, is refused), along
    // axes turned by 0.4 radians, and wider.
    Vec2 grad(NAN, NAN);
    // The model (settings.model_seed): the gradient and Hessian in the
    // frame (u, w) of the differences.
    Vec2 u, w, g_uw;
    Eigen::Matrix2d hessian;
    double step = 0, eu[2], ew[2];
    for (const auto& [h, turn] : {std::pair{1e-5, 0.0}, {1e-5, 0.4}, {1e-3, 0.4}, {1e-2, 0.4}}) {
      u = Vec2(std::cos(turn), std::sin(turn)), w = Vec2(-u.y(), u.x());
      step = h * scale;
      const std::array<Vec2, 4> at{p + step * u, p - step * u, p + step * w, p - step * w};
      std::array<double, 4> e4;
      if (energies)
        energies(at, e4);
      else
        for (std::size_t k = 0; k < 4; ++k) e4[k] = energy(at[k]);
      eu[0] = e4[0], eu[1] = e4[1], ew[0] = e4[2], ew[1] = e4[3];
      const double du = eu[0] - eu[1], dw = ew[0] - ew[1];
      grad = du * u + dw * w;
      g_uw = Vec2(du, dw) / (2 * step);
      if (grad.allFinite()) break;
    }
    if (!grad.allFinite() || grad.norm() == 0) break;
    bool model = false;
    if (settings.model_seed && rule == LineSearch::parabolic) {
      const Vec2 m = (u + w) / std::sqrt(2.0);
      const double em = energy(p + step * m);
      const double huu = (eu[0] + eu[1] - 2 * e) / (step * step);
      const double hww = (ew[0] + ew[1] - 2 * e) / (step * step);
      // mᵀHm = (huu + 2 huw + hww) / 2 from the one-sided difference along m.
      const double hmm =
          2 * (em - e - step * g_uw.dot(Vec2(1, 1) / std::sqrt(2.0))) / (step * step);
      hessian << huu, hmm - 0.5 * (huu + hww), hmm - 0.5 * (huu + hww), hww;
      model = hessian.allFinite();
    }
    const Vec2 start = p, d1(-grad.y(), grad.x());
    if (model) {
      auto in_frame = [&](const Vec2& d) { return Vec2(d.dot(u), d.dot(w)); };
      const Vec2 d0 = -grad.normalized(), a = in_frame(d0);
      search(d0, g_uw.dot(a), a.dot(hessian * a));
      // At the point reached, the model's slope along the perpendicular.
      const Vec2 b = in_frame(d1.normalized()), moved = in_frame(p - start);
      search(d1, b.dot(g_uw + hessian * moved), b.dot(hessian * b));
    } else {
      search(-grad);
      search(d1);
    }
    // (From the same point a second round would repeat the first.)
    if (!(e < give_up_above) || p == start) break;
  }
  return e;
}

double newton_in_kernel(const std::vector<Vec2>& ring, Vec2& p,
                        const std::function<double(const Vec2&, Vec2*, Eigen::Matrix2d*)>& energy,
                        int max_steps) {
  Vec2 gradient;
  Eigen::Matrix2d hessian;
  double e = energy(p, &gradient, &hessian);
  if (!(e < HUGE_VAL)) return HUGE_VAL;
  double scale = 0.0;
  for (const Vec2& q : ring) scale = std::max(scale, (q - p).norm());
  for (int step = 0; step < max_steps; ++step) {
    if (!gradient.allFinite() || !hessian.allFinite()) break;
    // The Hessian's smaller eigenvalue; shifted up to a small fraction of
    // the larger where it is not clearly positive.
    const double trace = hessian.trace(), gap = hessian(0, 0) - hessian(1, 1);
    const double root = std::sqrt(gap * gap + 4 * hessian(0, 1) * hessian(0, 1));
    const double low = 0.5 * (trace - root), high = 0.5 * (trace + root);
    if (!(high > 0)) break;
    if (low < 1e-6 * high) hessian.diagonal().array() += 1e-6 * high - low;
    const Vec2 d = -hessian.ldlt().solve(gradient);
    const double slope = gradient.dot(d);
    if (!d.allFinite() || !(slope < 0)) break;
    double t = std::min(1.0, 0.95 * max_kernel_step(ring, p, d));
    double next = HUGE_VAL;
    for (int back = 0; back < 40 && t * d.norm() > 1e-12 * scale; ++back, t *= 0.5) {
      next = energy(p + t * d, nullptr, nullptr);
      if (next <= e + 1e-4 * t * slope) break;
    }
    if (!(next <= e + 1e-4 * t * slope) || !(next < e)) break;
    p += t * d;
    e = energy(p, &gradient, &hessian);
    if (t * d.norm() < 1e-9 * scale) break;
  }
  return e;
}

double SurfaceMap::optimize_vertex(int v) {
  if (pinned_[v] || vertex_faces_[v].empty()) return 0.0;
  // Per-thread scratch: its lists keep their storage from vertex to vertex.
  thread_local Ring ring;
  if (!build_ring(v, ring)) return 0.0;
  ++optimizations_;
  if (ring.single_face) ++single_face_rings_;
  double e0 = ring_energy(ring, v, ring.centre);
  Vec2 p = ring.centre;
  if (!(e0 < HUGE_VAL)) {
    // Degenerate (a face of zero area in floating point): restart from the
    // middle of the kernel, which is always a valid place.
    const std::optional<Vec2> centre = kernel_centroid(ring.positions);
    if (!centre) return 0.0;
    p = *centre;
    const double e = ring_energy(ring, v, p);
    if (!(e < HUGE_VAL)) return 0.0;
    minimize_in_kernel(ring.positions, p, [&](const Vec2& q) { return ring_energy(ring, v, q); });
    return move_vertex(v, ring, p) ? 1e-300 : 0.0;  // repaired; no energy to compare
  }
  double e;
  if (options_.vertex_step == MapOptions::VertexStep::newton) {
    // Each face's energy as a function of p (CornerStretch: the same terms
    // as face_stretch); Newton steps on their exact derivatives.
    const std::size_t m = ring.faces.size();
    const double scale = backward_scale();
    // Per-thread scratch: one ring's terms, rebuilt for every vertex.
    thread_local std::vector<CornerStretch> corners;
    corners.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      const FaceTerms& k = ring.terms[i];
      const int c = ring.corner[i];
      corners[i] = {ring.positions[i],
                    ring.positions[(i + 1) % m],
                    k.squared[c],
                    k.squared[(c + 1) % 3],
                    k.squared[(c + 2) % 3],
                    2 * k.forward,
                    options_.inverse_stretch_weight * scale / (k.area_m * k.area_m)};
      if (options_.anisotropy_weight > 0) {
        // face_stretch's penalty: k.anisotropy already holds the surface
        // face's area (the fixed triangle's).
        corners[i].fixed_area = k.area_m, corners[i].kappa0 = k.anisotropy;
        corners[i].onset = anisotropy_onset(options_);
      }
    }
    newton_in_kernel(ring.positions, p,
                     [&](const Vec2& x, Vec2* gradient, Eigen::Matrix2d* hessian) {
                       return corners_energy(corners, x, gradient, hessian);
                     });
    e = p == ring.centre ? e0 : ring_energy(ring, v, p);
  } else {
    e = minimize_in_kernel(ring.positions, p,
                           [&](const Vec2& q) { return ring_energy(ring, v, q); });
  }
  if (!(e < e0 * (1 - 1e-12))) return 0.0;
  return move_vertex(v, ring, p) ? e0 - e : 0.0;
}

bool SurfaceMap::move_vertex(int v, const Ring& ring, const Vec2& target) {
  // Where p lies in M¹: walk from the old position.
  int face;
  std::array<Vec2, 3> layout;
  EdgeWalk scratch;
  WalkEnd end;
  const int x = at_domain_vertex_[v];
  if (x < 0) {
    if (!trace(ring.centre_face, ring.centre_layout, ring.centre, target, scratch, end))
      return false;
  } else {
    // From an M¹ vertex: start in the fan face whose angle holds p.
    int f = ring.centre_face;
    std::array<Vec2, 3> l = ring.centre_layout;
    if (!wedge_containing(x, f, l, target) || !trace(f, l, Vec2::Zero(), target, scratch, end))
      return false;
  }
  face = end.face;
  layout = end.layout;
  const Vec2 p = interior_point(layout, target);

  // New walks from p to every neighbour; commit only if all succeed.
  const std::size_t m = ring.faces.size();
  thread_local std::vector<EdgeWalk> forward;  // per-thread scratch
  forward.assign(m, EdgeWalk{});
  for (std::size_t i = 0; i < m; ++i) {
    WalkEnd e;
    if (!trace(face, layout, p, ring.positions[i], forward[i], e)) return false;
    const int u = ring.vertices[i];
    if (at_domain_vertex_[u] < 0
            ? e.face != location_[u].face
            : domain_.mesh().triangles[e.face][0] != at_domain_vertex_[u] &&
                  domain_.mesh().triangles[e.face][1] != at_domain_vertex_[u] &&
                  domain_.mesh().triangles[e.face][2] != at_domain_vertex_[u])
      return false;
  }
  // Commit, then check the ring's faces: a walk that went round a cone the
  // wrong way shows up as a face that does not close. Undo in that case.
  const DomainLocation old_location = location_[v];
  const int old_vertex = at_domain_vertex_[v];
  thread_local std::vector<std::array<EdgeWalk, 3>> old_walks;  // per-thread scratch
  old_walks.clear();
  for (int f : ring.faces) old_walks.push_back(walks_[f]);
  set_location(v, face, layout, p);
  for (std::size_t i = 0; i < m; ++i) {
    const int f = ring.faces[i], c = ring.corner[i];
    walks_[f][c] = forward[i];
    walks_[f][(c + 2) % 3] = reversed(forward[(i + 1) % m]);
  }
  if (!faces_are_valid(ring.faces)) {
    location_[v] = old_location;
    at_domain_vertex_[v] = old_vertex;
    for (std::size_t i = 0; i < m; ++i) walks_[ring.faces[i]] = old_walks[i];
    return false;
  }
  return true;
}

bool SurfaceMap::faces_are_valid(const std::vector<int>& faces) const {
  FaceChart chart;
  for (int f : faces)
    if (!face_chart(f, chart) || !(orient(chart.corner[0], chart.corner[1], chart.corner[2]) > 0))
      return false;
  return true;
}

}  // namespace ism
