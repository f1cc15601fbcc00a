#include "map/flat_torus_overlay.hpp"

#include <algorithm>
#include <cmath>

namespace ism {
namespace {

// Below this a barycentric coordinate or segment parameter is taken as 0:
// a point on an edge or vertex of the other side.
constexpr double kDegenerate = 1e-12;

// Side 0's faces laid out in the unit square, in side 0's corner order;
// nothing unless the domain is a flat unit-square torus and side 0's faces
// are its faces.
std::optional<std::vector<std::array<Vec2, 3>>> side0_layouts(const InterSurfaceMap& map,
                                                              const DomainGeometry& domain) {
  const auto square = unit_square_layouts(domain);
  if (!square) return std::nullopt;
  const MetaSide& side = map.meta().side[0];
  if (side.n_vertices() != domain.n_vertices()) return std::nullopt;
  std::vector<std::array<Vec2, 3>> out(side.faces.size());
  for (std::size_t f = 0; f < side.faces.size(); ++f) {
    const auto found = domain.find_face(side.faces[f]);
    if (!found) return std::nullopt;
    const auto [g, r] = *found;
    for (int k = 0; k < 3; ++k) out[f][k] = (*square)[g][(k + r) % 3];
  }
  return out;
}

// The corner of face f holding vertex x (-1 if none).
int corner_of(const Triangle& t, int x) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == x) return k;
  return -1;
}

Vec2 floor2(const Vec2& p) {
  return p.array().floor().matrix();
}

}  // namespace

std::optional<FlatTorusLayout> flat_layout(const InterSurfaceMap& map,
                                           const DomainGeometry& domain) {
  const auto layout0 = side0_layouts(map, domain);
  if (!layout0) return std::nullopt;
  const MetaSide& d = map.meta().side[0];
  const MetaSide& s = map.meta().side[1];
  // The faces on either side of each domain edge.
  std::vector<std::array<int, 2>> edge_faces(d.edges.size(), {-1, -1});
  for (std::size_t f = 0; f < d.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      auto& ef = edge_faces[d.face_edges[f][k]];
      (ef[0] < 0 ? ef[0] : ef[1]) = int(f);
    }
  // Where each side-1 vertex is: a domain face holding it (one of those
  // around it if it lies on a domain vertex) and its point in that face's
  // layout.
  auto at_vertex = [&](int f, int x) { return (*layout0)[f][corner_of(d.faces[f], x)]; };
  FlatTorusLayout out;
  out.position.assign(s.n_vertices(), Vec2::Zero());
  for (std::size_t v = 0; v < s.n_vertices(); ++v) {
    const MetaLocation& loc = s.location[v];
    Vec2 p;
    if (loc.vertex >= 0) {
      p = at_vertex(
          int(std::find_if(d.faces.begin(), d.faces.end(),
                           [&](const Triangle& t) { return corner_of(t, loc.vertex) >= 0; }) -
              d.faces.begin()),
          loc.vertex);
    } else if (loc.face >= 0) {
      p = from_barycentric(loc.bary, (*layout0)[loc.face]);
    } else {
      continue;
    }
    out.position[v] = p - floor2(p);
  }
  // The face across domain edge e from face f (-1 if f is not beside it).
  auto across = [&](int e, int f) {
    const auto& ef = edge_faces[e];
    return ef[0] == f ? ef[1] : ef[1] == f ? ef[0] : -1;
  };
  // The displacement in the plane from the lift of `from` to that of `to`
  // along the image of side-1 edge e between them: the translations of the
  // faces the image crosses, face to face.
  auto displacement = [&](int e, int from, int to) -> std::optional<Vec2> {
    const auto& list = s.crossings[e];
    const bool forward = s.edges[e][0] == from;
    auto crossing = [&](std::size_t i) -> const MetaCrossing& {
      return list[forward ? i : list.size() - 1 - i];
    };
    std::size_t first = 0;
    while (first < list.size() && crossing(first).is_kink()) ++first;
    // The face the image starts in: `from`'s, or beside the vertex it lies
    // on, the one opposite the first domain edge crossed (or holding `to`).
    const MetaLocation &start = s.location[from], &end = s.location[to];
    int f = start.face;
    Vec2 p0;
    if (start.vertex >= 0) {
      f = -1;
      if (first < list.size()) {
        for (int g : edge_faces[crossing(first).edge])
          if (g >= 0 && corner_of(d.faces[g], start.vertex) >= 0) f = g;
      } else if (end.face >= 0 && corner_of(d.faces[end.face], start.vertex) >= 0) {
        f = end.face;
      }
      if (f < 0) return std::nullopt;
      p0 = at_vertex(f, start.vertex);
    } else {
      p0 = from_barycentric(start.bary, (*layout0)[f]);
    }
    Vec2 shift = Vec2::Zero();  // lifted = point in face f's layout + shift
    for (std::size_t i = first; i < list.size(); ++i) {
      const MetaCrossing& c = crossing(i);
      if (c.is_kink()) continue;
      const int next = across(c.edge, f);
      if (next < 0) return std::nullopt;
      // A vertex of the shared edge, in both faces' layouts.
      const int x = d.edges[c.edge][0];
      shift -= at_vertex(next, x) - at_vertex(f, x);
      f = next;
    }
    Vec2 p1;
    if (end.vertex >= 0) {
      if (corner_of(d.faces[f], end.vertex) < 0) return std::nullopt;
      p1 = at_vertex(f, end.vertex);
    } else {
      if (f != end.face) return std::nullopt;
      p1 = from_barycentric(end.bary, (*layout0)[f]);
    }
    return p1 + shift - p0;
  };
  out.shift.resize(s.faces.size());
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    const Triangle& tri = s.faces[t];
    std::array<Vec2, 3> lifted;
    lifted[0] = out.position[tri[0]];
    for (int c : {1, 2}) {
      // Edge 0 runs from corner 0 to 1; edge 2 from corner 2 to 0.
      const auto step = displacement(s.face_edges[t][c == 1 ? 0 : 2], tri[0], tri[c]);
      if (!step) return std::nullopt;
      lifted[c] = lifted[0] + *step;
    }
    for (int c = 0; c < 3; ++c) {
      const Vec2 n = lifted[c] - out.position[tri[c]];
      const Vec2 r = n.array().round().matrix();
      if ((n - r).norm() > 1e-6) return std::nullopt;
      out.shift[t][c] = r.cast<int>();
    }
  }
  return out;
}

