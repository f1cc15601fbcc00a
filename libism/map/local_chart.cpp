// The local operations of InterSurfaceMap (paper §5.1): a one-ring of one
// side laid out in a chart of the other, vertex optimisation by line
// searches in the kernel of the ring, and vertex splits.
#include "map/chart_cell.hpp"
#include "map/inter_surface_map.hpp"
#include "map/inter_surface_map_impl.hpp"
#include "map/overlay.hpp"      // clip_to_triangle
#include "map/surface_map.hpp"  // minimize_in_kernel, kernel_centroid

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/LU>
#include <Eigen/SparseLU>

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace ism {

namespace {

using Layout3 = std::array<Vec2, 3>;

/// Where the last chart or evaluation on this thread failed (diagnostics
/// for a split that cannot be placed; per thread, as plans are made on
/// several).
thread_local int chart_failure_ = 0;

/// Barycentric coordinates kept inside the face (rounding), summing to 1.
Eigen::Vector3d clamp_bary(Eigen::Vector3d b) {
  b = b.cwiseMax(1e-12);
  return b / b.sum();
}

/// A point inside a simple counter-clockwise polygon (corners pos[cell[i]]):
/// the centroid of one of its ears; nothing if it has none.
// Angles at a chart's centre capped at 0.95 π, the excess spread over the
// others in proportion to their room below it (their sum kept); whether
// any changed.
bool cap_angles(std::vector<double>& theta) {
  bool changed = false;
  for (int round = 0; round < 8; ++round) {
    double excess = 0, room = 0;
    for (double a : theta) {
      excess += std::max(0.0, a - 0.95 * M_PI);
      room += std::max(0.0, 0.95 * M_PI - a);
    }
    if (excess <= 0) break;
    changed = true;
    for (double& a : theta)
      a = a > 0.95 * M_PI ? 0.95 * M_PI : a + excess * (0.95 * M_PI - a) / room;
  }
  return changed;
}

std::optional<Vec2> ear_point(const std::vector<Vec2>& pos, std::span<const int> cell) {
  const std::size_t n = cell.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = pos[cell[(i + n - 1) % n]], &b = pos[cell[i]], &c = pos[cell[(i + 1) % n]];
    if (!(orient(a, b, c) > 0)) continue;
    bool ear = true;
    for (std::size_t j = 0; j < n && ear; ++j) {
      if (j == i || j == (i + 1) % n || j == (i + n - 1) % n) continue;
      const Vec2& p = pos[cell[j]];
      if (orient(a, b, p) > 0 && orient(b, c, p) > 0 && orient(c, a, p) > 0) ear = false;
    }
    if (ear) return (a + b + c) / 3;
  }
  return std::nullopt;
}

}  // namespace

// ---------------------------------------------------------------- chart

std::map<int, double> InterSurfaceMap::vertex_edge_angles(int side, int x) const {
  // The directions of x's edges around it in its own metric, scaled so that
  // a full turn is 2π.
  const MetaSide& M = meta_.side[side];
  const auto& around = index_[side].vertex_faces[x];
  std::map<int, double> out;
  if (around.empty()) return out;
  auto corner_of = [&](int f) {
    const Triangle& tri = M.faces[f];
    return tri[0] == x ? 0 : tri[1] == x ? 1 : 2;
  };
  std::vector<std::pair<int, double>> fan;  // edge leaving x at the start of each face, angle
  int f = around.front();
  double angle = 0;
  do {
    const int c = corner_of(f);
    fan.push_back({M.face_edges[f][c], angle});
    const Layout3 L = meta_face_layout(M.lengths[f]);
    const Vec2 a = L[(c + 1) % 3] - L[c], b = L[(c + 2) % 3] - L[c];
    angle += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    const int last = M.faces[f][(c + 2) % 3];
    int next = -1;
    for (int g : around)
      if (M.faces[g][(corner_of(g) + 1) % 3] == last) next = g;
    f = next;
    if (f < 0 || fan.size() > around.size()) return {};
  } while (f != around.front());
  for (const auto& [e, a] : fan) out[e] = a * 2 * M_PI / angle;
  return out;
}

// The ring's boundary in the chart from ring[first] to ring[last] (last ==
// m: the whole loop), with the break points of its edges where those do not
// lie on the chords between the ring's vertices.
std::vector<Vec2> InterSurfaceMap::boundary_polygon(const Chart& chart, std::size_t first,
                                                    std::size_t last) {
  const std::size_t m = chart.ring.size();
  if (chart.straight_boundary) {
    if (last == m) return chart.w;
    return {chart.w.begin() + first, chart.w.begin() + last + 1};
  }
  const std::size_t end = last == m ? chart.boundary_loop.size() : chart.loop_start[last] + 1;
  std::vector<Vec2> polygon;
  for (std::size_t i = chart.loop_start[first]; i < end; ++i)
    polygon.push_back(chart.anchors[chart.boundary_loop[i]].pos);
  return polygon;
}

bool InterSurfaceMap::developed_ring(int s, int v, Chart& chart) const {
  const int t = 1 - s;
  const MetaSide& S = meta_.side[s];
  const MetaSide& T = meta_.side[t];
  const MetaSideIndex& IT = index_[t];
  const std::size_t m = chart.ring.size();
  for (int f : chart.faces)
    if (!index_[s].residents[f].empty()) return false;
  // (t's vertices on a boundary edge of the ring: its image bends there.)
  if (index_[s].open)
    for (int e : chart.boundary)
      if (!index_[s].on_edge[e].empty()) return false;
  // A face of t laid out in the chart: its canonical layout moved rigidly.
  struct Placed {
    int face;
    Layout3 corner;
  };
  // Follows edge e of s from its end `from` across the faces of t, from
  // `here` (the face holding `from`); each break point's chart position
  // goes to `breaks` (in order from `from`), and the face holding the other
  // end to `here`.
  auto walk = [&](int e, int from, Placed& here, std::vector<Vec2>* breaks) {
    const auto& list = S.crossings[e];
    const bool forward = S.edges[e][0] == from;
    for (std::size_t k = 0; k < list.size(); ++k) {
      const MetaCrossing& c = list[forward ? k : list.size() - 1 - k];
      if (c.is_kink()) {
        if (c.face != here.face) return false;
        if (breaks) breaks->push_back(from_barycentric(c.bary, here.corner));
        continue;
      }
      const auto& fe = T.face_edges[here.face];
      const int j = fe[0] == c.edge ? 0 : fe[1] == c.edge ? 1 : fe[2] == c.edge ? 2 : -1;
      if (j < 0) return false;
      const auto& ef = IT.edge_faces[c.edge];
      const int next = ef[0] == here.face ? ef[1] : ef[0];
      if (next < 0 || next == here.face) return false;
      const int a = T.faces[here.face][j], b = T.faces[here.face][(j + 1) % 3];
      const Vec2 pa = here.corner[j], pb = here.corner[(j + 1) % 3];
      if (breaks)
        breaks->push_back(T.edges[c.edge][0] == a ? pa + c.there * (pb - pa)
                                                  : pb + c.there * (pa - pb));
      const Triangle& g = T.faces[next];
      const int ia = g[0] == a ? 0 : g[1] == a ? 1 : g[2] == a ? 2 : -1;
      const int ib = g[0] == b ? 0 : g[1] == b ? 1 : g[2] == b ? 2 : -1;
      if (ia < 0 || ib < 0) return false;
      // The face's own layout (robust for slivers, unlike placing the third
      // corner by the law of cosines) moved rigidly: the rotation taking
      // G[ia] -> G[ib] to pa -> pb, then G[ia] to pa.
      const Layout3 G = meta_face_layout(T.lengths[next]);
      const double lu = (G[ib] - G[ia]).norm(), ld = (pb - pa).norm();
      if (std::abs(lu - ld) > 1e-9 * (lu + ld)) return false;
      const auto across = layout_across(G, ia, ib, pa, pb);
      if (!across) return false;
      here.face = next;
      here.corner = *across;
    }
    return true;
  };
  // Where vertex x of s lies in a placed face of t.
  auto position = [&](int x, const Placed& here) -> std::optional<Vec2> {
    const MetaLocation& loc = S.location[x];
    if (loc.face != here.face) return std::nullopt;
    return from_barycentric(loc.bary, here.corner);
  };
  const Placed centre{S.location[v].face, meta_face_layout(T.lengths[S.location[v].face])};
  std::vector<Vec2> w(m);
  std::vector<Placed> at(m);
  for (std::size_t i = 0; i < m; ++i) {
    at[i] = centre;
    if (!walk(chart.spoke[i], v, at[i], nullptr)) return false;
    const auto p = position(chart.ring[i], at[i]);
    if (!p) return false;  // (a neighbour on a vertex of t: the law of cosines)
    w[i] = *p;
  }
  // The ring must be star-shaped around v with every angle below 0.95 π
  // (as the law of cosines' layout is made).
  double total = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const Vec2 a = w[i] - chart.centre, b = w[(i + 1) % m] - chart.centre;
    const double angle = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    if (!(angle > 0) || angle > 0.95 * M_PI) return false;
    total += angle;
  }
  if (std::abs(total - 2 * M_PI) > 1e-9) return false;
  // The break points of the ring's edges, where they are on t; each edge
  // must end where the next spoke put its end.
  std::vector<std::vector<Vec2>> breaks(m);
  bool straight = true;
  for (std::size_t i = 0; i < m; ++i) {
    Placed here = at[i];
    if (!walk(chart.boundary[i], chart.ring[i], here, &breaks[i])) return false;
    const auto q = position(chart.ring[(i + 1) % m], here);
    const Vec2& end = w[(i + 1) % m];
    const double scale = (end - w[i]).norm();
    if (!q || (*q - end).norm() > 1e-9 * scale) return false;
    const int e = chart.boundary[i];
    const auto& list = S.crossings[e];
    const bool forward = S.edges[e][0] == chart.ring[i];
    for (std::size_t k = 0; k < list.size(); ++k) {
      const double u = forward ? list[k].here : 1 - list[list.size() - 1 - k].here;
      if ((breaks[i][k] - (w[i] + u * (end - w[i]))).norm() > 1e-9 * scale) straight = false;
    }
  }
  chart.straight_boundary = straight;
  chart.w = std::move(w);
  chart.boundary_breaks = std::move(breaks);
  return true;
}

bool InterSurfaceMap::build_chart(int s, int v, Chart& chart) const {
  return build_chart_from(s, v, -1, chart);
}

bool InterSurfaceMap::build_half_disc(int s, int v, Chart& chart, const Place* slide) const {
  return build_chart_from(s, v, -1, chart, false, true, slide);
}

