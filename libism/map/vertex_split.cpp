// Refinement of M² by one vertex split of its progressive mesh, with the map
// updated locally: the new vertex is embedded inside the old one-ring, close
// to the split vertex, in the sector of the faces it takes over, so every
// face stays positive; optimisation then moves it to a good place.
#include "map/surface_map.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ism {

int SurfaceMap::split_next() {
  if (next_split_ >= pm_.splits.size()) return -1;
  const VertexSplit& s = pm_.splits[next_split_];
  const std::string where = "split " + std::to_string(next_split_) + " (vertex " +
                            std::to_string(s.vs) + " from " + std::to_string(s.vt) + ")";

  // The ring of vt in a chart, starting at the face (vt, vl, *).
  Ring ring;
  if (!build_ring(s.vt, ring)) throw std::runtime_error(where + ": invalid ring");
  const std::size_t m = ring.faces.size();
  std::size_t first = m;
  for (std::size_t i = 0; i < m; ++i)
    if (ring.vertices[i] == s.vl) first = i;
  if (first == m) throw std::runtime_error(where + ": vl is not a neighbour");
  // Rotate the ring so it starts at vl; rebuild positions for a cone centre
  // so that the fan vl..vr is unwrapped contiguously.
  auto rotate = [&](auto& v) { std::rotate(v.begin(), v.begin() + first, v.end()); };
  rotate(ring.faces), rotate(ring.corner), rotate(ring.vertices), rotate(ring.positions);
  rotate(ring.end_face), rotate(ring.end_layout);
  const int x = at_domain_vertex_[s.vt];
  if (x >= 0) {
    double previous = -HUGE_VAL, extra = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      const EdgeWalk& w = walks_[ring.faces[i]][ring.corner[i]];
      const int idx = fan_index(x, w.start_face);
      const double start = domain_.fan(x)[idx].start;
      if (start + extra < previous - 1e-12) extra += domain_.total_angle(x);
      previous = start + extra;
      const WalkEnd end = follow(w, domain_.fan_layout(x, idx, extra));
      ring.positions[i] = position_in(ring.vertices[i], end.face, end.layout);
      ring.end_face[i] = end.face;
      ring.end_layout[i] = end.layout;
      if (i == 0) {
        ring.centre_face = w.start_face;
        ring.centre_layout = domain_.fan_layout(x, idx, extra);
      }
    }
  }
  std::size_t last = m;  // index of vr in the ring
  for (std::size_t i = 1; i < m; ++i)
    if (ring.vertices[i] == s.vr) last = i;
  if (last == m) throw std::runtime_error(where + ": vr is not a neighbour after vl");

  // Direction for vs: inside the sector vl..vr (ccw) and on the correct side
  // of both new faces (vs, vt, vl) and (vt, vs, vr).
  const Vec2 pt = ring.centre;
  double sector = 0.0;
  for (std::size_t i = 0; i < last; ++i) {
    const Vec2 a = ring.positions[i] - pt, b = ring.positions[i + 1] - pt;
    sector += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  const double phi = 0.5 * (std::max(0.0, sector - M_PI) + std::min(sector, M_PI));
  const Vec2 dl = (ring.positions[0] - pt).normalized();
  const Vec2 d(std::cos(phi) * dl.x() - std::sin(phi) * dl.y(),
               std::sin(phi) * dl.x() + std::cos(phi) * dl.y());
  double eps = HUGE_VAL;
  for (std::size_t i = 0; i <= last; ++i) eps = std::min(eps, (ring.positions[i] - pt).norm());
  eps *= 0.25;
  Vec2 ps;
  bool valid = false;
  for (int attempt = 0; attempt < 60 && !valid; ++attempt, eps *= 0.5) {
    ps = pt + eps * d;
    valid = orient(ps, pt, ring.positions[0]) > 0 && orient(pt, ps, ring.positions[last]) > 0;
    for (std::size_t i = 0; valid && i < last; ++i)
      valid = orient(ps, ring.positions[i], ring.positions[i + 1]) > 0;
  }
  if (!valid) {
    if (std::getenv("ISM_DEBUG")) {
      std::fprintf(stderr, "x=%d sector=%g last=%zu m=%zu pt=(%g,%g)\n", x, sector, last, m, pt.x(), pt.y());
      for (std::size_t i = 0; i < m; ++i) {
        const EdgeWalk& w = walks_[ring.faces[i]][ring.corner[i]];
        std::fprintf(stderr, "  %zu v=%d pos=(%g,%g) start=%d count=%d at=%d\n", i, ring.vertices[i], ring.positions[i].x(), ring.positions[i].y(), w.start_face, w.count, at_domain_vertex_[ring.vertices[i]]);
      }
    }
    throw std::runtime_error(where + ": no valid position for the new vertex");
  }

  // Locate vs in M¹: from vt's position, in the face holding direction d.
  int face = ring.centre_face;
  std::array<Vec2, 3> layout = ring.centre_layout;
  if (x >= 0) {
    for (std::size_t i = 0; i < domain_.fan(x).size(); ++i) {
      const Triangle& t = domain_.mesh().triangles[face];
      const int c = t[0] == x ? 0 : t[1] == x ? 1 : 2;
      if (orient(layout[c], layout[(c + 1) % 3], ps) >= 0 &&
          orient(layout[c], ps, layout[(c + 2) % 3]) >= 0)
        break;
      layout = domain_.unfold(face, layout, (c + 2) % 3);
      face = domain_.neighbour(face, (c + 2) % 3);
    }
  }
  EdgeWalk scratch;
  WalkEnd at;
  if (!trace(face, layout, pt, ps, scratch, at)) throw std::runtime_error(where + ": cannot locate");

  // Walks from vs to vl..vr and to vt.
  std::vector<EdgeWalk> forward(last + 1);
  for (std::size_t i = 0; i <= last; ++i) {
    WalkEnd e;
    if (!trace(at.face, at.layout, ps, ring.positions[i], forward[i], e))
      throw std::runtime_error(where + ": cannot trace a new edge");
  }
  EdgeWalk to_vt;
  {
    WalkEnd e;
    if (!trace(at.face, at.layout, ps, pt, to_vt, e))
      throw std::runtime_error(where + ": cannot trace the new edge to vt");
  }
  const EdgeWalk vt_to_vl = walks_[ring.faces[0]][ring.corner[0]];
  const EdgeWalk vr_to_vt = walks_[ring.faces[last - 1]][(ring.corner[last - 1] + 2) % 3];

  // Topology: the fan vl..vr moves from vt to vs.
  auto area_of = [&](int f) {
    const Triangle& t = faces_[f];
    return 0.5 * (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]).norm();
  };
  for (std::size_t i = 0; i < last; ++i) {
    const int f = ring.faces[i], c = ring.corner[i];
    surface_area_ -= area_of(f);
    faces_[f][c] = s.vs;
    surface_area_ += area_of(f);
    std::erase(vertex_faces_[s.vt], f);
    vertex_faces_[s.vs].push_back(f);
    walks_[f][c] = forward[i];
    walks_[f][(c + 2) % 3] = reversed(forward[i + 1]);
  }
  set_location(s.vs, at.face, at.layout, ps);
  pinned_[s.vs] = 0;
  const int a = int(faces_.size());
  add_face({s.vs, s.vt, s.vl});
  walks_[a] = {to_vt, vt_to_vl, reversed(forward[0])};
  const int b = int(faces_.size());
  add_face({s.vt, s.vs, s.vr});
  walks_[b] = {reversed(to_vt), forward[last], vr_to_vt};
  surface_area_ += area_of(a) + area_of(b);
  ++active_vertices_;
  ++next_split_;
  return s.vs;
}

}  // namespace ism