std::optional<MetaMesh> flat_torus_overlay(const InterSurfaceMap& map, const DomainGeometry& domain,
                                           const FlatTorusLayout& layout) {
  const auto layout0 = side0_layouts(map, domain);
  if (!layout0) return std::nullopt;
  MetaMesh out = map.meta();
  MetaSide& d = out.side[0];
  MetaSide& s = out.side[1];
  if (layout.position.size() != s.n_vertices() || layout.shift.size() != s.faces.size())
    return std::nullopt;
  for (MetaSide* side : {&d, &s}) {
    for (MetaLocation& loc : side->location)  // -2: used, to be placed
      if (loc.face >= 0 || loc.vertex >= 0) loc = MetaLocation{.vertex = -1, .face = -2};
    for (auto& list : side->crossings) list.clear();
  }
  auto lifted = [&](int t) {
    return std::array<Vec2, 3>{layout.corner(s.faces, t, 0), layout.corner(s.faces, t, 1),
                               layout.corner(s.faces, t, 2)};
  };
  struct Box {
    Vec2 lo, hi;
  };
  auto box = [](const auto& points) {
    Box b{points[0], points[0]};
    for (const Vec2& p : points) b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
    return b;
  };
  // The integer translations n with (b + n) meeting a.
  auto translations = [](const Box& a, const Box& b, auto&& visit) {
    for (int nx = int(std::ceil(a.lo.x() - b.hi.x())); nx <= int(std::floor(a.hi.x() - b.lo.x()));
         ++nx)
      for (int ny = int(std::ceil(a.lo.y() - b.hi.y())); ny <= int(std::floor(a.hi.y() - b.lo.y()));
           ++ny)
        if (!visit(Vec2(nx, ny))) return false;
    return true;
  };

  // Side-1 vertices: in the domain face (some copy of it) holding the point.
  for (std::size_t v = 0; v < s.n_vertices(); ++v) {
    if (s.location[v].face != -2) continue;
    const Vec2 p = layout.position[v];
    if (!p.allFinite()) return std::nullopt;
    const Box at{p, p};
    int best_face = -1;
    double best = -HUGE_VAL;
    Eigen::Vector3d best_bary;
    for (std::size_t f = 0; f < layout0->size(); ++f)
      translations(at, box((*layout0)[f]), [&](const Vec2& n) {
        const auto& l = (*layout0)[f];
        const Eigen::Vector3d b = barycentric(p, l[0] + n, l[1] + n, l[2] + n);
        if (b.minCoeff() > best) best = b.minCoeff(), best_face = int(f), best_bary = b;
        return true;
      });
    if (!(best > kDegenerate)) return std::nullopt;
    s.location[v] =
        MetaLocation{.vertex = -1, .face = best_face, .bary = best_bary / best_bary.sum()};
  }
  // Domain vertices: inside the side-1 face whose lifted triangle holds them.
  std::vector<Vec2> domain_point(d.n_vertices());
  for (std::size_t f = 0; f < d.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) domain_point[d.faces[f][k]] = (*layout0)[f][k];
  std::vector<double> best(d.n_vertices(), -HUGE_VAL);
  std::vector<MetaLocation> found(d.n_vertices());
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    const auto l = lifted(int(t));
    if (!(orient(l[0], l[1], l[2]) > 0)) return std::nullopt;
    const Box face_box = box(l);
    for (std::size_t x = 0; x < d.n_vertices(); ++x) {
      if (d.location[x].face != -2) continue;  // unused
      const Box at{domain_point[x], domain_point[x]};
      translations(face_box, at, [&](const Vec2& n) {
        const Eigen::Vector3d b = barycentric(domain_point[x] + n, l[0], l[1], l[2]);
        if (b.minCoeff() > best[x])
          best[x] = b.minCoeff(), found[x] = {.vertex = -1, .face = int(t), .bary = b / b.sum()};
        return true;
      });
    }
  }
  for (std::size_t x = 0; x < d.n_vertices(); ++x) {
    if (d.location[x].face != -2) continue;
    if (!(best[x] > kDegenerate)) return std::nullopt;
    d.location[x] = found[x];
  }

  // Crossings of every side-1 edge with every domain edge (some copy of it).
  std::vector<std::array<Vec2, 2>> domain_edge(d.edges.size());
  for (std::size_t f = 0; f < d.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int e = d.face_edges[f][k];
      const bool forward = d.faces[f][k] == d.edges[e][0];
      const Vec2 a = (*layout0)[f][k], b = (*layout0)[f][(k + 1) % 3];
      domain_edge[e] = forward ? std::array<Vec2, 2>{a, b} : std::array<Vec2, 2>{b, a};
    }
  std::vector<char> done(s.edges.size(), 0);
  auto cross = [](const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); };
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    const auto l = lifted(int(t));
    for (int k = 0; k < 3; ++k) {
      const int e = s.face_edges[t][k];
      if (done[e]) continue;
      done[e] = 1;
      const bool forward = s.faces[t][k] == s.edges[e][0];
      const Vec2 a = forward ? l[k] : l[(k + 1) % 3], b = forward ? l[(k + 1) % 3] : l[k];
      const Box segment_box = box(std::array<Vec2, 2>{a, b});
      for (std::size_t de = 0; de < d.edges.size(); ++de) {
        const auto& [p, q] = domain_edge[de];
        const bool ok = translations(segment_box, box(domain_edge[de]), [&](const Vec2& n) {
          const Vec2 r = b - a, w = q - p, o = p + n - a;
          const double denom = cross(r, w);
          const double along = cross(o, w), there = cross(o, r);
          if (denom == 0) return along != 0;  // collinear overlap: degenerate
          const double sa = along / denom, sd = there / denom;
          if (sa < -kDegenerate || sa > 1 + kDegenerate || sd < -kDegenerate ||
              sd > 1 + kDegenerate)
            return true;
          if (sa < kDegenerate || sa > 1 - kDegenerate || sd < kDegenerate || sd > 1 - kDegenerate)
            return false;  // through a vertex
          s.crossings[e].push_back({int(de), sa, sd});
          d.crossings[de].push_back({e, sd, sa});
          return true;
        });
        if (!ok) return std::nullopt;
      }
    }
  }
  for (MetaSide* side : {&d, &s})
    for (auto& list : side->crossings)
      std::sort(list.begin(), list.end(),
                [](const MetaCrossing& x, const MetaCrossing& y) { return x.here < y.here; });
  return out;
}

}  // namespace ism