bool InterSurfaceMap::build_chart_from(int s, int v, int start, Chart& chart, bool ring_only,
                                       bool half_disc, const Place* slide) const {
  chart.clear();
  auto chart_fail = [&](int where) {
    chart_failure_ = where;
    return false;
  };
  const int t = 1 - s;
  chart.s = s, chart.t = t, chart.v = v;
  const MetaSide& S = meta_.side[s];
  const MetaSide& T = meta_.side[t];
  const MetaSideIndex& IS = index_[s];
  const MetaSideIndex& IT = index_[t];
  if (half_disc) {
    // A boundary vertex on a boundary edge of t (not on a vertex of t).
    // (Its ring alone also where it sits on a vertex of t.)
    if (!IS.open || !(S.location[v].on_edge() || (ring_only && S.location[v].vertex >= 0)))
      return chart_fail(20);
    fan_faces(s, v, chart.faces);
    chart.half_disc = true;
  } else {
    ring_faces(s, v, chart.faces);
  }
  const std::size_t m = chart.faces.size();
  if (m < (half_disc ? 2 : 3)) return chart_fail(10);
  if (start >= 0) {
    std::size_t i0 = m;
    for (std::size_t i = 0; i < m; ++i) {
      const Triangle& f = S.faces[chart.faces[i]];
      const int c = f[0] == v ? 0 : f[1] == v ? 1 : 2;
      if (f[(c + 1) % 3] == start) i0 = i;
    }
    if (i0 == m) return chart_fail(18);
    std::rotate(chart.faces.begin(), chart.faces.begin() + i0, chart.faces.end());
  }
  for (int f : chart.faces) {
    const Triangle& tri = S.faces[f];
    const int c = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    chart.corner.push_back(c);
    chart.ring.push_back(tri[(c + 1) % 3]);
  }
  if (half_disc) {  // (the fan's last neighbour, across its last boundary edge)
    const int c = chart.corner.back();
    chart.ring.push_back(S.faces[chart.faces.back()][(c + 2) % 3]);
  }
  const std::size_t nr = chart.ring.size();
  for (std::size_t i = 0; i < m; ++i) {
    // Face i's edges (face_edges[f][k] joins corners k and k + 1) where its
    // third corner is the next neighbour; the edge map where the fan is open.
    const Triangle& tri = S.faces[chart.faces[i]];
    const int c = chart.corner[i], next = chart.ring[(i + 1) % nr];
    chart.spoke.push_back(S.face_edges[chart.faces[i]][c]);
    chart.boundary.push_back(tri[(c + 2) % 3] == next ? S.face_edges[chart.faces[i]][(c + 1) % 3]
                                                      : IS.edge(chart.ring[i], next));
  }
  if (half_disc)
    chart.spoke.push_back(S.face_edges[chart.faces.back()][(chart.corner.back() + 2) % 3]);
  if (ring_only) return true;
  // An open map: a ring edge on the boundary of s lies on the boundary of
  // t, and t's vertices on it (IS.on_edge) are fixed anchors of the ring's
  // boundary; their edges into the ring are chords like any other.
  bool boundary_lodgers = half_disc;
  if (IS.open)
    for (int e : chart.boundary) {
      if (e < 0) return chart_fail(19);
      boundary_lodgers = boundary_lodgers || (IS.is_boundary(e) && !IS.on_edge[e].empty());
    }
  const MetaLocation& vloc = S.location[v];

  // Fast path: the ring and everything in it inside one face of t.
  bool fast = vloc.face >= 0 && !boundary_lodgers;
  for (std::size_t i = 0; i < m && fast; ++i) {
    const MetaLocation& loc = S.location[chart.ring[i]];
    fast = loc.face == vloc.face && S.crossings[chart.spoke[i]].empty() &&
           S.crossings[chart.boundary[i]].empty() && IS.residents[chart.faces[i]].empty();
  }
  if (fast) {
    chart.kind = Chart::fast;
    chart.single_face = vloc.face;
    const Layout3 L = meta_face_layout(T.lengths[vloc.face]);
    auto at = [&](const Eigen::Vector3d& b) { return from_barycentric(b, L); };
    chart.centre = at(vloc.bary);
    for (std::size_t i = 0; i < m; ++i) {
      chart.w.push_back(at(S.location[chart.ring[i]].bary));
      chart.ring_anchor.push_back(int(chart.anchors.size()));
      chart.boundary_loop.push_back(int(chart.anchors.size()));
      chart.anchors.push_back({vertex_node(meta_, s, chart.ring[i]), chart.w.back()});
    }
    return true;
  }

  std::vector<int> faces_a, faces_b;
  bool bent = false, rescale = true;
  // Where v lies inside a face of t and no vertex of t lies inside the
  // ring's faces, the region is flat: each neighbour where its spoke's
  // image, unfolded face by face across the edges of t it crosses, ends.
  // This is the exact development; the law of cosines below equals it only
  // while the ring's edges are straight across the edges of t they cross.
  if (vloc.face >= 0)
    chart.centre = from_barycentric(vloc.bary, meta_face_layout(T.lengths[vloc.face]));
  if (!half_disc && vloc.face >= 0 && developed_ring(s, v, chart)) {
    rescale = false;
    for (std::size_t i = 0; i < m; ++i)
      for (const int e : {chart.spoke[i], chart.boundary[i]})
        for (const MetaCrossing& c : S.crossings[e]) bent |= c.is_kink();
  } else {
    // The one-ring unfolding of paper §5.1: each neighbour at the length of
    // its edge's image on t, the angles between them from the law of cosines
    // on the images' lengths, scaled to sum to 2π. Where the ring's image is
    // flat and its edges straight, this is the isometric development.
    auto image_length = [&](int e, double& length, bool& bent) {
      const auto& list = S.crossings[e];
      const MetaNode a = vertex_node(meta_, s, S.edges[e][0]),
                     b = vertex_node(meta_, s, S.edges[e][1]);
      Place previous = a.place[t];
      length = 0;
      // (A boundary edge has no break points; its image runs through t's
      // vertices on it.)
      const std::vector<int>* lodged =
          IS.open && IS.is_boundary(e) && !IS.on_edge[e].empty() ? &IS.on_edge[e] : nullptr;
      const std::size_t n = lodged ? lodged->size() : list.size();
      for (std::size_t k = 0; k <= n; ++k) {
        Place next = b.place[t];
        if (k < n && lodged) {
          next = vertex_node(meta_, t, (*lodged)[k]).place[t];
        } else if (k < n) {
          const auto node = break_node(meta_, s, e, int(k));
          if (!node) return false;
          next = node->place[t];
          bent |= list[k].is_kink();
        }
        place_faces(meta_, index_, t, previous, faces_a);
        place_faces(meta_, index_, t, next, faces_b);
        bool found = false;
        for (int f : faces_a)
          if (!found && std::find(faces_b.begin(), faces_b.end(), f) != faces_b.end()) {
            const auto p = place_in_face(meta_, t, f, previous),
                       q = place_in_face(meta_, t, f, next);
            if (!p || !q) return false;
            length += (*q - *p).norm();
            found = true;
          }
        if (!found) return false;
        previous = next;
      }
      bent |= lodged != nullptr;
      return length > 0;
    };
    if (half_disc) {
      // A half-disc: v at the origin, its boundary edges along the x axis
      // (ring[0] on the positive side), the angles between consecutive
      // edges by the law of cosines scaled to sum to π, none above 0.95 π.
      std::vector<double> radius(m + 1), side(m), theta(m);
      for (std::size_t i = 0; i <= m; ++i)
        if (!image_length(chart.spoke[i], radius[i], bent)) return chart_fail(1);
      double total = 0;
      for (std::size_t i = 0; i < m; ++i) {
        if (!image_length(chart.boundary[i], side[i], bent)) return chart_fail(1);
        const double r0 = radius[i], r1 = radius[i + 1], b = side[i];
        const double c = (r0 * r0 + r1 * r1 - b * b) / (2 * r0 * r1);
        theta[i] = c > -1 + 1e-9 && c < 1 - 1e-9 ? std::acos(c) : M_PI / double(m);
        total += theta[i];
      }
      for (double& a : theta) a *= M_PI / total;
      cap_angles(theta);
      chart.centre = Vec2::Zero();
      chart.w.resize(m + 1);
      double phi = 0;
      for (std::size_t i = 0; i < m; ++i) {
        chart.w[i] = radius[i] * Vec2(std::cos(phi), std::sin(phi));
        phi += theta[i];
      }
      chart.w[m] = Vec2(-radius[m], 0);
    } else {
      std::vector<double> radius(m), side(m);
      for (std::size_t i = 0; i < m; ++i)
        if (!image_length(chart.spoke[i], radius[i], bent) ||
            !image_length(chart.boundary[i], side[i], bent))
          return chart_fail(1);
      // Directions: each edge as it leaves v (in the layout of v's face, or
      // around the vertex of t that v sits on, its fan unwrapped); consecutive
      // angles scaled to sum to 2π.
      auto first_place = [&](std::size_t i) {
        const int e = chart.spoke[i];
        const auto& list = S.crossings[e];
        const bool forward = S.edges[e][0] == v;
        if (list.empty())
          return std::optional<Place>(vertex_node(meta_, s, chart.ring[i]).place[t]);
        const auto node = break_node(meta_, s, e, forward ? 0 : int(list.size()) - 1);
        return node ? std::optional<Place>(node->place[t]) : std::nullopt;
      };
      std::vector<double> direction(m);
      double cone = 2 * M_PI;
      if (vloc.face >= 0) {
        // (chart.centre: set above, in this face's layout.)
        for (std::size_t i = 0; i < m; ++i) {
          const auto first = first_place(i);
          if (!first) return chart_fail(3);
          const auto q = place_in_face(meta_, t, vloc.face, *first);
          if (!q) return chart_fail(4);
          direction[i] = std::atan2((*q - chart.centre).y(), (*q - chart.centre).x());
        }
      } else {
        const int x = vloc.vertex;
        const auto& around = IT.vertex_faces[x];
        auto corner_of = [&](int f) {
          const Triangle& tri = T.faces[f];
          return tri[0] == x ? 0 : tri[1] == x ? 1 : 2;
        };
        std::vector<int> fan{around.front()};
        while (fan.size() < around.size()) {
          const int f = fan.back();
          const int last = T.faces[f][(corner_of(f) + 2) % 3];
          int next = -1;
          for (int g : around)
            if (T.faces[g][(corner_of(g) + 1) % 3] == last) next = g;
          if (next < 0 || next == fan.front()) return chart_fail(5);
          fan.push_back(next);
        }
        std::vector<double> start(fan.size() + 1, 0.0);
        for (std::size_t j = 0; j < fan.size(); ++j) {
          const int c = corner_of(fan[j]);
          const Layout3 L = meta_face_layout(T.lengths[fan[j]]);
          const Vec2 a = L[(c + 1) % 3] - L[c], b = L[(c + 2) % 3] - L[c];
          start[j + 1] = start[j] + std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
        }
        cone = start.back();
        chart.centre = Vec2::Zero();
        for (std::size_t i = 0; i < m; ++i) {
          const auto first = first_place(i);
          if (!first) return chart_fail(6);
          // The fan face the edge leaves x through, and its angle there.
          bool found = false;
          for (std::size_t j = 0; j < fan.size() && !found; ++j) {
            const int f = fan[j], c = corner_of(f);
            const auto q = place_in_face(meta_, t, f, *first);
            if (!q) continue;
            if (first->kind == Place::vertex && first->index != T.faces[f][(c + 1) % 3]) continue;
            if (first->kind == Place::edge && first->index != T.face_edges[f][(c + 1) % 3])
              continue;
            const Layout3 L = meta_face_layout(T.lengths[f]);
            const Vec2 a = L[(c + 1) % 3] - L[c], d = *q - L[c];
            direction[i] = start[j] + std::atan2(a.x() * d.y() - a.y() * d.x(), a.dot(d));
            found = true;
          }
          if (!found) return chart_fail(7);
        }
      }
      // Angles between consecutive edges: by the law of cosines on the lengths
      // of their images (paper §5.1), or, where those lengths break the
      // triangle inequality, as the edges leave v; scaled to sum to 2π, none
      // reaching π (so the ring is star-shaped around v in the chart).
      std::vector<double> theta(m);
      double total = 0, local_total = 0;
      for (std::size_t i = 0; i < m; ++i) {
        double d = direction[(i + 1) % m] - direction[i];
        d = std::fmod(std::fmod(d, cone) + cone, cone);
        if (!(d > 0)) return chart_fail(8);
        local_total += d;
        const double r0 = radius[i], r1 = radius[(i + 1) % m], b = side[i];
        const double c = (r0 * r0 + r1 * r1 - b * b) / (2 * r0 * r1);
        theta[i] = c > -1 + 1e-9 && c < 1 - 1e-9 ? std::acos(c) : d * 2 * M_PI / cone;
        total += theta[i];
      }
      if (!(total > 0) || local_total > 2 * cone + 1e-9) return chart_fail(9);
      rescale = vloc.face < 0 || std::abs(total - 2 * M_PI) > 1e-9;
      for (double& a : theta) a *= 2 * M_PI / total;
      if (cap_angles(theta)) rescale = true;
      total = 2 * M_PI;
      chart.w.resize(m);
      double phi = vloc.face >= 0 ? direction[0] : 0.0;
      for (std::size_t i = 0; i < m; ++i) {
        chart.w[i] = chart.centre + radius[i] * Vec2(std::cos(phi), std::sin(phi));
        phi += theta[i] * 2 * M_PI / total;
      }
    }
  }

  // Anchors: the ring's vertices and the break points of its boundary edges.
  std::map<NodeKey, int> anchor_of;
  auto add_anchor = [&](const MetaNode& node, const Vec2& pos) {
    auto [it, added] = anchor_of.try_emplace(node.key, int(chart.anchors.size()));
    if (added) chart.anchors.push_back({node, pos});
    return it->second;
  };
  for (std::size_t i = 0; i < nr; ++i) {
    const int a = add_anchor(vertex_node(meta_, s, chart.ring[i]), chart.w[i]);
    chart.ring_anchor.push_back(a);
    chart.loop_start.push_back(chart.boundary_loop.size());
    chart.boundary_loop.push_back(a);
    if (i == m) break;  // (a half-disc's last neighbour)
    const int e = chart.boundary[i];
    const auto& list = S.crossings[e];
    const bool forward = S.edges[e][0] == chart.ring[i];
    const Vec2 &p = chart.w[i], &q = chart.w[(i + 1) % nr];
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int n = int(forward ? k : list.size() - 1 - k);
      if (list[n].is_kink()) bent = true;
      const auto node = break_node(meta_, s, e, n);
      if (!node) return chart_fail(227);
      const double u = forward ? list[n].here : 1 - list[n].here;
      chart.boundary_loop.push_back(add_anchor(
          *node, chart.boundary_breaks.empty() ? p + u * (q - p) : chart.boundary_breaks[i][k]));
    }
    // t's vertices on a boundary edge, in order from ring[i] (a boundary
    // edge has no break points; the chart is not a development here).
    if (boundary_lodgers && IS.is_boundary(e)) {
      const auto& lodged = IS.on_edge[e];
      for (std::size_t k = 0; k < lodged.size(); ++k) {
        const int x = lodged[forward ? k : lodged.size() - 1 - k];
        const double u = forward ? T.location[x].t : 1 - T.location[x].t;
        chart.boundary_loop.push_back(add_anchor(vertex_node(meta_, t, x), p + u * (q - p)));
      }
    }
  }
  if (half_disc) {
    // Back along v's boundary edges: t's vertices on (v, ring[m]) from
    // ring[m], v itself (at its place, or slid to `slide` between its
    // neighbours on the line), t's vertices on (v, ring[0]).
    auto lodgers = [&](int e, bool from_v) {
      std::vector<std::pair<double, int>> list;  // (parameter from v, vertex of t)
      for (int x : IS.on_edge[e])
        list.push_back({S.edges[e][0] == v ? T.location[x].t : 1 - T.location[x].t, x});
      std::sort(list.begin(), list.end());
      if (!from_v) std::reverse(list.begin(), list.end());
      return list;
    };
    for (const auto& [u, x] : lodgers(chart.spoke[m], false))
      chart.boundary_loop.push_back(add_anchor(vertex_node(meta_, t, x), u * chart.w[m]));
    const auto after = lodgers(chart.spoke[0], true);
    MetaNode self = vertex_node(meta_, s, v);
    Vec2 at = chart.centre;
    if (slide) {
      // Where the slide puts v on t's boundary edge, between the anchors
      // before and after it on the line.
      const int before = chart.boundary_loop.back();
      const int next = after.empty() ? chart.ring_anchor[0] : -1;
      const Vec2 p_next = after.empty() ? chart.w[0] : after.front().first * chart.w[0];
      const Place& q_before = chart.anchors[before].node.place[t];
      const Place q_next = next >= 0 ? chart.anchors[next].node.place[t]
                                     : vertex_node(meta_, t, after.front().second).place[t];
      auto along = [&](const Place& q) {
        const int g = slide->index;
        if (q.kind == Place::edge && q.index == g) return q.t;
        if (q.kind == Place::vertex && q.index == T.edges[g][0]) return 0.0;
        if (q.kind == Place::vertex && q.index == T.edges[g][1]) return 1.0;
        return std::nan("");
      };
      const double a = along(q_before), b = along(q_next);
      const double lambda = (slide->t - a) / (b - a);
      if (slide->kind != Place::edge || !(lambda > 0 && lambda < 1)) return chart_fail(22);
      at = chart.anchors[before].pos + lambda * (p_next - chart.anchors[before].pos);
      self.place[t] = *slide;
    }
    chart.slider = add_anchor(self, at);
    chart.boundary_loop.push_back(chart.slider);
    for (const auto& [u, x] : after)
      chart.boundary_loop.push_back(add_anchor(vertex_node(meta_, t, x), u * chart.w[0]));
  }
  // t's vertices inside: under v, and in the ring's faces (where their
  // barycentric coordinates put them in the chart).
  if (vloc.vertex >= 0) {
    chart.centre_anchor = add_anchor(vertex_node(meta_, t, vloc.vertex), chart.centre);
    chart.interior.push_back(chart.centre_anchor);
  }
  for (std::size_t i = 0; i < m; ++i) {
    const int f = chart.faces[i], c = chart.corner[i];
    std::array<Vec2, 3> corner;
    corner[c] = chart.centre;
    corner[(c + 1) % 3] = chart.w[i];
    corner[(c + 2) % 3] = chart.w[(i + 1) % nr];
    for (int x : IS.residents[f]) {
      const Eigen::Vector3d& b = T.location[x].bary;
      chart.interior.push_back(add_anchor(vertex_node(meta_, t, x), from_barycentric(b, corner)));
    }
  }

  // Chords: the pieces of t's edges inside the ring, between anchors. Each
  // lies between the anchors on its edge, so only the break points of an
  // edge between its first and last anchor are visited (with one more on
  // each side): an edge of an abstract domain has thousands.
  struct Span {
    int edge;
    double lo, hi;  // along the edge
  };
  std::vector<Span> spans;
  for (const auto& anchor : chart.anchors) {
    // (t's boundary edges lie on the ring's boundary: they are no chords.)
    const Place& p = anchor.node.place[t];
    if (p.kind == Place::edge && !(IT.open && IT.is_boundary(p.index)))
      spans.push_back({p.index, p.t, p.t});
    if (p.kind == Place::vertex)
      for (int g : IT.vertex_edges[p.index]) {
        if (IT.open && IT.is_boundary(g)) continue;
        const double at = T.edges[g][0] == p.index ? 0.0 : 1.0;
        spans.push_back({g, at, at});
      }
  }
  std::sort(spans.begin(), spans.end(),
            [](const Span& a, const Span& b) { return a.edge < b.edge; });
  std::vector<Span> edges;
  for (const Span& x : spans)
    if (edges.empty() || edges.back().edge != x.edge) {
      edges.push_back(x);
    } else {
      edges.back().lo = std::min(edges.back().lo, x.lo);
      edges.back().hi = std::max(edges.back().hi, x.hi);
    }
  auto in_ring = [&](int f) {
    return std::find(chart.faces.begin(), chart.faces.end(), f) != chart.faces.end();
  };
  std::vector<MetaNode> points;

  for (const Span& span : edges) {
    const int g = span.edge;
    const auto& list = T.crossings[g];
    const int n = int(list.size());
    auto param = [&](int j) { return j == 0 ? 0.0 : j == n + 1 ? 1.0 : list[j - 1].here; };
    // Points first..last of 0 (g's first vertex), 1..n (its break points),
    // n + 1 (its second vertex).
    const auto by_here = [](const MetaCrossing& c, double h) { return c.here < h; };
    const int first =
        int(std::lower_bound(list.begin(), list.end(), span.lo, by_here) - list.begin());
    const int last = std::min(
        n + 1,
        int(std::lower_bound(list.begin(), list.end(), span.hi, by_here) - list.begin()) + 2);
    points.clear();
    for (int j = first; j <= last; ++j) {
      if (j == 0 || j == n + 1) {
        points.push_back(vertex_node(meta_, t, T.edges[g][j == 0 ? 0 : 1]));
        continue;
      }
      const auto node = break_node(meta_, t, g, j - 1);
      if (!node) return chart_fail(271);
      points.push_back(*node);
    }
    auto point = [&](int j) -> const MetaNode& { return points[j - first]; };
    int run = -1;
    for (int j = first; j < last; ++j) {
      const Place &a = point(j).place[s], &b = point(j + 1).place[s];
      bool inside = false;
      if (a.kind == Place::vertex && b.kind == Place::vertex) {
        inside = (a.index == v || b.index == v) && a.index != b.index;  // along a spoke
      } else {
        place_faces(meta_, index_, s, a, faces_a);
        place_faces(meta_, index_, s, b, faces_b);
        int common = 0, ring_face = 0;
        for (int f : faces_a)
          if (std::find(faces_b.begin(), faces_b.end(), f) != faces_b.end())
            ++common, ring_face += in_ring(f);
        if (common > 1 && ring_face > 0) return chart_fail(288);  // along an edge inside the ring
        inside = common == 1 && ring_face == 1;
      }
      if (inside && run < 0) run = j;
      if (!inside || j == last - 1) {
        if (run >= 0) {
          const int end = inside ? j + 1 : j;
          const auto ia = anchor_of.find(point(run).key), ib = anchor_of.find(point(end).key);
          if (ia == anchor_of.end() || ib == anchor_of.end() || ia->second == ib->second)
            return chart_fail(296);
          chart.chords.push_back({ia->second, ib->second, g, param(run), param(end), run, end - 1});
          for (int k = run + 1; k < end; ++k)
            if (list[k - 1].is_kink()) bent = true;
          run = -1;
        }
      }
    }
  }

  // The cells of t's content in the chart, each in one face of t: if the
  // content folds where it is, its inner vertices are relaxed by mean-value
  // weights (paper §5.1), and if it still folds, the ring is mapped to a
  // convex polygon inscribed in a circle first.
  auto make_fragments = [&]() {
    chart.fragments.clear();
    // Work lists kept per thread (a chart is built for every optimisation).
    thread_local std::vector<Vec2> position;
    thread_local std::vector<std::array<int, 2>> segments;
    thread_local PlanarCells cells;
    thread_local std::vector<int> common;
    if (position.capacity() > 4096) {  // (after a large chart: let its storage go)
      std::vector<Vec2>().swap(position);
      std::vector<std::array<int, 2>>().swap(segments);
      cells = PlanarCells{};
    }
    position.clear(), segments.clear();
    for (const auto& a : chart.anchors) position.push_back(a.pos);
    const std::size_t nb = chart.boundary_loop.size();
    for (std::size_t i = 0; i < nb; ++i)
      segments.push_back({chart.boundary_loop[i], chart.boundary_loop[(i + 1) % nb]});
    for (const auto& c : chart.chords) segments.push_back({c.a, c.b});
    if (!planar_cells(position, segments, cells)) return chart_fail(401);
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::span<const int> cell = cells[i];
      Chart::Fragment fragment;
      place_faces(meta_, index_, t, chart.anchors[cell[0]].node.place[t], common);
      for (std::size_t i = 1; i < cell.size(); ++i) {
        place_faces(meta_, index_, t, chart.anchors[cell[i]].node.place[t], faces_a);
        std::erase_if(common, [&](int h) {
          return std::find(faces_a.begin(), faces_a.end(), h) == faces_a.end();
        });
      }
      fragment.face = -1;
      for (int h : common) {
        std::vector<Vec2> other;
        const std::array<Vec2, 3> Lh = meta_face_layout(T.lengths[h]);
        for (int c : cell) {
          const auto p = place_in_face(meta_, t, h, Lh, chart.anchors[c].node.place[t]);
          if (!p) break;
          other.push_back(*p);
        }
        if (other.size() != cell.size() || !(polygon_area(other) > 0)) continue;
        fragment.face = h;
        fragment.other = std::move(other);
      }
      if (fragment.face < 0) return chart_fail(402);
      std::vector<Vec2> in_chart;
      for (int c : cell) in_chart.push_back(position[c]);
      // The cell's map to t: affine where the chart is a true development
      // there; otherwise through a triangulation valid on both, and edges
      // crossing it may bend at its diagonals.
      auto made = make_chart_cell(std::move(in_chart), std::move(fragment.other));
      if (!made) return chart_fail(403);
      static_cast<ChartCell&>(fragment) = std::move(*made);
      const auto inside = ear_point(position, cell);
      if (!inside) return chart_fail(404);
      fragment.inside = *inside;
      fragment.nodes.assign(cell.begin(), cell.end());
      fragment.summable = cell.size() == 3 && fragment.affine;
      for (int c : cell) fragment.summable &= chart.anchors[c].node.place[s].kind != Place::edge;
      if (fragment.summable)
        fragment.summable =
            fragment.moments.add({fragment.chart[0], fragment.chart[1], fragment.chart[2]},
                                 {fragment.other[0], fragment.other[1], fragment.other[2]});
      chart.fragments.push_back(std::move(fragment));
    }
    chart.chord_of.clear();
    for (std::size_t c = 0; c < chart.chords.size(); ++c) {
      auto& chord = chart.chords[c];
      chart.chord_of[undirected_edge_key(chord.a, chord.b)] = int(c);
      chord.lo = position[chord.a].cwiseMin(position[chord.b]);
      chord.hi = position[chord.a].cwiseMax(position[chord.b]);
    }
    chart.chord_fragments.assign(chart.chords.size(), {-1, -1});
    for (std::size_t j = 0; j < chart.fragments.size(); ++j) {
      const auto& nodes = chart.fragments[j].nodes;
      for (std::size_t k = 0; k < nodes.size(); ++k) {
        const auto it =
            chart.chord_of.find(undirected_edge_key(nodes[k], nodes[(k + 1) % nodes.size()]));
        if (it == chart.chord_of.end()) continue;
        auto& sides = chart.chord_fragments[it->second];
        sides[sides[0] < 0 ? 0 : 1] = int(j);
      }
    }
    // The cells must tile the ring (no chord crossing another or the ring).
    std::vector<Vec2> loop;
    for (int a : chart.boundary_loop) loop.push_back(chart.anchors[a].pos);
    double covered = 0;
    for (const auto& f : chart.fragments) covered += polygon_area(f.chart);
    const double ring_area = polygon_area(loop);
    if (!(ring_area > 0 && std::abs(covered - ring_area) <= 1e-9 * ring_area))
      return chart_fail(410);
    chart.curved.clear();
    for (std::size_t i = 0; i < chart.fragments.size(); ++i)
      if (!chart.fragments[i].affine) chart.curved.push_back(int(i));
    return true;
  };
  auto relax = [&](bool fix_centre) {
    if (chart.interior.empty()) return;
    // Mean-value weights of each inner vertex x of t over the anchors its
    // chords reach, from t's metric: angles at x (scaled to 2π) and lengths.
    // The vertex of t under v stays where v is (the ring is star-shaped
    // around that point).
    std::vector<int> slot(chart.anchors.size(), -1);
    for (std::size_t k = 0; k < chart.interior.size(); ++k)
      if (!fix_centre || chart.interior[k] != chart.centre_anchor) slot[chart.interior[k]] = int(k);
    std::vector<std::vector<std::pair<int, double>>> weights(chart.interior.size());
    std::vector<std::vector<int>> chords_at(chart.anchors.size());
    for (std::size_t c = 0; c < chart.chords.size(); ++c)
      for (int end : {chart.chords[c].a, chart.chords[c].b}) chords_at[end].push_back(int(c));
    for (std::size_t k = 0; k < chart.interior.size(); ++k) {
      const int xa = chart.interior[k];
      const int x = chart.anchors[xa].node.place[t].index;
      std::vector<std::pair<double, std::pair<int, double>>> spokes;  // angle, (anchor, length)
      const auto angles = vertex_edge_angles(t, x);
      for (const int ci : chords_at[xa]) {
        const auto& c = chart.chords[ci];
        const int other = c.a == xa ? c.b : c.a;
        const auto it = angles.find(c.edge);
        if (it == angles.end()) continue;
        const int h =
            IT.edge_faces[c.edge][0] >= 0 ? IT.edge_faces[c.edge][0] : IT.edge_faces[c.edge][1];
        int kk = 0;
        while (T.face_edges[h][kk] != c.edge) ++kk;
        spokes.push_back({it->second, {other, std::abs(c.tb - c.ta) * T.lengths[h][kk]}});
      }
      std::sort(spokes.begin(), spokes.end());
      const std::size_t n = spokes.size();
      for (std::size_t j = 0; j < n; ++j) {
        auto half_tan = [&](std::size_t i0, std::size_t i1) {
          double a = spokes[i1].first - spokes[i0].first;
          if (a <= 0) a += 2 * M_PI;
          return std::tan(0.5 * std::min(a, M_PI - 1e-6));
        };
        const double w = (half_tan((j + n - 1) % n, j) + half_tan(j, (j + 1) % n)) /
                         std::max(spokes[j].second.second, 1e-300);
        weights[k].push_back({spokes[j].second.first, std::max(w, 1e-12)});
      }
    }
    // Each inner vertex at the weighted mean of its neighbours: one sparse
    // linear system (a Tutte embedding when the boundary is convex; a
    // cone's chart holds half the surface).
    const int ni = int(chart.interior.size());
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni, 2);
    for (int k = 0; k < ni; ++k) {
      if (weights[k].empty() || (fix_centre && chart.interior[k] == chart.centre_anchor)) {
        entries.push_back({k, k, 1.0});
        rhs.row(k) = chart.anchors[chart.interior[k]].pos.transpose();
        continue;
      }
      for (const auto& [a, w] : weights[k]) {
        entries.push_back({k, k, w});
        if (slot[a] >= 0)
          entries.push_back({k, slot[a], -w});
        else
          rhs.row(k) += w * chart.anchors[a].pos.transpose();
      }
    }
    Eigen::SparseMatrix<double> M(ni, ni);
    M.setFromTriplets(entries.begin(), entries.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(M);
    if (lu.info() != Eigen::Success) return;
    const Eigen::MatrixXd x = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !x.allFinite()) return;
    for (int k = 0; k < ni; ++k) chart.anchors[chart.interior[k]].pos = x.row(k).transpose();
  };
  bool laid_out = make_fragments();
  if (!laid_out && !chart.interior.empty()) {
    relax(true);
    laid_out = make_fragments();
  }
  if (!laid_out && half_disc) return chart_fail(23);
  if (!laid_out) {
    // Convex: the ring's vertices on a circle at the chart's angles, the
    // boundary's break points on the straight sides between them.
    double mean_radius = 0;
    for (std::size_t i = 0; i < m; ++i)
      mean_radius += (chart.w[i] - chart.centre).norm() / double(m);
    double angle = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const Vec2 d = chart.w[i] - chart.centre;
      if (i == 0) angle = std::atan2(d.y(), d.x());
      chart.w[i] = chart.centre + mean_radius * Vec2(std::cos(angle), std::sin(angle));
      const Vec2 d1 = chart.w[(i + 1) % m] - chart.centre;
      double step = std::atan2(d.x() * d1.y() - d.y() * d1.x(), d.dot(d1));
      if (step <= 0) step += 2 * M_PI;
      angle += std::min(step, M_PI * 0.999);
    }
    for (std::size_t i = 0; i < m; ++i) {
      chart.anchors[chart.ring_anchor[i]].pos = chart.w[i];
      const int e = chart.boundary[i];
      const bool forward = S.edges[e][0] == chart.ring[i];
      for (const auto& a : chart.boundary_loop) {
        const Place& p = chart.anchors[a].node.place[s];
        if (p.kind != Place::edge || p.index != e) continue;
        const double u = forward ? p.t : 1 - p.t;
        chart.anchors[a].pos = chart.w[i] + u * (chart.w[(i + 1) % m] - chart.w[i]);
      }
    }
    rescale = true;
    chart.straight_boundary = true;
    relax(false);
    laid_out = make_fragments();
  }
  if (!laid_out) return false;
  if (chart.centre_anchor >= 0) chart.centre = chart.anchors[chart.centre_anchor].pos;
  // Is the chart an isometric development of t around the ring? Then every
  // cell of t's content is congruent to its image.
  bool isometric = !rescale && !bent && chart.interior.empty() && chart.straight_boundary;
  for (const auto& fragment : chart.fragments) {
    const auto &p = fragment.chart, &q = fragment.other;
    for (std::size_t j = 1; j < p.size() && isometric; ++j)
      for (std::size_t k : {std::size_t(0), (j + 1) % p.size()}) {
        const double a = (p[j] - p[k]).norm(), b = (q[j] - q[k]).norm();
        if (std::abs(a - b) > 1e-9 * (a + b)) isometric = false;
      }
  }
  chart.kind = isometric ? Chart::developed : Chart::general;
  return true;
}

// ---------------------------------------------------------------- evaluation

namespace {

/// A new crossing of an inner edge with a chord, in evaluate().
struct SpokeHit {
  double u;  // along the spoke
  int node;
  int chord;
  double lambda;  // along the chord
};

/// Resizes a list of lists to n, each empty (their storage kept).
template <class T>
void reset_lists(std::vector<std::vector<T>>& lists, std::size_t n) {
  lists.resize(n);
  for (auto& list : lists) list.clear();
}

/// evaluate()'s work arrays, kept between calls (one set per thread): an
/// optimisation evaluates its chart some forty times (its line searches),
/// and allocating them afresh each time was nearly a quarter of the
/// refinement's instructions.
struct EvaluateBuffers {
  std::vector<Vec2> pos;
  std::vector<int> inner_node, inner_fragment;
  std::vector<Place> place, s_place;
  std::vector<std::vector<SpokeHit>> spoke_hits;
  std::vector<std::vector<std::pair<double, int>>> chord_hits, spoke_chain;
  std::vector<char> chord_used, is_kink, cut;
  std::vector<std::pair<int, int>> kink_fragment;
  std::vector<std::array<int, 2>> spoke_segments, segments;
  std::vector<std::array<Vec2, 3>> tri_chart;
  std::vector<int> common, faces, node_chord, node_fragment, segment_fragment, split;
  std::vector<StretchMoments> per_tri;
  std::vector<double> part;
  struct SummedPart {  // a fragment's share of a face of s (the anisotropy penalty's)
    int tri, fragment;
    double share;
  };
  std::vector<SummedPart> summed_parts;
  std::vector<Eigen::Matrix2d> to_s;
  std::vector<std::uint64_t> node_tris;
  // Each node's corner in a cell, on s and on t, memoised: the face (chart
  // triangle on s, face of t) it was last placed in, and where.
  std::vector<int> s_corner_tri, t_corner_face;
  std::vector<Vec2> s_corner;
  std::vector<std::optional<Vec2>> t_corner;
  MetaPiece piece;
  PlanarCells cells;
};

}  // namespace

void InterSurfaceMap::evaluate_each(const Chart& chart, const Layout& layout,
                                    std::span<const Vec2> at, std::span<double> out,
                                    std::size_t grain) const {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, at.size(), std::max<std::size_t>(grain, 1)),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Layout local = layout;
                      for (std::size_t k = range.begin(); k < range.end(); ++k) {
                        local.inner[0].pos = at[k];
                        out[k] = evaluate(chart, local, nullptr);
                      }
                    });
}

double InterSurfaceMap::evaluate(const Chart& chart, const Layout& layout, Proposal* out) const {
  const int s = chart.s, t = chart.t;
  const MetaSide& S = meta_.side[s];
  const EnergyTerms terms = energy_terms();
  const std::size_t A = chart.anchors.size();
  auto eval_fail = [&](int where) {
    chart_failure_ = 1000 + where;
    return HUGE_VAL;
  };
  thread_local EvaluateBuffers buffers;
  // Chart points: anchors, then inner vertices that are not on an anchor.
  auto& pos = buffers.pos;
  pos.clear();
  for (const auto& a : chart.anchors) pos.push_back(a.pos);
  auto& inner_node = buffers.inner_node;
  inner_node.assign(layout.inner.size(), 0);
  for (std::size_t k = 0; k < layout.inner.size(); ++k) {
    if (layout.inner[k].on_anchor >= 0) {
      inner_node[k] = layout.inner[k].on_anchor;
    } else {
      inner_node[k] = int(pos.size());
      pos.push_back(layout.inner[k].pos);
    }
  }
  auto node_of = [&](int ref) { return ref >= 0 ? chart.ring_anchor[ref] : inner_node[-1 - ref]; };

  const MetaSide& side1 = meta_.side[1];
  // A triangle of s over one face of t (`face`: s's face, t's is the fast
  // chart's single face).
  auto sides = [&](const std::array<Vec2, 3>& mine, const std::array<Vec2, 3>& theirs, int face,
                   double& e) {
    e = s == 0
            ? triangle_energy(mine, theirs, terms, terms.forward_weight(side1, chart.single_face))
            : triangle_energy(theirs, mine, terms, terms.forward_weight(side1, face));
  };
  // Every triangle of the ring one affine map: the energy is their sum.
  auto affine_sum = [&] {
    double sum = 0;
    for (const auto& tri : layout.tris) {
      const std::array<Vec2, 3> q{pos[node_of(tri.ref[0])], pos[node_of(tri.ref[1])],
                                  pos[node_of(tri.ref[2])]};
      double e;
      sides(tri.shape, q, tri.face, e);
      sum += e;
      if (!(sum < HUGE_VAL)) return eval_fail(31);
    }
    return sum;
  };
  const bool affine = affine_ring(chart);
  if (!out && affine) return affine_sum();
  if (chart.kind == Chart::fast) {
    // One face of t holds the ring and all it moves: the layout's triangles
    // are the pieces (each in that face), the inner edges cross nothing, and
    // the proposal is the inner vertices' places in the face.
    const std::array<Vec2, 3> L = meta_face_layout(meta_.side[t].lengths[chart.single_face]);
    out->clear();
    for (const auto& in : layout.inner) {
      if (in.on_anchor >= 0) continue;
      const Eigen::Vector3d b = barycentric(in.pos, L[0], L[1], L[2]);
      if (b.minCoeff() < layout.clearance) return eval_fail(96);  // too close to an edge of t
      out->locations[0].push_back({in.vertex, MetaLocation{-1, chart.single_face, b / b.sum()}});
    }
    for (const auto& tri : layout.tris)
      if (!(orient(pos[node_of(tri.ref[0])], pos[node_of(tri.ref[1])], pos[node_of(tri.ref[2])]) >
            0))
        return eval_fail(140);
    const double sum = affine_sum();
    if (!(sum < HUGE_VAL)) return HUGE_VAL;
    for (const auto& spoke : layout.spokes) out->lists.push_back({spoke.edge, {}});
    return sum;
  }

  // Where each point lies on t.
  auto& place = buffers.place;
  place.assign(A, Place{});
  for (std::size_t i = 0; i < A; ++i) place[i] = chart.anchors[i].node.place[t];
  place.resize(pos.size());
  auto& inner_fragment = buffers.inner_fragment;
  inner_fragment.assign(layout.inner.size(), -1);
  for (std::size_t k = 0; k < layout.inner.size(); ++k) {
    if (layout.inner[k].on_anchor >= 0) continue;
    const Vec2& p = layout.inner[k].pos;
    int face = -1;
    Vec2 q;
    if (chart.kind == Chart::fast) {
      face = chart.single_face;
      q = p;
    } else {
      for (std::size_t j = 0; j < chart.fragments.size(); ++j)
        if (inside_cell(chart.fragments[j], p)) {
          face = chart.fragments[j].face;
          q = cell_image(chart.fragments[j], p);
          inner_fragment[k] = int(j);
          break;
        }
    }
    if (face < 0) return eval_fail(56);
    const std::array<Vec2, 3> L = meta_face_layout(meta_.side[t].lengths[face]);
    const Eigen::Vector3d b = barycentric(q, L[0], L[1], L[2]);
    if (b.minCoeff() < layout.clearance) return eval_fail(96);  // too close to an edge of t
    place[inner_node[k]] = {Place::face, face, 0, b / b.sum()};
  }

  // New crossings of the inner edges with the chords.
  using Hit = SpokeHit;
  auto& spoke_hits = buffers.spoke_hits;
  reset_lists(spoke_hits, layout.spokes.size());
  auto& chord_hits = buffers.chord_hits;
  reset_lists(chord_hits, chart.chords.size());
  auto& chord_used = buffers.chord_used;
  chord_used.assign(chart.chords.size(), 1);
  for (std::size_t i = 0; i < layout.spokes.size(); ++i) {
    const int na = node_of(layout.spokes[i].a), nb = node_of(layout.spokes[i].b);
    const Vec2 P = pos[na], Q = pos[nb];
    // (make_fragments' planar cells admit one chord per pair of anchors.)
    if (const auto it = chart.chord_of.find(undirected_edge_key(na, nb));
        it != chart.chord_of.end()) {
      chord_used[it->second] = 0;  // the edge of t runs along this inner edge
      continue;
    }
    // Chords whose box lies apart from the edge's cannot cross it (the gap,
    // 10⁻⁹ of the coordinates' size, is far above the orientations'
    // rounding).
    const Vec2 lo = P.cwiseMin(Q), hi = P.cwiseMax(Q);
    const double gap = 1e-9 * std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    for (std::size_t c = 0; c < chart.chords.size(); ++c) {
      const auto& chord = chart.chords[c];
      if (boxes_apart(lo, hi, chord.lo, chord.hi, gap)) continue;
      if (chord.a == na || chord.a == nb || chord.b == na || chord.b == nb) continue;
      const Vec2 &C = pos[chord.a], &D = pos[chord.b];
      const double o1 = orient(P, Q, C), o2 = orient(P, Q, D);
      if ((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0)) continue;
      const double o3 = orient(C, D, P), o4 = orient(C, D, Q);
      if ((o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0)) continue;
      if (o1 == 0 || o2 == 0 || o3 == 0 || o4 == 0) {
        return eval_fail(93);  // touching
      }
      const double u = o3 / (o3 - o4), lambda = o1 / (o1 - o2);
      // Nearly through a vertex or an end: pieces of no size.
      // Kept clear of ends and vertices (1e-6 relative): no piece of
      // vanishing size, which later charts could not lay out.
      const double clear = layout.clearance;
      if (u < clear || u > 1 - clear || lambda < clear || lambda > 1 - clear) return eval_fail(94);
      const int node = int(pos.size());
      pos.push_back(P + u * (Q - P));
      place.push_back({Place::edge, chord.edge, chord.ta + lambda * (chord.tb - chord.ta),
                       Eigen::Vector3d::Zero()});
      spoke_hits[i].push_back({u, node, int(c), lambda});
      chord_hits[c].push_back({lambda, node});
    }
  }
  // Each inner edge: its crossings in order, and kinks where it runs
  // through a cell of t's content that is not convex on t (paper §5.1,
  // Figure 4: there a straight segment on t could leave the cell, so the
  // edge follows the cell's triangulation and bends at its diagonals).
  auto& spoke_chain = buffers.spoke_chain;
  reset_lists(spoke_chain, layout.spokes.size());
  auto& is_kink = buffers.is_kink;
  auto& kink_fragment = buffers.kink_fragment;  // kink node, the fragment it bends in
  kink_fragment.clear();
  for (std::size_t i = 0; i < layout.spokes.size(); ++i) {
    auto& hits = spoke_hits[i];
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.u < b.u; });
    auto& chain = spoke_chain[i];
    const int na = node_of(layout.spokes[i].a), nb_ = node_of(layout.spokes[i].b);
    chain.push_back({0.0, na});
    for (const Hit& h : hits) chain.push_back({h.u, h.node});
    chain.push_back({1.0, nb_});
    if (chart.kind == Chart::general) {
      const Vec2 P = pos[na], Q = pos[nb_];
      const int first_kink = int(pos.size());
      std::vector<std::pair<double, int>> kinks;
      for (std::size_t j = 0; j + 1 < chain.size(); ++j) {
        const Vec2 mid = 0.5 * (pos[chain[j].second] + pos[chain[j + 1].second]);
        for (const int curved : chart.curved) {
          const Chart::Fragment& fragment = chart.fragments[curved];
          if (!inside_cell(fragment, mid)) continue;
          // The segment's ends mapped to t; where it bends there, as the
          // options' kink rule says (paper §5.1: only where a straight
          // segment between them would leave the cell).
          const std::array<Vec2, 3> L = meta_face_layout(meta_.side[t].lengths[fragment.face]);
          const auto a = place_in_face(meta_, t, fragment.face, L, place[chain[j].second]);
          const auto b = place_in_face(meta_, t, fragment.face, L, place[chain[j + 1].second]);
          const double size =
              std::max({(L[1] - L[0]).norm(), (L[2] - L[1]).norm(), (L[0] - L[2]).norm()});
          const Vec2 A = pos[chain[j].second], B = pos[chain[j + 1].second];
          // Kinks clear of t's edges as a moved vertex is (a kink that close
          // leaves pieces later charts cannot lay out), and of the segment's
          // ends. Under follow_cells a segment whose bends would not be
          // clear bends only where it must (where_needed).
          auto clear = [&](const CellKink& kink) {
            return barycentric(kink.other, L[0], L[1], L[2]).minCoeff() >= layout.clearance &&
                   !(a && (kink.other - *a).norm() < layout.clearance * size) &&
                   !(b && (kink.other - *b).norm() < layout.clearance * size);
          };
          KinkRule rule = a && b ? options_.kinks : KinkRule::follow_cells;
          std::vector<CellKink> bends =
              cell_kinks(fragment, A, B, a.value_or(A), b.value_or(B), rule);
          if (rule == KinkRule::follow_cells && a && b &&
              !std::all_of(bends.begin(), bends.end(), clear))
            bends = cell_kinks(fragment, A, B, *a, *b, KinkRule::where_needed);
          for (const CellKink& kink : bends) {
            const int node = int(pos.size());
            const Eigen::Vector3d bary = barycentric(kink.other, L[0], L[1], L[2]);
            if (!clear(kink)) return eval_fail(bary.minCoeff() < layout.clearance ? 97 : 98);
            kink_fragment.push_back({node, curved});
            pos.push_back(kink.chart);
            place.push_back({Place::face, fragment.face, 0, clamp_bary(bary)});
            kinks.push_back({(kink.chart - P).dot(Q - P) / (Q - P).squaredNorm(), node});
          }
          break;
        }
      }
      chain.insert(chain.end() - 1, kinks.begin(), kinks.end());
      std::sort(chain.begin(), chain.end());
      // Kinks clear of the spoke's other break points, as crossings are
      // of its ends.
      for (std::size_t k = 1; k + 1 < chain.size(); ++k)
        if (chain[k].second >= first_kink &&
            (chain[k].first - chain[k - 1].first < layout.clearance ||
             chain[k + 1].first - chain[k].first < layout.clearance))
          return eval_fail(95);
    }
  }
  auto& s_place = buffers.s_place;  // places on s of the new crossings and kinks
  s_place.assign(pos.size(), Place{});
  is_kink.assign(pos.size(), 0);
  for (std::size_t i = 0; i < layout.spokes.size(); ++i)
    for (const auto& [u, node] : spoke_chain[i])
      if (node >= int(A + layout.inner.size()) && place[node].kind == Place::face)
        is_kink[node] = 1;
  auto& spoke_segments = buffers.spoke_segments;
  spoke_segments.clear();
  for (std::size_t i = 0; i < layout.spokes.size(); ++i) {
    const int e = layout.spokes[i].edge;
    const int first_vertex = layout.spokes[i].a >= 0 ? chart.ring[layout.spokes[i].a]
                                                     : layout.inner[-1 - layout.spokes[i].a].vertex;
    const bool forward = S.edges[e][0] == first_vertex;
    const auto& chain = spoke_chain[i];
    for (std::size_t j = 0; j < chain.size(); ++j) {
      if (j > 0 && j + 1 < chain.size())
        s_place[chain[j].second] = {Place::edge, e, forward ? chain[j].first : 1 - chain[j].first,
                                    Eigen::Vector3d::Zero()};
      if (j > 0) spoke_segments.push_back({chain[j - 1].second, chain[j].second});
    }
  }
  for (auto& hits : chord_hits) std::sort(hits.begin(), hits.end());
  // The pieces of a side of a fragment or of the ring between two anchors:
  // a chord's split at its new crossings.
  auto add_side = [&](int a, int b, std::vector<std::array<int, 2>>& out_segments) {
    const auto it = chart.chord_of.find(undirected_edge_key(a, b));
    if (it == chart.chord_of.end()) {
      out_segments.push_back({a, b});
      return;
    }
    const int c = it->second;
    if (!chord_used[c]) return;  // an inner edge runs along it
    int previous = chart.chords[c].a;
    for (const auto& [lambda, node] : chord_hits[c]) {
      out_segments.push_back({previous, node});
      previous = node;
    }
    out_segments.push_back({previous, chart.chords[c].b});
  };

  // The face of s each triangle of the layout is, for locating cells.
  auto& tri_chart = buffers.tri_chart;
  tri_chart.clear();
  for (const auto& tri : layout.tris) {
    tri_chart.push_back(
        {pos[node_of(tri.ref[0])], pos[node_of(tri.ref[1])], pos[node_of(tri.ref[2])]});
    if (!(orient(tri_chart.back()[0], tri_chart.back()[1], tri_chart.back()[2]) > 0))
      return eval_fail(140);
  }
  // Sets of faces of s: a bit per triangle of the layout (all of them past
  // 64 faces).
  const std::size_t T = tri_chart.size();
  const std::uint64_t all_tris = T >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << T) - 1;
  // Of the faces `allowed`, the one whose chart triangle is nearest to
  // holding p (the largest smallest barycentric coordinate).
  auto deepest = [&](const Vec2& p, std::uint64_t allowed) {
    // A triangle that holds p strictly, if it is the only one, is the
    // deepest (its smallest coordinate is positive, every other's is not;
    // the signs are barycentric's own numerators): found without divisions.
    int holding = -1, n_holding = 0;
    for (std::size_t i = 0; i < T && n_holding < 2; ++i) {
      if (i < 64 && !(allowed >> i & 1)) continue;
      const auto& c = tri_chart[i];
      if (orient(p, c[1], c[2]) > 0 && orient(c[0], p, c[2]) > 0 && orient(c[0], c[1], p) > 0)
        holding = int(i), ++n_holding;
    }
    if (n_holding == 1) return holding;
    int best = -1;
    double depth = -HUGE_VAL;
    for (std::size_t i = 0; i < T; ++i) {
      if (i < 64 && !(allowed >> i & 1)) continue;
      const double b = barycentric(p, tri_chart[i][0], tri_chart[i][1], tri_chart[i][2]).minCoeff();
      if (b > depth) depth = b, best = int(i);
    }
    return best;
  };
  // The face whose chart triangle holds p strictly, or is nearest to
  // holding it (a cell on a ring edge that bends outwards pokes out of its
  // triangle).
  auto tri_of = [&](const Vec2& p) {
    for (std::size_t i = 0; i < T; ++i) {
      const auto& c = tri_chart[i];
      if (orient(c[0], c[1], p) > 0 && orient(c[1], c[2], p) > 0 && orient(c[2], c[0], p) > 0)
        return int(i);
    }
    return deepest(p, all_tris);
  };
  // The faces of s a point may lie in by the place on s it keeps through
  // the move: a ring vertex, a break point of a ring edge, a moved vertex,
  // a new break point of an inner edge: the faces around it (all where
  // nothing is kept, or past 64 faces).
  auto& node_tris = buffers.node_tris;
  node_tris.assign(pos.size(), 0);
  if (T <= 64) {
    const std::size_t m = chart.ring.size();
    const bool breaks_known = chart.loop_start.size() == m;
    auto has_ref = [&](std::size_t ti, int ref) {
      const auto& r = layout.tris[ti].ref;
      return r[0] == ref || r[1] == ref || r[2] == ref;
    };
    for (std::size_t ti = 0; ti < T; ++ti) {
      const std::uint64_t bit = std::uint64_t{1} << ti;
      for (const int ref : layout.tris[ti].ref) {
        node_tris[node_of(ref)] |= bit;
        // The break points of the ring edge from this ring position.
        if (ref < 0 || !breaks_known || !has_ref(ti, int((ref + 1) % m))) continue;
        const std::size_t end =
            ref + 1 < int(m) ? chart.loop_start[ref + 1] : chart.boundary_loop.size();
        for (std::size_t k = chart.loop_start[ref] + 1; k < end; ++k)
          node_tris[chart.boundary_loop[k]] |= bit;
      }
    }
    for (std::size_t i = 0; i < layout.spokes.size(); ++i) {
      std::uint64_t around = 0;
      for (std::size_t ti = 0; ti < T; ++ti)
        if (has_ref(ti, layout.spokes[i].a) && has_ref(ti, layout.spokes[i].b))
          around |= std::uint64_t{1} << ti;
      const auto& chain = spoke_chain[i];
      for (std::size_t j = 1; j + 1 < chain.size(); ++j) node_tris[chain[j].second] |= around;
    }
  }
  for (auto& bits : node_tris)
    if (!bits) bits = all_tris;
  // The face of s a cell lies in: among those its corners' kept places
  // allow, the one whose chart triangle holds the inside point (or is
  // nearest to it). (Where the ring's edges bend in the chart, a cell
  // reaches into a neighbouring face's chart triangle.)
  auto tri_of_cell = [&](std::span<const int> cell, const Vec2& p) {
    std::uint64_t allowed = all_tris;
    for (const int c : cell) allowed &= node_tris[c];
    if (!allowed) return tri_of(p);
    if (!(allowed & (allowed - 1))) return std::countr_zero(allowed);
    return deepest(p, allowed);
  };
  // The energy of one cell (its points counter-clockwise, a point inside
  // it, and t's face holding it with its corners there when known);
  // HUGE_VAL if it cannot be placed.
  auto &common = buffers.common, &faces = buffers.faces;
  MetaPiece& piece = buffers.piece;
  PlanarCells& cells = buffers.cells;
  // A node's corner on s in chart triangle ti, and on t in face h (laid
  // out as L, made when first needed): each a function of the node and the
  // face alone, so a node shared by cells is placed once per face (the same
  // values as placed anew).
  auto &s_corner_tri = buffers.s_corner_tri, &t_corner_face = buffers.t_corner_face;
  auto& s_corner = buffers.s_corner;
  auto& t_corner = buffers.t_corner;
  s_corner_tri.assign(pos.size(), -1);
  t_corner_face.assign(pos.size(), -1);
  s_corner.resize(pos.size());
  t_corner.resize(pos.size());
  auto corner_on_s = [&](int c, int ti) -> const Vec2& {
    if (s_corner_tri[c] == ti) return s_corner[c];
    s_corner_tri[c] = ti;
    const auto& tl = layout.tris[ti].shape;
    // Anchors on the ring's edges: exactly where their records put them.
    if (c < int(A) && chart.anchors[c].node.place[s].kind == Place::edge)
      if (const auto exact =
              place_in_face(meta_, s, layout.tris[ti].face, tl, chart.anchors[c].node.place[s]))
        return s_corner[c] = *exact;
    const auto& tc = tri_chart[ti];
    return s_corner[c] = from_barycentric(barycentric(pos[c], tc[0], tc[1], tc[2]), tl);
  };
  auto corner_on_t = [&](int c, int h,
                         std::optional<std::array<Vec2, 3>>& L) -> const std::optional<Vec2>& {
    if (t_corner_face[c] == h) return t_corner[c];
    t_corner_face[c] = h;
    if (!L) L = meta_face_layout(meta_.side[t].lengths[h]);
    return t_corner[c] = place_in_face(meta_, t, h, *L, place[c]);
  };
  auto cell_energy = [&](std::span<const int> cell, const Vec2& inside, int known_face,
                         const std::vector<Vec2>* known_corners) {
    const std::size_t n = cell.size();
    const int ti = tri_of_cell(cell, inside);
    if (ti < 0) return eval_fail(171);
    piece.corner[s].clear();
    for (int c : cell) piece.corner[s].push_back(corner_on_s(c, ti));
    piece.face[s] = layout.tris[ti].face;
    piece.area[s] = polygon_area(piece.corner[s]);
    if (!(piece.area[s] > 0)) return eval_fail(181);
    if (known_corners) {
      piece.face[t] = known_face;
      piece.corner[t] = *known_corners;
      piece.area[t] = polygon_area(piece.corner[t]);
    } else {
      // The face of t holding it.
      place_faces(meta_, index_, t, place[cell[0]], common);
      for (std::size_t i = 1; i < n && common.size() > 1; ++i) {
        place_faces(meta_, index_, t, place[cell[i]], faces);
        std::erase_if(
            common, [&](int h) { return std::find(faces.begin(), faces.end(), h) == faces.end(); });
      }
      int h_found = -1;
      for (int h : common) {
        std::vector<Vec2>& other = piece.corner[t];
        other.clear();
        std::optional<std::array<Vec2, 3>> Lh;
        for (int c : cell) {
          const auto& p = corner_on_t(c, h, Lh);
          if (!p) break;
          other.push_back(*p);
        }
        if (other.size() != n) continue;
        const double a = polygon_area(other);
        if (!(a > 0)) continue;
        h_found = h;
        piece.face[t] = h;
        piece.area[t] = a;
        break;
      }
      if (h_found < 0) return eval_fail(205);
    }
    const double e = piece_energy(piece, terms, terms.forward_weight(side1, piece.face[1]));
    return e < HUGE_VAL ? e : eval_fail(207);
  };
  auto cell_area = [&](std::span<const int> cell) { return polygon_area(pos, cell); };
  auto cells_area = [&](const PlanarCells& cells) {
    double covered = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) covered += cell_area(cells[i]);
    return covered;
  };
  auto cells_energy = [&](const PlanarCells& cells) {
    double total = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::span<const int> cell = cells[i];
      const auto inside = ear_point(pos, cell);
      if (!inside) return eval_fail(169);
      total += cell_energy(cell, *inside, -1, nullptr);
      if (!(total < HUGE_VAL)) return HUGE_VAL;
    }
    return total;
  };

  // Only the fragments of t's content that the inner edges run through are
  // cut into cells; the others are cells as they are. (The cells of the
  // whole ring, below, when that does not apply.) A developed chart's
  // proposal needs no cells: its energy is the triangles' sum, and the
  // transaction checks its pieces.
  double sum = HUGE_VAL;
  bool summed = false;
  if (affine) {
    sum = affine_sum();
    if (!(sum < HUGE_VAL)) return HUGE_VAL;
    summed = true;
  } else if (chart.kind == Chart::general && chart.large()) {
    const std::size_t F = chart.fragments.size();
    auto& cut = buffers.cut;
    cut.assign(F, 0);
    std::size_t n_cut = 0;
    auto mark = [&](int f) {
      if (f >= 0 && !cut[f]) cut[f] = 1, ++n_cut;
    };
    auto &node_chord = buffers.node_chord, &node_fragment = buffers.node_fragment;
    node_chord.assign(pos.size(), -1);
    node_fragment.assign(pos.size(), -1);
    for (const auto& hits : spoke_hits)
      for (const Hit& h : hits) node_chord[h.node] = h.chord;
    for (const auto& [node, f] : kink_fragment) node_fragment[node] = f;
    for (std::size_t k = 0; k < layout.inner.size(); ++k)
      if (layout.inner[k].on_anchor < 0) node_fragment[inner_node[k]] = inner_fragment[k];
    for (std::size_t c = 0; c < chart.chords.size(); ++c)
      if (!chord_used[c]) mark(chart.chord_fragments[c][0]), mark(chart.chord_fragments[c][1]);
    bool located = true;
    // Each piece of an inner edge: the fragment it runs through, or -2 - c
    // when it runs along chord c (between two fragments).
    auto& segment_fragment = buffers.segment_fragment;
    segment_fragment.assign(spoke_segments.size(), -1);
    for (std::size_t k = 0; k < spoke_segments.size() && located; ++k) {
      const auto [a, b] = spoke_segments[k];
      const auto it = chart.chord_of.find(undirected_edge_key(a, b));
      if (it != chart.chord_of.end() && !chord_used[it->second]) {
        segment_fragment[k] = -2 - it->second;
        continue;
      }
      const Vec2 mid = 0.5 * (pos[a] + pos[b]);
      int found = -1;
      for (int node : {a, b}) {
        if (node_fragment[node] >= 0 && found < 0 &&
            inside_cell(chart.fragments[node_fragment[node]], mid))
          found = node_fragment[node];
        if (node_chord[node] >= 0)
          for (int f : chart.chord_fragments[node_chord[node]])
            if (f >= 0 && found < 0 && inside_cell(chart.fragments[f], mid)) found = f;
      }
      for (std::size_t f = 0; f < F && found < 0; ++f)
        if (inside_cell(chart.fragments[f], mid)) found = int(f);
      if (found < 0) located = false;
      segment_fragment[k] = found;
      mark(found);
    }
    if (located && 2 * n_cut <= F) {  // (small charts: the whole ring)
      // The triangles of t inside the ring: their stretch summed per face
      // of s (one affine map of the chart to s each), a cut one shared by
      // the areas of its parts. The other cut fragments: their cells.
      // On side 0 the m sums are the forward term: weighed per face of
      // side 1 (t) as they are added.
      auto m_weight = [&](const Chart::Fragment& fragment) {
        return s == 0 ? terms.forward_weight(side1, fragment.face) : 1.0;
      };
      auto& per_tri = buffers.per_tri;
      per_tri.assign(tri_chart.size(), StretchMoments{});
      auto& part = buffers.part;
      part.assign(tri_chart.size(), 0.0);
      auto& split = buffers.split;
      split.clear();
      // The anisotropy penalty does not sum: each part's kept apart.
      const bool penalised = terms.anisotropy_weight > 0;
      auto& summed_parts = buffers.summed_parts;
      summed_parts.clear();
      sum = 0;
      for (std::size_t f = 0; f < F && sum < HUGE_VAL; ++f) {
        const auto& fragment = chart.fragments[f];
        if (fragment.summable && !cut[f]) {
          const int ti = tri_of_cell(fragment.nodes, fragment.inside);
          if (ti < 0) return eval_fail(171);
          per_tri[ti].add(fragment.moments, 1, m_weight(fragment));
          if (penalised) summed_parts.push_back({ti, int(f), 1.0});
        } else if (fragment.summable) {
          double covered = 0;
          for (std::size_t i = 0; i < tri_chart.size(); ++i)
            covered += part[i] =
                clipped_area(fragment.chart, fragment.lo, fragment.hi, tri_chart[i]);
          if (!(std::abs(covered - fragment.moments.area) <= 1e-9 * fragment.moments.area)) {
            split.push_back(int(f));
            continue;
          }
          for (std::size_t i = 0; i < tri_chart.size(); ++i)
            if (part[i] > 0) {
              const double share = part[i] / fragment.moments.area;
              per_tri[i].add(fragment.moments, share, m_weight(fragment));
              if (penalised) summed_parts.push_back({int(i), int(f), share});
            }
        } else if (!cut[f]) {
          sum += cell_energy(fragment.nodes, fragment.inside, fragment.face, &fragment.other);
        } else {
          split.push_back(int(f));
        }
      }
      if (!(sum < HUGE_VAL)) return HUGE_VAL;
      auto& to_s = buffers.to_s;  // the chart -> s, per face of s
      to_s.resize(per_tri.size());
      for (std::size_t i = 0; i < per_tri.size(); ++i) {
        if (!(per_tri[i].area > 0)) continue;
        to_s[i] = affine_linear_part(tri_chart[i], layout.tris[i].shape);
        const auto [x, y] = per_tri[i].evaluate(to_s[i]);
        if (!(x < HUGE_VAL)) return eval_fail(182);
        sum += s == 0
                   ? stretch_energy(x, y, terms)
                   : stretch_energy(y, x, terms, terms.forward_weight(side1, layout.tris[i].face));
      }
      for (const auto& [i, f, share] : summed_parts) {
        // The part's map s -> t: B A⁻¹ (A: the chart to s, B: to t).
        const auto& c = chart.fragments[f].chart;
        const auto& o = chart.fragments[f].other;
        const Eigen::Matrix2d to_t = affine_linear_part({c[0], c[1], c[2]}, {o[0], o[1], o[2]});
        const Eigen::Matrix2d J = to_t * to_s[i].inverse();
        const double chart_area = share * chart.fragments[f].moments.area;
        const double a1 = chart_area * (s == 1 ? to_s[i] : to_t).determinant();
        sum += terms.anisotropy(J.squaredNorm() / J.determinant(), a1);
      }
      // Each fragment to cut: its sides (split at the new crossings) and the
      // pieces of inner edges in it, cut into cells.
      summed = true;
      auto& segments = buffers.segments;
      for (const int f : split) {
        const auto& fragment = chart.fragments[f];
        segments.clear();
        for (std::size_t k = 0; k < spoke_segments.size(); ++k) {
          const int g = segment_fragment[k];
          if (g == f) segments.push_back(spoke_segments[k]);
          if (g <= -2) {
            const auto& sides = chart.chord_fragments[-2 - g];
            if (sides[0] == f || sides[1] == f) segments.push_back(spoke_segments[k]);
          }
        }
        const auto& nodes = fragment.nodes;
        for (std::size_t k = 0; k < nodes.size(); ++k)
          add_side(nodes[k], nodes[(k + 1) % nodes.size()], segments);
        const bool cut = planar_cells(pos, segments, cells);
        const double area = polygon_area(fragment.chart);
        if (!cut || !(std::abs(cells_area(cells) - area) <= 1e-9 * area)) {
          summed = false;  // the whole ring, below
          break;
        }
        sum += cells_energy(cells);
        if (!(sum < HUGE_VAL)) return HUGE_VAL;
      }
    }
  }
  if (!summed) {
    std::vector<std::array<int, 2>> segments = spoke_segments;
    const std::size_t nb = chart.boundary_loop.size();
    for (std::size_t i = 0; i < nb; ++i)
      segments.push_back({chart.boundary_loop[i], chart.boundary_loop[(i + 1) % nb]});
    for (std::size_t c = 0; c < chart.chords.size(); ++c)
      add_side(chart.chords[c].a, chart.chords[c].b, segments);
    if (!planar_cells(pos, segments, cells)) return eval_fail(134);
    const double covered = cells_area(cells), ring_area = cell_area(chart.boundary_loop);
    if (!(std::abs(covered - ring_area) <= 1e-9 * ring_area)) return eval_fail(300);  // not planar
    sum = cells_energy(cells);
    if (!(sum < HUGE_VAL)) return HUGE_VAL;
  }
  if (!out) return sum;

  // What to write.
  out->clear();
  for (std::size_t k = 0; k < layout.inner.size(); ++k) {
    if (layout.inner[k].on_anchor >= 0) continue;
    const Place& p = place[inner_node[k]];
    out->locations[0].push_back({layout.inner[k].vertex, MetaLocation{-1, p.index, p.bary}});
  }
  for (int a : chart.interior) {
    bool sat_on = false;
    for (const auto& in : layout.inner) sat_on |= in.on_anchor == a;
    if (sat_on) continue;
    const int ti = tri_of(pos[a]);
    if (ti < 0) return eval_fail(223);
    const auto& tc = tri_chart[ti];
    if (barycentric(pos[a], tc[0], tc[1], tc[2]).minCoeff() < layout.clearance)
      return eval_fail(224);
    out->locations[1].push_back(
        {chart.anchors[a].node.place[t].index,
         MetaLocation{-1, layout.tris[ti].face,
                      clamp_bary(barycentric(pos[a], tc[0], tc[1], tc[2]))}});
  }
  for (std::size_t i = 0; i < layout.spokes.size(); ++i) {
    std::vector<MetaCrossing> list;
    for (const Hit& h : spoke_hits[i])
      list.push_back({chart.chords[h.chord].edge, s_place[h.node].t, place[h.node].t});
    for (const auto& [u, node] : spoke_chain[i])
      if (node < int(is_kink.size()) && is_kink[node])
        list.push_back({-1, s_place[node].t, 0, place[node].index, place[node].bary});
    std::sort(list.begin(), list.end(),
              [](const auto& a, const auto& b) { return a.here < b.here; });
    out->lists.push_back({layout.spokes[i].edge, std::move(list)});
  }
  // Each chord's break points replaced by its new crossings.
  std::vector<int> order(chart.chords.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = int(c);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto &x = chart.chords[a], &y = chart.chords[b];
    return x.edge != y.edge ? x.edge < y.edge
                            : std::min(x.first, x.last) > std::min(y.first, y.last);
  });
  for (std::size_t k = 0; k < order.size();) {
    const int g = chart.chords[order[k]].edge;
    std::vector<MetaCrossing> list = meta_.side[t].crossings[g];
    for (; k < order.size() && chart.chords[order[k]].edge == g; ++k) {
      const int c = order[k];
      const auto& chord = chart.chords[c];
      const int lo = std::min(chord.first, chord.last), hi = std::max(chord.first, chord.last);
      std::vector<MetaCrossing> fresh;
      for (const auto& [lambda, node] : chord_hits[c]) {
        // Which spoke: the one whose hits hold this node.
        for (std::size_t i = 0; i < layout.spokes.size(); ++i)
          for (const Hit& h : spoke_hits[i])
            if (h.node == node)
              fresh.push_back({layout.spokes[i].edge, place[node].t, s_place[node].t});
      }
      list.erase(list.begin() + lo, list.begin() + hi);
      list.insert(list.begin() + lo, fresh.begin(), fresh.end());
    }
    std::sort(list.begin(), list.end(),
              [](const auto& a, const auto& b) { return a.here < b.here; });
    out->other_lists.push_back({g, std::move(list)});
  }
  return sum;
}

// ---------------------------------------------------------------- splits in place

bool InterSurfaceMap::shifted_copy(int s, int vt, int vs, int old_edge, int new_edge, double side,
                                   double eps, std::map<int, std::vector<MetaCrossing>>& other,
                                   std::vector<MetaCrossing>& copy) const {
  const int t = 1 - s;
  const MetaSide& S = meta_.side[s];
  const MetaSide& T = meta_.side[t];
  const Place pt = vertex_node(meta_, s, vt).place[t];
  std::vector<int> faces_a, faces_b;
  auto common_face = [&](const Place& a, const Place& b) {
    place_faces(meta_, index_, t, a, faces_a);
    place_faces(meta_, index_, t, b, faces_b);
    for (int f : faces_a)
      if (std::find(faces_b.begin(), faces_b.end(), f) != faces_b.end()) {
        if (a.kind == Place::vertex && b.kind == Place::vertex) continue;  // along an edge of t
        return f;
      }
    return -1;
  };
  copy.clear();
  const auto& list = S.crossings[old_edge];
  const bool forward = S.edges[old_edge][0] == vt;
  const bool new_forward = S.edges[new_edge][0] == vs;
  Place previous = pt;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::size_t n = forward ? i : list.size() - 1 - i;
    const MetaCrossing& c = list[n];
    const double u = forward ? c.here : 1 - c.here;  // along vt -> w
    const auto node = break_node(meta_, s, old_edge, int(n));
    if (!node) return false;
    const Place here = node->place[t];
    const int f = common_face(previous, here);
    if (f < 0) return false;
    const Vec2 p0 = *place_in_face(meta_, t, f, previous), p1 = *place_in_face(meta_, t, f, here);
    const Vec2 dir = p1 - p0;
    if (c.is_kink()) {
      const std::array<Vec2, 3> Lk = meta_face_layout(T.lengths[c.face]);
      const Vec2 at = from_barycentric(c.bary, Lk);
      const Vec2 shifted = at + side * eps * Vec2(-dir.y(), dir.x());
      const Eigen::Vector3d b = barycentric(shifted, Lk[0], Lk[1], Lk[2]);
      if (!(b.minCoeff() > 0)) return false;
      copy.push_back({-1, new_forward ? u : 1 - u, 0, c.face, b / b.sum()});
    } else {
      // Along the crossed edge g towards vs's side, by eps of the way
      // to the nearest other break point on g in that direction.
      const int g = c.edge;
      const Vec2 ga =
          *place_in_face(meta_, t, f, {Place::vertex, T.edges[g][0], 0, Eigen::Vector3d::Zero()});
      const Vec2 gb =
          *place_in_face(meta_, t, f, {Place::vertex, T.edges[g][1], 0, Eigen::Vector3d::Zero()});
      const double cross = dir.x() * (gb - ga).y() - dir.y() * (gb - ga).x();
      const double sign = (cross > 0) == (side > 0) ? 1.0 : -1.0;
      const auto& glist = other.count(g) ? other[g] : T.crossings[g];
      double room = sign > 0 ? 1 - c.there : c.there;
      for (const auto& o : glist)
        if ((o.here - c.there) * sign > 0) room = std::min(room, std::abs(o.here - c.there));
      const double there = c.there + sign * eps * room;
      copy.push_back({g, new_forward ? u : 1 - u, there});
      auto& target_list = other.try_emplace(g, T.crossings[g]).first->second;
      target_list.push_back({new_edge, there, new_forward ? u : 1 - u});
    }
    previous = here;
  }
  std::sort(copy.begin(), copy.end(), [](const auto& a, const auto& b) { return a.here < b.here; });
  return true;
}

bool InterSurfaceMap::split_in_place(const Chart& chart, std::size_t last, int vs, int e_vl,
                                     int e_vr, double eps, Proposal& out) const {
  // After the connectivity change: the edges (vs, ring[i]), 0 < i < last,
  // are vt's old edges renamed, with their records. vs goes a fraction eps
  // along the first segment of one of them (or into the wedge of face 0
  // when there is none); the new edges (vs, vl) and (vs, vr) follow (vt,
  // vl) and (vt, vr) shifted by eps to vs's side. For eps small enough this
  // is the old map with two slivers added, hence valid.
  const int s = chart.s, t = chart.t, vt = chart.v;
  const MetaSide& S = meta_.side[s];
  const MetaSide& T = meta_.side[t];
  out.clear();
  // Where a vertex of s sits on t, and an edge's first break from a vertex.
  auto vertex_place = [&](int v) { return vertex_node(meta_, s, v).place[t]; };
  auto first_place = [&](int e, int from) -> std::optional<Place> {
    const auto& list = S.crossings[e];
    const int to = S.edges[e][0] == from ? S.edges[e][1] : S.edges[e][0];
    if (list.empty()) return vertex_place(to);
    const auto node = break_node(meta_, s, e, S.edges[e][0] == from ? 0 : int(list.size()) - 1);
    if (!node) return std::nullopt;
    return node->place[t];
  };
  // A face of t holding vt and a place.
  const Place pt = vertex_place(vt);
  std::vector<int> faces_a, faces_b;
  auto common_face = [&](const Place& a, const Place& b) {
    place_faces(meta_, index_, t, a, faces_a);
    place_faces(meta_, index_, t, b, faces_b);
    for (int f : faces_a)
      if (std::find(faces_b.begin(), faces_b.end(), f) != faces_b.end()) {
        if (a.kind == Place::vertex && b.kind == Place::vertex) continue;  // along an edge of t
        return f;
      }
    return -1;
  };
  int face = -1;
  Vec2 target;
  if (pt.kind == Place::face) {
    // vt inside a face of t: every spoke's first segment lies in it. The
    // slivers (vs, vt, vl) and (vt, vs, vr) are positive when vs leaves vt
    // less than a half-turn counter-clockwise of (vt, vl) and less than a
    // half-turn clockwise of (vt, vr): half-way round the wedge from one to
    // the other is both, whatever its angle.
    const auto f0 = first_place(chart.spoke[0], vt), f1 = first_place(chart.spoke[last], vt);
    const int f = pt.index;
    const auto a = place_in_face(meta_, t, f, pt);
    const auto b = f0 ? place_in_face(meta_, t, f, *f0) : std::nullopt;
    const auto c = f1 ? place_in_face(meta_, t, f, *f1) : std::nullopt;
    if (a && b && c && (*b - *a).norm() > 0 && (*c - *a).norm() > 0) {
      double reach = std::min((*b - *a).norm(), (*c - *a).norm());
      for (std::size_t j = 1; j < last; ++j)
        if (const auto first = first_place(chart.spoke[j], vs))
          if (const auto p = place_in_face(meta_, t, f, *first))
            reach = std::min(reach, (*p - *a).norm());
      const Vec2 u = *b - *a, w = *c - *a;
      double angle = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));
      if (angle <= 0) angle += 2 * M_PI;
      const Vec2 d = Eigen::Rotation2Dd(0.5 * angle) * u.normalized();
      if (reach > 0) face = f, target = *a + eps * reach * d;
    }
  }
  for (std::size_t j = 1; j < last && face < 0; ++j) {
    const auto first = first_place(chart.spoke[j], vs);
    if (!first) continue;
    const int f = common_face(pt, *first);
    if (f < 0) continue;
    const Vec2 a = *place_in_face(meta_, t, f, pt), b = *place_in_face(meta_, t, f, *first);
    face = f, target = a + eps * (b - a);
  }
  if (face < 0) {
    const auto f0 = first_place(chart.spoke[0], vt), f1 = first_place(chart.spoke[last], vt);
    if (!f0 || !f1) return false;
    const int f = common_face(pt, *f0);
    if (f < 0) return false;
    const Vec2 a = *place_in_face(meta_, t, f, pt), b = *place_in_face(meta_, t, f, *f0);
    const auto c = place_in_face(meta_, t, f, *f1);
    Vec2 d = (b - a).normalized();
    if (c && orient(a, b, *c) > 0)
      d = 0.5 * (d + (*c - a).normalized());
    else
      d = Eigen::Rotation2Dd(1e-3) * d;  // just inside the wedge, counter-clockwise of (vt, vl)
    face = f, target = a + eps * (b - a).norm() * d;
  }
  const std::array<Vec2, 3> L = meta_face_layout(T.lengths[face]);
  const Eigen::Vector3d bary = barycentric(target, L[0], L[1], L[2]);
  if (!(bary.minCoeff() > 0)) return false;
  out.locations[0].push_back({vs, MetaLocation{-1, face, bary / bary.sum()}});

  // (vs, vl) and (vs, vr): copies of vt's edges, shifted to vs's side
  // (left of vt -> vl, right of vt -> vr).
  std::map<int, std::vector<MetaCrossing>> other;
  for (int k = 0; k < 2; ++k) {
    const int new_edge = k == 0 ? e_vl : e_vr;
    std::vector<MetaCrossing> copy;
    if (!shifted_copy(s, vt, vs, chart.spoke[k == 0 ? 0 : last], new_edge, k == 0 ? 1.0 : -1.0, eps,
                      other, copy))
      return false;
    out.lists.push_back({new_edge, std::move(copy)});
  }
  for (auto& [g, list] : other) {
    std::sort(list.begin(), list.end(),
              [](const auto& a, const auto& b) { return a.here < b.here; });
    out.other_lists.push_back({g, std::move(list)});
  }
  return true;
}

// ---------------------------------------------------------------- operations

void InterSurfaceMap::ring_layout(const Chart& chart, Layout& layout) const {
  const std::size_t m = chart.faces.size();
  layout.inner.clear(), layout.tris.clear(), layout.spokes.clear();
  layout.clearance = Layout{}.clearance;
  if (chart.half_disc) {
    // v on its anchor of the chart's straight side; its boundary edges run
    // along that side (no inner edges).
    layout.inner.push_back({chart.v, chart.anchors[chart.slider].pos, chart.slider});
    for (std::size_t i = 0; i < m; ++i) {
      std::array<int, 3> ref;
      const int c = chart.corner[i];
      ref[c] = -1, ref[(c + 1) % 3] = int(i), ref[(c + 2) % 3] = int(i + 1);
      layout.tris.push_back(
          {chart.faces[i], ref, meta_face_layout(meta_.side[chart.s].lengths[chart.faces[i]])});
      if (i > 0) layout.spokes.push_back({-1, int(i), chart.spoke[i]});
    }
    return;
  }
  layout.inner.push_back({chart.v, chart.centre, -1});
  for (std::size_t i = 0; i < m; ++i) {
    std::array<int, 3> ref;
    const int c = chart.corner[i];
    ref[c] = -1, ref[(c + 1) % 3] = int(i), ref[(c + 2) % 3] = int((i + 1) % m);
    layout.tris.push_back(
        {chart.faces[i], ref, meta_face_layout(meta_.side[chart.s].lengths[chart.faces[i]])});
    layout.spokes.push_back({-1, int(i), chart.spoke[i]});
  }
}

bool InterSurfaceMap::affine_ring(const Chart& chart) const {
  // A developed chart is an isometric development of t with none of its
  // vertices inside the ring: each ring triangle is one affine map, as in
  // a fast chart (one face of t).
  return chart.kind == Chart::fast ||
         (chart.kind == Chart::developed && (chart.s == 1 || options_.forward_density.empty()));
}

bool InterSurfaceMap::smooth_ring(const Chart& chart, const Layout& layout,
                                  std::vector<CornerStretch>& corners) const {
  // As evaluate's sum without cutting, with one inner vertex off the anchors.
  if (!affine_ring(chart) || layout.inner.size() != 1 || layout.inner[0].on_anchor >= 0)
    return false;
  const EnergyTerms terms = energy_terms();
  const MetaSide& side1 = meta_.side[1];
  corners.clear();
  for (const auto& tri : layout.tris) {
    std::array<Vec2, 3> q;
    int k = -1;
    for (int c = 0; c < 3; ++c) {
      if (tri.ref[c] == -1) k = c;
      q[c] =
          tri.ref[c] >= 0 ? chart.anchors[chart.ring_anchor[tri.ref[c]]].pos : layout.inner[0].pos;
    }
    if (k < 0) return false;
    const auto c = chart.s == 0 ? corner_stretch(tri.shape, q, 1, k, terms,
                                                 terms.forward_weight(side1, chart.single_face))
                                : corner_stretch(q, tri.shape, 0, k, terms,
                                                 terms.forward_weight(side1, tri.face));
    if (!c) return false;
    corners.push_back(*c);
  }
  return true;
}

InterSurfaceMap::Move InterSurfaceMap::search_move(const Chart& chart, Layout& layout,
                                                   double give_up_above) const {
  Move move;
  Vec2& p = move.p;
  const std::size_t m = chart.faces.size();
  auto energy = [&](const Vec2& x) {
    layout.inner[0].pos = x;
    layout.inner[0].on_anchor =
        chart.centre_anchor >= 0 && x == chart.centre ? chart.centre_anchor : -1;
    ++move.evaluations;
    return evaluate(chart, layout, nullptr);
  };
  // (give_up_above: a large chart's first round of line searches mostly
  // ends above the ring's energy (re-laying the other side's content in a cone's chart, which
  // is not isometric, costs more than moving gains), and a second round
  // then almost never gets below it: results-two-surfaces.md, stop 40.)
  p = chart.centre;
  const std::vector<Vec2> kernel = boundary_polygon(chart, 0, m);
  thread_local std::vector<CornerStretch> corners;
  move.smooth = smooth_ring(chart, layout, corners);
  if (move.smooth) {
    // The ring's energy is a sum of triangles whose other side is fixed:
    // Newton steps on its exact derivatives; the energy as evaluate
    // defines it comes with the proposal below.
    newton_in_kernel(kernel, p, [&](const Vec2& x, Vec2* gradient, Eigen::Matrix2d* hessian) {
      return corners_energy(corners, x, gradient, hessian);
    });
  } else {
    move.energy =
        minimize_in_kernel(kernel, p, energy, LineSearch::parabolic, give_up_above, search_);
  }
  return move;
}

bool InterSurfaceMap::Move::gains(const Chart& chart, double before) const {
  // (Newton steps stop where the ring's exact energy stops dropping.)
  if (!smooth && !(energy < before * (1 - 1e-12))) return false;
  return p != chart.centre;
}

double InterSurfaceMap::propose_move(const Chart& chart, Layout& layout, const Vec2& p,
                                     Proposal& proposal) const {
  layout.inner[0].pos = p;
  layout.inner[0].on_anchor = -1;
  return evaluate(chart, layout, &proposal);
}

double InterSurfaceMap::finish_move(int s, const std::vector<int>& faces, double before,
                                    const Proposal& proposal, double predicted, bool smooth) {
  if (!(predicted < (smooth ? before * (1 - 1e-12) : HUGE_VAL))) return 0.0;
  const auto gain = apply(s, faces, proposal, before, true);
  if (!gain) {
    ++stats_.rejected;
    return 0.0;
  }
  ++stats_.moves;
  const double after = before - *gain, off = std::abs(predicted - after) / after;
  stats_.mispredicted += off > 0.01;
  stats_.worst_prediction = std::max(stats_.worst_prediction, off);
  return *gain;
}

double InterSurfaceMap::slide_vertex(int s, int v) {
  const int t = 1 - s;
  Chart chart;
  if (!build_half_disc(s, v, chart)) return 0.0;
  const MetaSide& S = meta_.side[s];
  const MetaSide& T = meta_.side[t];
  const int g = S.location[v].edge;
  // The slider's neighbours on the chart's straight side, and where they
  // are along g (its ends, or other points of it).
  const auto& loop = chart.boundary_loop;
  const std::size_t k =
      std::size_t(std::find(loop.begin(), loop.end(), chart.slider) - loop.begin());
  auto along = [&](int anchor) {
    const Place& q = chart.anchors[anchor].node.place[t];
    if (q.kind == Place::edge && q.index == g) return q.t;
    if (q.kind == Place::vertex && q.index == T.edges[g][0]) return 0.0;
    if (q.kind == Place::vertex && q.index == T.edges[g][1]) return 1.0;
    return std::nan("");
  };
  const double lo = along(loop[k - 1]), hi = along(loop[(k + 1) % loop.size()]);
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo != hi)) return 0.0;
  const std::vector<int> faces = chart.faces;
  const double before = faces_energy(s, faces);
  if (!(before < HUGE_VAL)) return 0.0;
  ++stats_.optimizations;
  ++stats_.general;
  Layout layout;
  Chart at;
  auto energy = [&](double lambda, Proposal* out) {
    const Place place{Place::edge, g, lo + lambda * (hi - lo), Eigen::Vector3d::Zero()};
    if (!build_half_disc(s, v, at, &place)) return HUGE_VAL;
    ring_layout(at, layout);
    const Vec2 p = layout.inner[0].pos;
    for (std::size_t i = 0; i + 1 < at.w.size(); ++i)
      if (!(orient(p, at.w[i], at.w[i + 1]) > 0)) return HUGE_VAL;
    ++stats_.evaluations;
    return evaluate(at, layout, out);
  };
  // A golden-section search along g between the neighbours (kept 1e-3 of
  // the gap from them), from where v is.
  const double margin = 1e-3, phi = 0.5 * (std::sqrt(5.0) - 1);
  double a = margin, b = 1 - margin;
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
  double e1 = energy(x1, nullptr), e2 = energy(x2, nullptr);
  for (int round = 0; round < 24; ++round) {
    if (e1 <= e2) {
      b = x2, x2 = x1, e2 = e1;
      x1 = b - phi * (b - a);
      e1 = energy(x1, nullptr);
    } else {
      a = x1, x1 = x2, e1 = e2;
      x2 = a + phi * (b - a);
      e2 = energy(x2, nullptr);
    }
  }
  const double best = e1 <= e2 ? x1 : x2;
  if (!(std::min(e1, e2) < before * (1 - 1e-12))) return 0.0;
  thread_local Proposal proposal;
  const double predicted = energy(best, &proposal);
  if (!(predicted < before * (1 - 1e-12))) return 0.0;
  // v's new place on g, and the new parameters of t's vertices on v's
  // boundary edges (fixed in the chart, measured from v's new position).
  MetaLocation here;
  const auto& gf = index_[t].edge_faces[g];
  set_edge_location(here, T, gf[0] >= 0 ? gf[0] : gf[1], g, lo + best * (hi - lo));
  proposal.locations[0].push_back({v, here});
  const Vec2 p = at.anchors[at.slider].pos;
  const std::size_t m = at.faces.size();
  for (const auto& [e, face, end] : {std::tuple{at.spoke[0], at.faces[0], at.w[0]},
                                     std::tuple{at.spoke[m], at.faces[m - 1], at.w[m]}})
    for (int x : index_[s].on_edge[e]) {
      const auto it = std::find_if(at.anchors.begin(), at.anchors.end(), [&](const auto& a) {
        return a.node.place[t].kind == Place::vertex && a.node.place[t].index == x &&
               a.node.place[s].kind == Place::edge;
      });
      if (it == at.anchors.end()) return 0.0;
      const double u = (it->pos - p).norm() / (end - p).norm();
      MetaLocation there;
      set_edge_location(there, S, face, e, S.edges[e][0] == v ? u : 1 - u);
      proposal.locations[1].push_back({x, there});
    }
  return finish_move(s, faces, before, proposal, predicted, false);
}

double InterSurfaceMap::optimize_vertex(int s, int v) {
  VertexPlan unplanned;
  unplanned.side = s, unplanned.vertex = v;
  return commit_plan(unplanned);
}

InterSurfaceMap::VertexPlan::VertexPlan() = default;
InterSurfaceMap::VertexPlan::~VertexPlan() = default;
InterSurfaceMap::VertexPlan::VertexPlan(VertexPlan&&) noexcept = default;
InterSurfaceMap::VertexPlan& InterSurfaceMap::VertexPlan::operator=(VertexPlan&&) noexcept =
    default;

void InterSurfaceMap::plan_vertex(int s, int v, VertexPlan& plan) const {
  plan.side = s, plan.vertex = v;
  if (!plan.state) plan.state = std::make_unique<VertexPlan::State>();
  VertexPlan::State& st = *plan.state;
  st.planned = true;
  st.charted = false;
  st.proposed = false;
  st.before = HUGE_VAL;
  st.clock = edit_clock_;
  if (pinned_[s][v] || !is_active(s, v)) return;
  if (!build_chart(s, v, st.chart)) return;
  st.charted = true;
  thread_local Layout layout;
  ring_layout(st.chart, layout);
  // The ring's energy (its sums kept for the commit: the cache of
  // committed faces, which only the commit fills), and where the move
  // gains its proposal, both as the commit would make them if no edit
  // touches the ring before.
  st.before = faces_energy_read(s, st.chart.faces, &st.sums);
  if (!(st.before < HUGE_VAL)) return;
  st.move = search_move(st.chart, layout, st.chart.large() ? st.before : HUGE_VAL);
  if (!st.move.gains(st.chart, st.before)) return;
  st.predicted = propose_move(st.chart, layout, st.move.p, st.proposal);
  st.proposed = true;
}

double InterSurfaceMap::commit_plan(VertexPlan& plan) {
  const int s = plan.side, v = plan.vertex;
  last_chart_ = ChartKind::none;
  if (pinned_[s][v] || !is_active(s, v)) return 0.0;
  // A boundary vertex of an open map on a boundary edge of the other side
  // slides along it.
  if (index_[s].open && meta_.side[s].location[v].on_edge()) return slide_vertex(s, v);
  // Per-thread scratch: the chart and layout keep their lists' storage
  // from vertex to vertex (nothing here optimises a vertex re-entrantly).
  thread_local Chart chart;
  thread_local Layout layout;
  thread_local Proposal proposal;  // (its lists' storage kept; evaluate clears it)
  VertexPlan::State* st = plan.state.get();
  // A plan whose ring faces no edit has touched since holds its chart as
  // it would be built now (face_edit_), and the ring's sums and the
  // move's proposal too.
  const bool unchanged =
      st && st->planned && st->charted && untouched_since(s, st->chart.faces, st->clock);
  // The sums the plan cut hold for the ring's faces no edit touched since
  // (keep_sums stamps them with the plan's clock: the others stay stale).
  if (st && st->planned && st->charted && st->before < HUGE_VAL)
    keep_sums(s, st->chart.faces, st->sums, st->clock);
  if (unchanged) {
    if (check_plans_) {
      if (!build_chart(s, v, chart) || !(chart == st->chart))
        throw std::logic_error("commit_plan: vertex " + std::to_string(v) + " of side " +
                               std::to_string(s) +
                               ": its chart changed while no edit touched its ring");
    }
    std::swap(chart, st->chart);
    ++stats_.plans_untouched;
  } else if (!build_chart(s, v, chart)) {
    return 0.0;
  }
  last_chart_ = chart.large()                    ? ChartKind::large
                : chart.kind == Chart::fast      ? ChartKind::fast
                : chart.kind == Chart::developed ? ChartKind::developed
                                                 : ChartKind::general;
  ++stats_.optimizations;
  ++(chart.kind == Chart::fast        ? stats_.fast_path
     : chart.kind == Chart::developed ? stats_.developed
                                      : stats_.general);
  ring_layout(chart, layout);
  const double before = faces_energy(s, chart.faces);
  if (!(before < HUGE_VAL)) return 0.0;
  const bool held = st && st->planned && st->charted && (unchanged || st->chart == chart) &&
                    (!chart.large() || st->before == before);
  // (Only where untouched: a proposal also carries whole lists of the other
  // side's edges that cross the ring, which an equal chart does not show.)
  const bool proposed = held && unchanged && st->proposed;
  if (st) {
    st->planned = false;                         // (used once)
    if (st->chart.large()) st->chart = Chart{};  // (a large chart's storage let go)
  }
  Move move;
  if (held) {
    ++stats_.plans_held;
    move = st->move;
  } else {
    stats_.plans_stale += st != nullptr;
    move = search_move(chart, layout, chart.large() ? before : HUGE_VAL);
  }
  stats_.evaluations += move.evaluations;
  if (!move.gains(chart, before)) return 0.0;
  if (proposed) {
    if (check_plans_ && !(propose_move(chart, layout, move.p, proposal) == st->predicted))
      throw std::logic_error("commit_plan: vertex " + std::to_string(v) + " of side " +
                             std::to_string(s) + ": its planned proposal is not the one made now");
    return finish_move(s, chart.faces, before, st->proposal, st->predicted, move.smooth);
  }
  const double predicted = propose_move(chart, layout, move.p, proposal);
  return finish_move(s, chart.faces, before, proposal, predicted, move.smooth);
}

int InterSurfaceMap::add_edge(int s, int u, int v) {
  MetaSide& side = meta_.side[s];
  const int e = int(side.edges.size());
  side.edges.push_back({std::min(u, v), std::max(u, v)});
  side.crossings.emplace_back();
  index_[s].edge_of[undirected_edge_key(u, v)] = e;
  index_[s].edge_faces.push_back({-1, -1});
  if (index_[s].open) index_[s].on_edge.emplace_back();
  index_[s].vertex_edges[u].push_back(e);
  index_[s].vertex_edges[v].push_back(e);
  return e;
}

int InterSurfaceMap::try_boundary_split(int s, bool place, double cap) {
  const VertexSplit& sp = input_[s].splits[next_split_[s]];
  const std::string where = std::string(s == 0 ? "M¹" : "M²") + " split " +
                            std::to_string(next_split_[s]) + " (vertex " + std::to_string(sp.vs) +
                            " from " + std::to_string(sp.vt) + ")";
  const int t = 1 - s, vt = sp.vt, vs = sp.vs;
  // ccw: the fan from (vt, vl, *) to the boundary moves to vs, new face
  // (vs, vt, vl); else the fan from the boundary to (vt, *, vr), new face
  // (vt, vs, vr).
  const bool ccw = sp.vr < 0;
  const int wing = ccw ? sp.vl : sp.vr;
  Chart chart;
  if (!build_chart_from(s, vt, -1, chart, true, true))
    throw std::runtime_error(where +
                             ": a boundary split of a vertex that is not on the boundary of the "
                             "other surface");
  const std::size_t m = chart.faces.size();
  std::size_t j = m + 1;
  for (std::size_t i = 0; i <= m; ++i)
    if (chart.ring[i] == wing) j = i;
  if (j > m)
    throw std::runtime_error(where + ": the wing is not a neighbour of the vertex to split");
  if (ccw ? j == m : j == 0)
    throw std::runtime_error(where +
                             ": a boundary split adding a face outside the boundary, which open "
                             "maps do not refine yet");
  const std::size_t f_lo = ccw ? j : 0, f_hi = ccw ? m : j;          // moved faces
  const std::size_t e_lo = ccw ? j + 1 : 0, e_hi = ccw ? m + 1 : j;  // renamed spokes
  const int moved_boundary = ccw ? chart.spoke[m] : chart.spoke[0];  // becomes vs's
  const int far = ccw ? chart.ring[m] : chart.ring[0];

  const double before = place ? faces_energy(s, chart.faces) : HUGE_VAL;
  const double limit = before < HUGE_VAL && cap < HUGE_VAL ? cap * before : HUGE_VAL;
  touch_under(s, chart.faces);
  MetaSide& S = meta_.side[s];
  MetaSideIndex& IS = index_[s];
  const SplitUndo undo = split_undo(s, chart, sp);
  // The other side's vertices on the boundary edge vs takes keep their
  // places; their parameters follow its ends' order.
  std::vector<double> lodger_t;  // (their parameters before, for the undo: 1 - (1 - t) is not t)
  auto flip_lodgers = [&](int e) {
    auto& list = IS.on_edge[e];
    for (int x : list) {
      lodger_t.push_back(meta_.side[t].location[x].t);
      meta_.side[t].location[x].t = 1 - lodger_t.back();
    }
    std::reverse(list.begin(), list.end());
  };
  bool lodgers_flipped = false;
  for (std::size_t i = e_lo; i < e_hi; ++i) {
    // Edge (vt, w) becomes (vs, w): same records, renamed.
    const int e = chart.spoke[i], w = chart.ring[i];
    IS.edge_of.erase(undirected_edge_key(vt, w));
    const bool flip = (vt < w) != (vs < w);
    S.edges[e] = {std::min(vs, w), std::max(vs, w)};
    IS.edge_faces[e] = {-1, -1};  // (set again below from its faces: one, on the boundary)
    IS.edge_of[undirected_edge_key(vs, w)] = e;
    std::erase(IS.vertex_edges[vt], e);
    IS.vertex_edges[vs].push_back(e);
    if (!flip) continue;
    auto& list = S.crossings[e];
    std::reverse(list.begin(), list.end());
    std::vector<int> others;
    for (auto& c : list) {
      c.here = 1 - c.here;
      if (!c.is_kink()) others.push_back(c.edge);
    }
    std::sort(others.begin(), others.end());
    others.erase(std::unique(others.begin(), others.end()), others.end());
    for (int g : others)
      for (auto& o : meta_.side[t].crossings[g])
        if (o.edge == e) o.there = 1 - o.there;
    if (e == moved_boundary) flip_lodgers(e), lodgers_flipped = true;
  }
  for (std::size_t i = f_lo; i < f_hi; ++i) {
    const int f = chart.faces[i];
    area_[s] -= face_area(s, f);
    S.faces[f][chart.corner[i]] = vs;
    if (!S.positions.empty()) S.lengths[f] = face_lengths(s, S.faces[f]);
    area_[s] += face_area(s, f);
    std::erase(IS.vertex_faces[vt], f);
    IS.vertex_faces[vs].push_back(f);
  }
  const int e_w = add_edge(s, vs, wing);
  add_edge(s, vs, vt);  // (on the boundary)
  const int fa = int(S.faces.size());
  const Triangle tri = ccw ? Triangle{vs, vt, wing} : Triangle{vt, vs, wing};
  S.faces.push_back(tri);
  S.lengths.push_back(S.positions.empty() ? FaceLengths{1, 1, 1} : face_lengths(s, tri));
  S.face_edges.push_back({});
  IS.residents.emplace_back();
  for (int x : tri) IS.vertex_faces[x].push_back(fa);
  area_[s] += face_area(s, fa);
  std::vector<int> changed(chart.faces.begin(), chart.faces.end());
  changed.push_back(fa);
  for (int f : changed)
    for (int k = 0; k < 3; ++k) {
      const int u = S.faces[f][k], w = S.faces[f][(k + 1) % 3];
      const int e = IS.edge(u, w);
      S.face_edges[f][k] = e;
      IS.edge_faces[e][u == S.edges[e][0] ? 0 : 1] = f;
    }
  ++active_[s];
  ++next_split_[s];
  ++stats_.splits;
  pinned_[s][vs] = 0;
  auto undo_all = [&] {
    if (lodgers_flipped) {
      auto& list = IS.on_edge[moved_boundary];
      std::reverse(list.begin(), list.end());
      for (std::size_t k = 0; k < list.size(); ++k) meta_.side[t].location[list[k]].t = lodger_t[k];
    }
    restore(s, undo);
  };
  if (!place) {
    undo_all();
    return -1;
  }

  // In place: vs on t's boundary edge g that vt lies on, a fraction eps of
  // the way to the next boundary point along the edge vs took (the other
  // side's first vertex on it, or its far end); its edge to the wing a copy
  // of vt's shifted to vs's side. The slides then place both.
  const MetaSide& T = meta_.side[t];
  Place next = vertex_node(meta_, s, far).place[t];
  double nearest = 1;
  for (int x : IS.on_edge[moved_boundary]) {
    const double u = S.edges[moved_boundary][0] == vs ? T.location[x].t : 1 - T.location[x].t;
    if (u < nearest) nearest = u, next = vertex_node(meta_, t, x).place[t];
  }
  // The boundary edge g of t from vt's place towards that point: the one
  // vt lies on, or where vt sits on a boundary vertex x of t, x's boundary
  // edge that leads there.
  int g = S.location[vt].edge;
  double tau = S.location[vt].t;
  if (const int x = S.location[vt].vertex; x >= 0) {
    g = next.kind == Place::edge     ? next.index
        : next.kind == Place::vertex ? index_[t].edge(x, next.index)
                                     : -1;
    if (g < 0 || !index_[t].is_boundary(g) || (T.edges[g][0] != x && T.edges[g][1] != x))
      throw std::runtime_error(where +
                               ": the boundary next to the vertex to split does not run along one "
                               "edge of the other surface");
    tau = T.edges[g][0] == x ? 0.0 : 1.0;
  }
  const double tau_next = next.kind == Place::edge && next.index == g                 ? next.t
                          : next.kind == Place::vertex && next.index == T.edges[g][0] ? 0.0
                          : next.kind == Place::vertex && next.index == T.edges[g][1] ? 1.0
                                                                                      : tau;
  const auto& gf = index_[t].edge_faces[g];
  for (double eps = 0.25; tau_next != tau && eps > 1e-12; eps *= 0.0625) {
    Proposal proposal;
    MetaLocation loc;
    set_edge_location(loc, T, gf[0] >= 0 ? gf[0] : gf[1], g, tau + eps * (tau_next - tau));
    proposal.locations[0].push_back({vs, loc});
    std::map<int, std::vector<MetaCrossing>> other;
    std::vector<MetaCrossing> copy;
    if (!shifted_copy(s, vt, vs, chart.spoke[j], e_w, ccw ? 1.0 : -1.0, eps, other, copy)) {
      last_refusal_ = "the boundary split in place could not be set up";
      continue;
    }
    proposal.lists.push_back({e_w, std::move(copy)});
    for (auto& [h, list] : other) {
      std::sort(list.begin(), list.end(),
                [](const auto& a, const auto& b) { return a.here < b.here; });
      proposal.other_lists.push_back({h, std::move(list)});
    }
    if (apply(s, changed, proposal, limit, limit < HUGE_VAL)) {
      ++stats_.splits_in_place;
      last_split_growth_ = faces_energy(s, changed) / before;
      return vs;
    }
  }
  undo_all();
  return -1;
}

int InterSurfaceMap::try_split(int s, bool place, double cap) {
  const VertexSplit& sp = input_[s].splits[next_split_[s]];
  if (sp.vl < 0 || sp.vr < 0) return try_boundary_split(s, place, cap);
  const std::string where = std::string(s == 0 ? "M¹" : "M²") + " split " +
                            std::to_string(next_split_[s]) + " (vertex " + std::to_string(sp.vs) +
                            " from " + std::to_string(sp.vt) + ")";
  Chart chart;
  bool charted = false;
  std::size_t m = 0, last = 0;
  if (index_[s].open && ring_faces(s, sp.vt).empty()) {
    // A boundary vertex with both wings: where the fan from vl to vr lies
    // inside, it moves to vs (an inner vertex), split in place with that
    // fan as the chart's ring; where it runs across the boundary (vs would
    // take the boundary from vt), the split is refused.
    Chart fan;
    if (!build_chart_from(s, sp.vt, -1, fan, true, true))
      throw std::runtime_error(where +
                               ": a split at the boundary of a vertex that is not on a boundary "
                               "edge of the other surface, which open maps do not refine yet");
    const auto a = std::find(fan.ring.begin(), fan.ring.end(), sp.vl) - fan.ring.begin();
    const auto b = std::find(fan.ring.begin(), fan.ring.end(), sp.vr) - fan.ring.begin();
    if (a == std::ptrdiff_t(fan.ring.size()) || b == std::ptrdiff_t(fan.ring.size()))
      throw std::runtime_error(where + ": vl or vr is not a neighbour of the vertex to split");
    if (a >= b)
      throw std::runtime_error(where +
                               ": a split at the boundary that moves a fan across it, which open "
                               "maps do not refine yet");
    chart.s = s, chart.t = 1 - s, chart.v = sp.vt;
    chart.faces.assign(fan.faces.begin() + a, fan.faces.begin() + b);
    chart.corner.assign(fan.corner.begin() + a, fan.corner.begin() + b);
    chart.boundary.assign(fan.boundary.begin() + a, fan.boundary.begin() + b);
    chart.ring.assign(fan.ring.begin() + a, fan.ring.begin() + b + 1);
    chart.spoke.assign(fan.spoke.begin() + a, fan.spoke.begin() + b + 1);
    m = last = chart.faces.size();
  } else {
    charted = build_chart_from(s, sp.vt, sp.vl, chart);
    if (!charted && !build_chart_from(s, sp.vt, sp.vl, chart, true))
      throw std::runtime_error(where + ": the ring of the vertex to split is not a closed fan");
    m = last = chart.faces.size();
    for (std::size_t i = 1; i < m; ++i)
      if (chart.ring[i] == sp.vr) last = i;
    if (last == m) throw std::runtime_error(where + ": vr is not a neighbour after vl");
  }

  // The energy of the ring before the split bounds the placement's.
  const double before = place ? faces_energy(s, chart.faces) : HUGE_VAL;
  const double limit = before < HUGE_VAL && cap < HUGE_VAL ? cap * before : HUGE_VAL;

  // The other side's faces under the ring take its new metric (the new
  // faces lie inside it): their cached sums go stale.
  touch_under(s, chart.faces);

  // Connectivity: the faces from vl to vr go to vs, two new faces.
  MetaSide& S = meta_.side[s];
  MetaSideIndex& IS = index_[s];
  const int vt = sp.vt, vs = sp.vs;
  const SplitUndo undo = split_undo(s, chart, sp);
  for (std::size_t i = 1; i < last; ++i) {
    // Edge (vt, w) becomes (vs, w): same records, renamed.
    const int e = chart.spoke[i], w = chart.ring[i];
    IS.edge_of.erase(undirected_edge_key(vt, w));
    const bool flip = (vt < w) != (vs < w);
    S.edges[e] = {std::min(vs, w), std::max(vs, w)};
    IS.edge_of[undirected_edge_key(vs, w)] = e;
    std::erase(IS.vertex_edges[vt], e);
    IS.vertex_edges[vs].push_back(e);
    if (flip) {
      auto& list = S.crossings[e];
      std::reverse(list.begin(), list.end());
      std::vector<int> others;
      for (auto& c : list) {
        c.here = 1 - c.here;
        if (!c.is_kink()) others.push_back(c.edge);
      }
      std::sort(others.begin(), others.end());
      others.erase(std::unique(others.begin(), others.end()), others.end());
      for (int g : others)
        for (auto& o : meta_.side[1 - s].crossings[g])
          if (o.edge == e) o.there = 1 - o.there;
    }
  }
  for (std::size_t i = 0; i < last; ++i) {
    const int f = chart.faces[i];
    area_[s] -= face_area(s, f);
    S.faces[f][chart.corner[i]] = vs;
    if (!S.positions.empty()) S.lengths[f] = face_lengths(s, S.faces[f]);
    area_[s] += face_area(s, f);
    std::erase(IS.vertex_faces[vt], f);
    IS.vertex_faces[vs].push_back(f);
  }
  const int e_vl = add_edge(s, vs, sp.vl), e_vr = add_edge(s, vs, sp.vr),
            e_vt = add_edge(s, vs, vt);
  const int fa = int(S.faces.size()), fb = fa + 1;
  for (const Triangle& tri : {Triangle{vs, vt, sp.vl}, Triangle{vt, vs, sp.vr}}) {
    S.faces.push_back(tri);
    S.lengths.push_back(S.positions.empty() ? FaceLengths{1, 1, 1} : face_lengths(s, tri));
    S.face_edges.push_back({});
    IS.residents.emplace_back();
    for (int x : tri) IS.vertex_faces[x].push_back(int(S.faces.size()) - 1);
    area_[s] += face_area(s, int(S.faces.size()) - 1);
  }
  std::vector<int> changed(chart.faces.begin(), chart.faces.end());
  changed.push_back(fa), changed.push_back(fb);
  for (int f : changed)
    for (int k = 0; k < 3; ++k) {
      const int u = S.faces[f][k], w = S.faces[f][(k + 1) % 3];
      const int e = IS.edge(u, w);
      S.face_edges[f][k] = e;
      IS.edge_faces[e][u == S.edges[e][0] ? 0 : 1] = f;
    }
  ++active_[s];
  ++next_split_[s];
  ++stats_.splits;
  pinned_[s][vs] = 0;
  if (!place) {
    restore(s, undo);
    return -1;
  }

  // Placement: vt stays, vs in the middle of the kernel of its new ring.
  Layout layout;
  layout.inner.push_back({vs, chart.centre, -1});
  layout.inner.push_back({vt, chart.centre, chart.centre_anchor});
  for (std::size_t i = 0; i < m; ++i) {
    std::array<int, 3> ref;
    const int c = chart.corner[i];
    ref[c] = i < last ? -1 : -2, ref[(c + 1) % 3] = int(i), ref[(c + 2) % 3] = int((i + 1) % m);
    layout.tris.push_back({chart.faces[i], ref, meta_face_layout(S.lengths[chart.faces[i]])});
  }
  // A strict attempt keeps the clearance of moves; the last one may come
  // closer (a split must place its vertex).
  layout.clearance = cap < HUGE_VAL ? 1e-6 : 1e-8;
  layout.tris.push_back({fa, {-1, -2, 0}, meta_face_layout(S.lengths[fa])});
  layout.tris.push_back({fb, {-2, -1, int(last)}, meta_face_layout(S.lengths[fb])});
  for (std::size_t i = 0; i <= last; ++i)
    layout.spokes.push_back({-1, int(i), i == 0 ? e_vl : i == last ? e_vr : chart.spoke[i]});
  for (std::size_t i = last; i <= m; ++i)
    layout.spokes.push_back({-2, int(i % m), chart.spoke[i % m]});
  layout.spokes.push_back({-1, -2, e_vt});

  // Candidate places for vs: the middle of the kernel of its new ring, and
  // the middles of the triangles (vt, w_j, w_j+1) it takes over, each also
  // drawn towards vt; the valid one of lowest energy wins. vt stays; in
  // the last attempt, when no candidate there is valid and accepted (straight edges
  // from vt's place need not stay inside a ring whose edges bend in the
  // chart), vt goes to the middle of the kernel of the whole ring and the
  // candidates are tried again around it, before the split in place.
  std::vector<Vec2> vt_places{chart.centre};
  if (charted && !(cap < HUGE_VAL) && !pinned_[s][vt])  // (a held feature stays)
    if (const auto middle = kernel_centroid(boundary_polygon(chart, 0, m)))
      if (*middle != chart.centre) vt_places.push_back(*middle);
  for (std::size_t round = 0; charted && round < vt_places.size(); ++round) {
    const Vec2 centre = vt_places[round];
    layout.inner[1].pos = centre;
    layout.inner[1].on_anchor = round == 0 ? chart.centre_anchor : -1;
    std::vector<Vec2> polygon = boundary_polygon(chart, 0, last);
    polygon.push_back(centre);
    std::vector<Vec2> candidates;
    if (const std::optional<Vec2> kernel = kernel_centroid(polygon)) candidates.push_back(*kernel);
    for (std::size_t j = 0; j < last; ++j)
      candidates.push_back((centre + chart.w[j] + chart.w[j + 1]) / 3);
    const std::size_t n_base = candidates.size();
    // The first halvings with them; the rest only when none of those is
    // valid below the limit.
    const int first = std::clamp(split_placement_.first_halvings, 0, 8);
    std::vector<std::pair<double, Vec2>> ranked;  // valid candidates below the limit
    for (int from = 1, to = first; ranked.empty(); from = to + 1, to = 8) {
      std::vector<Vec2> tried = from == 1 ? candidates : std::vector<Vec2>{};
      for (int k = from; k <= to; ++k)
        for (std::size_t c = 0; c < n_base; ++c)
          tried.push_back(centre + std::pow(0.5, k) * (candidates[c] - centre));
      // Evaluated in parallel in the caller's arena (each task with its own
      // layout; evaluate is const), ranked in the candidates' order: the
      // same result for any number of threads.
      std::erase_if(tried, [&](const Vec2& c) { return !inside_polygon(polygon, c); });
      std::vector<double> energies(tried.size());
      evaluate_each(chart, layout, tried, energies, 4);
      stats_.split_evaluations += tried.size();
      for (std::size_t k = 0; k < tried.size(); ++k)
        if (energies[k] < limit) ranked.push_back({energies[k], tried[k]});
      if (to == 8) break;
    }
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    if (!ranked.empty()) {
      // Line searches from the best candidate, inside vs's kernel (the
      // central differences' points in two halves in parallel).
      Vec2 p = ranked[0].second;
      const double e = minimize_in_kernel(
          polygon, p,
          [&](const Vec2& q) {
            layout.inner[0].pos = q;
            ++stats_.split_evaluations;
            return evaluate(chart, layout, nullptr);
          },
          LineSearch::parabolic, HUGE_VAL, split_placement_.search,
          [&](std::span<const Vec2> at, std::span<double> out) {
            stats_.split_evaluations += at.size();
            evaluate_each(chart, layout, at, out, (at.size() + 1) / 2);
          });
      if (e < ranked[0].first) ranked.insert(ranked.begin(), {e, p});
    }
    // The transaction's check may refuse a place the chart accepts (the
    // faces of the other side cut differently): then the next best.
    constexpr std::size_t kTries = 8;
    for (std::size_t k = 0; k < ranked.size() && k < kTries; ++k) {
      layout.inner[0].pos = ranked[k].second;
      Proposal proposal;
      if (evaluate(chart, layout, &proposal) < HUGE_VAL &&
          apply(s, changed, proposal, limit, limit < HUGE_VAL)) {
        last_split_growth_ = faces_energy(s, changed) / before;
        stats_.splits_old_moved += round > 0;
        return vs;
      }
      chart_failure_ = 5000;
    }
  }
  // Fallback: vs next to vt, its edges along vt's old ones; as far out as
  // the transaction accepts (a vertex put 1e-11 of the way leaves later
  // splits there no room).
  for (double eps = 0.25; eps > 1e-12; eps *= 0.0625) {
    Proposal proposal;
    const bool set_up = split_in_place(chart, last, vs, e_vl, e_vr, eps, proposal);
    if (!set_up) last_refusal_ = "the split in place could not be set up";
    if (set_up && apply(s, changed, proposal, limit, limit < HUGE_VAL)) {
      ++stats_.splits_in_place;
      last_split_growth_ = faces_energy(s, changed) / before;
      return vs;
    }
  }
  restore(s, undo);
  return -1;
}

InterSurfaceMap::SplitUndo InterSurfaceMap::split_undo(int s, const Chart& chart,
                                                       const VertexSplit& sp) const {
  // The connectivity change renames vt's spokes to vs (reversing the
  // crossings of those whose ends swap order), adds three edges and two
  // faces, and rewrites the ring's faces and the four vertices' lists.
  const MetaSide& S = meta_.side[s];
  const MetaSideIndex& IS = index_[s];
  SplitUndo u;
  u.n_edges = S.edges.size();
  u.n_faces = S.faces.size();
  u.area = area_[s];
  for (int x : {sp.vt, sp.vs, sp.vl, sp.vr})
    if (x >= 0) u.vertices.push_back({x, IS.vertex_edges[x], IS.vertex_faces[x]});
  for (int f : chart.faces) u.faces.push_back({f, S.faces[f], S.lengths[f], S.face_edges[f]});
  std::vector<int> others;
  for (std::size_t i = 0; i < chart.spoke.size(); ++i) {
    const int e = chart.spoke[i], w = chart.ring[i];
    SplitUndo::EdgeRecord r{e, S.edges[e], IS.edge_faces[e], {}};
    if ((sp.vt < w) != (sp.vs < w)) {  // reversed if renamed: keep its crossings
      r.crossings = S.crossings[e];
      for (const MetaCrossing& c : r.crossings)
        if (!c.is_kink()) others.push_back(c.edge);
    }
    u.edges.push_back(std::move(r));
  }
  std::sort(others.begin(), others.end());
  others.erase(std::unique(others.begin(), others.end()), others.end());
  for (int g : others) u.other_lists.push_back({g, meta_.side[1 - s].crossings[g]});
  return u;
}

void InterSurfaceMap::restore(int s, const SplitUndo& u) {
  MetaSide& S = meta_.side[s];
  MetaSideIndex& IS = index_[s];
  // Keys of the edges as the split named them, then as they were.
  for (std::size_t e = u.n_edges; e < S.edges.size(); ++e)
    IS.edge_of.erase(undirected_edge_key(S.edges[e][0], S.edges[e][1]));
  for (const auto& r : u.edges)
    IS.edge_of.erase(undirected_edge_key(S.edges[r.edge][0], S.edges[r.edge][1]));
  for (const auto& r : u.edges) {
    S.edges[r.edge] = r.ends;
    IS.edge_faces[r.edge] = r.faces;
    if (!r.crossings.empty()) S.crossings[r.edge] = r.crossings;
    IS.edge_of[undirected_edge_key(r.ends[0], r.ends[1])] = r.edge;
  }
  for (const auto& [g, list] : u.other_lists) meta_.side[1 - s].crossings[g] = list;
  S.edges.resize(u.n_edges);
  S.crossings.resize(u.n_edges);
  IS.edge_faces.resize(u.n_edges);
  if (IS.open) IS.on_edge.resize(u.n_edges);
  for (const auto& r : u.faces) {
    S.faces[r.face] = r.corners;
    S.lengths[r.face] = r.lengths;
    S.face_edges[r.face] = r.edges;
  }
  S.faces.resize(u.n_faces);
  S.lengths.resize(u.n_faces);
  S.face_edges.resize(u.n_faces);
  IS.residents.resize(u.n_faces);
  for (const auto& r : u.vertices) {
    IS.vertex_edges[r.vertex] = r.edges;
    IS.vertex_faces[r.vertex] = r.faces;
  }
  area_[s] = u.area;
  if (sums_cache_[s].size() > u.n_faces) sums_cache_[s].resize(u.n_faces);
  --active_[s];
  --next_split_[s];
  --stats_.splits;
}

int InterSurfaceMap::split_next(int s) {
  if (next_split_[s] >= input_[s].splits.size()) return -1;
  for (int attempt = 0;; ++attempt) {
    // Placements raising the ring's energy more than kSplitEnergyCap-fold
    // are refused but in the last attempt of each round: such a piece is
    // nearly degenerate, and later moves often cannot undo it. A split the
    // first round places is placed as with one round.
    const bool uncapped = attempt % (kSplitRetries + 1) == kSplitRetries;
    const bool refused = refused_split_attempts_ > 0;  // (tests)
    if (refused) --refused_split_attempts_;
    const int vs = refused ? -1 : try_split(s, true, uncapped ? HUGE_VAL : kSplitEnergyCap);
    // (Placed or undone, a split changes connectivity and metrics: every
    // plan is stale. The cached energies it changes, it touched.)
    touch_all({});
    if (vs >= 0) {
      stats_.splits_later_round += attempt > kSplitRetries;
      return vs;
    }
    const VertexSplit& sp = input_[s].splits[next_split_[s]];
    if (attempt == kSplitRounds * (kSplitRetries + 1) - 1)
      throw std::runtime_error(
          std::string(s == 0 ? "M¹" : "M²") + " split " + std::to_string(next_split_[s]) +
          " (vertex " + std::to_string(sp.vs) + " from " + std::to_string(sp.vt) +
          (pinned_[s][sp.vt] ? ", a feature held on the other surface" : "") +
          "): no valid placement of the new vertex after " + std::to_string(attempt) +
          " retries (chart " + std::to_string(chart_failure_) + "; in place: " + last_refusal_ +
          ")");
    // The map is as before the split. Move what makes vt's ring hard to
    // chart: the other side's vertices inside or on the rings around vt,
    // then vt and the vertices of those rings (each move kept only if
    // valid and lower in energy), and try again; each retry one ring
    // wider (a sliver wedge may need room from further out).
    ++stats_.split_retries;
    std::vector<int> mine{sp.vt};
    std::size_t centres = 1;  // mine[0..centres): the vertices whose rings are searched
    for (int radius = 0; radius <= attempt; ++radius) {
      centres = mine.size();
      for (std::size_t i = 0; i < centres; ++i)
        for (int w : neighbours(s, mine[i]))
          if (std::find(mine.begin(), mine.end(), w) == mine.end()) mine.push_back(w);
    }
    std::vector<int> theirs;
    for (std::size_t i = 0; i < centres; ++i)
      for (int x : others_in_ring(s, mine[i]))
        if (std::find(theirs.begin(), theirs.end(), x) == theirs.end()) theirs.push_back(x);
    for (int x : theirs)
      if (is_active(1 - s, x)) optimize_vertex(1 - s, x);
    std::rotate(mine.begin(), mine.begin() + 1, mine.end());  // vt last
    for (int v : mine)
      if (is_active(s, v)) optimize_vertex(s, v);
  }
}

}  // namespace ism
