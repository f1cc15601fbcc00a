// Releasing cone points of M¹. A cone (angle sum ≠ 2π) must sit on a vertex
// of M² for every one-ring to stay flat; it is released by moving it to a
// neighbouring vertex w when that lowers the symmetric energy: w goes onto
// the cone, the old vertex v becomes free and is optimised in its new
// one-ring. At coarse levels a step moves the cone far; later levels refine.
#include "map/surface_map.hpp"

#include <algorithm>
#include <cmath>

namespace ism {

double SurfaceMap::relocate_cone(int v) {
  const int x = at_domain_vertex_[v];
  if (x < 0 || !domain_.is_cone(x) || !options_.release_features) return 0.0;
  const std::vector<int> around = neighbours(v);
  const std::size_t m = around.size();

  struct Candidate {
    double gain = 0;
    int w = -1;
    Vec2 pv;
    Ring v_ring;               // v's ring starting after w: w is last
    std::vector<Vec2> w_ring;  // w's neighbours in w's sheet, ccw from v
    std::vector<int> w_vertices;
    WalkEnd w_end;  // layout of w's face in w's sheet
  } best;

  for (std::size_t j = 0; j < m; ++j) {
    const int w = around[j];
    if (at_domain_vertex_[w] >= 0 || pinned_[w]) continue;
    // v's ring unwrapped from the vertex after w, so w comes last and its
    // own one-ring lies in one sheet of the cone's chart.
    Ring vr;
    if (!build_ring(v, vr, around[(j + 1) % m])) continue;
    const std::size_t last = vr.vertices.size() - 1;
    if (vr.vertices[last] != w) continue;
    const WalkEnd w_end{vr.end_face[last], vr.end_layout[last]};
    const Vec2 pw = vr.positions[last];

    // w's one-ring (ccw from v) in w's sheet, by w's own walks.
    std::vector<int> w_vertices;
    std::vector<Vec2> w_ring;
    std::vector<int> w_faces;
    {
      const int f0 = face_after(w, v);
      int f = f0;
      bool ok = f0 >= 0;
      while (ok) {
        const int c = corner_of(f, w);
        const int u = faces_[f][(c + 1) % 3];
        const EdgeWalk& walk = walks_[f][c];
        if (walk.start_face != w_end.face) {
          ok = false;
          break;
        }
        const WalkEnd e = follow(walk, w_end.layout);
        if (at_domain_vertex_[u] < 0 && location_[u].face != e.face) {
          ok = false;
          break;
        }
        w_vertices.push_back(u);
        w_ring.push_back(position_in(u, e.face, e.layout));
        w_faces.push_back(f);
        f = face_after(w, faces_[f][(c + 2) % 3]);
        if (f == f0 || f < 0 || w_faces.size() > vertex_faces_[w].size()) break;
      }
      if (!ok || f != f0) continue;
    }

    // Energy now: v's faces (v at the cone, origin) and w's other faces.
    auto face_with = [&](int f, int a, const Vec2& pa, int b, const Vec2& pb, int c,
                         const Vec2& pc) {
      std::array<Vec2, 3> corner;
      corner[corner_of(f, a)] = pa;
      corner[corner_of(f, b)] = pb;
      corner[corner_of(f, c)] = pc;
      return face_energy(f, corner[0], corner[1], corner[2]);
    };
    double before = 0;
    for (std::size_t i = 0; i <= last; ++i) {
      const int f = vr.faces[i];
      const int a = vr.vertices[i], b = vr.vertices[(i + 1) % (last + 1)];
      // The face (v, w, next) wraps the cut: take `next` from w's sheet.
      const Vec2 pb = i == last ? w_ring.back() : vr.positions[i + 1];
      before += face_with(f, v, Vec2::Zero(), a, vr.positions[i], b, pb);
    }
    // w's faces without v: w_ring[k], w_ring[k+1] for k = 1 .. size-2.
    for (std::size_t k = 1; k + 1 < w_ring.size(); ++k)
      before +=
          face_with(w_faces[k], w, pw, w_vertices[k], w_ring[k], w_vertices[k + 1], w_ring[k + 1]);

    // After: w at the cone (origin), v free inside its new ring: the
    // vertices after w around v, then the origin (w) last.
    std::vector<Vec2> ring(vr.positions.begin(), vr.positions.end());
    ring.back() = Vec2::Zero();
    auto energy_after_v = [&](const Vec2& p) {
      double e = 0;
      for (std::size_t i = 0; i <= last; ++i) {
        const int f = vr.faces[i];
        const int a = vr.vertices[i], b = vr.vertices[(i + 1) % (last + 1)];
        e += face_with(f, v, p, a, ring[i], b, ring[(i + 1) % (last + 1)]);
        if (e == HUGE_VAL) break;
      }
      return e;
    };
    double w_after = 0;
    for (std::size_t k = 1; k + 1 < w_ring.size(); ++k)
      w_after += face_with(w_faces[k], w, Vec2::Zero(), w_vertices[k], w_ring[k], w_vertices[k + 1],
                           w_ring[k + 1]);
    if (!(w_after < HUGE_VAL)) continue;
    std::optional<Vec2> start = kernel_centroid(ring);
    if (!start) continue;
    Vec2 pv = *start;
    const double v_after = minimize_in_kernel(ring, pv, energy_after_v);
    const double gain = before - (v_after + w_after);
    if (gain > best.gain * (1 + 1e-12) && gain > 1e-12 * before) {
      best.gain = gain;
      best.w = w;
      best.pv = pv;
      best.v_ring = vr;
      best.w_ring = w_ring;
      best.w_vertices = w_vertices;
      best.w_end = w_end;
    }
  }
  if (best.w < 0) return 0.0;

  // Commit: walks first (all-or-nothing), then the locations.
  const int w = best.w;
  const Ring& vr = best.v_ring;
  const std::size_t last = vr.vertices.size() - 1;
  std::vector<Vec2> ring(vr.positions.begin(), vr.positions.end());
  ring.back() = Vec2::Zero();
  // v's new location: from the cone, in the wedge holding pv.
  int face = vr.centre_face;
  std::array<Vec2, 3> layout = vr.centre_layout;
  EdgeWalk scratch;
  WalkEnd at;
  if (!wedge_containing(x, face, layout, best.pv) ||
      !trace(face, layout, Vec2::Zero(), best.pv, scratch, at))
    return 0.0;
  best.pv = interior_point(at.layout, best.pv);
  // Walks v -> ring[i] (w is the origin, reached at the cone's corner).
  std::vector<EdgeWalk> from_v(last + 1);
  for (std::size_t i = 0; i <= last; ++i) {
    WalkEnd e;
    if (!trace(at.face, at.layout, best.pv, ring[i], from_v[i], e)) return 0.0;
  }
  // Walks u -> w for w's other neighbours, traced towards the cone in w's sheet.
  std::vector<EdgeWalk> to_w(best.w_vertices.size());
  for (std::size_t k = 1; k < best.w_vertices.size(); ++k) {
    const int u = best.w_vertices[k];
    const int f = face_after(w, u);
    const EdgeWalk& old = walks_[f][corner_of(f, w)];  // w -> u
    const WalkEnd e = follow(old, best.w_end.layout);
    WalkEnd end;
    if (!trace_from(u, e.face, e.layout, Vec2::Zero(), to_w[k], end)) return 0.0;
  }

  // Remember what changes, so that an inconsistent result can be undone.
  std::vector<int> touched = vertex_faces_[v];
  touched.insert(touched.end(), vertex_faces_[w].begin(), vertex_faces_[w].end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  std::vector<std::array<EdgeWalk, 3>> saved_walks;
  for (int f : touched) saved_walks.push_back(walks_[f]);
  const DomainLocation saved_v = location_[v], saved_w = location_[w];
  const int saved_at_v = at_domain_vertex_[v], saved_at_w = at_domain_vertex_[w];

  // Locations: w onto the cone, v free.
  const auto& entry = domain_.fan(x).front();
  at_domain_vertex_[w] = x;
  location_[w].face = entry.face;
  location_[w].bary = Eigen::Vector3d::Zero();
  location_[w].bary[entry.corner] = 1.0;
  pinned_[w] = 1;
  pinned_[v] = 0;
  set_location(v, at.face, at.layout, best.pv);

  // Half-edges around v: v -> ring[i] in face i, ring[i+1] -> v reversed.
  for (std::size_t i = 0; i <= last; ++i) {
    const int f = vr.faces[i], c = vr.corner[i];
    walks_[f][c] = from_v[i];
    walks_[f][(c + 2) % 3] = reversed(from_v[(i + 1) % (last + 1)]);
  }
  // Half-edges between w and its other neighbours.
  for (std::size_t k = 1; k < best.w_vertices.size(); ++k) {
    const int u = best.w_vertices[k];
    const int f = face_after(w, u);  // (w, u, *): holds w -> u
    walks_[f][corner_of(f, w)] = reversed(to_w[k]);
    const int g = face_after(u, w);  // (u, w, *): holds u -> w
    walks_[g][corner_of(g, u)] = to_w[k];
  }
  if (!faces_are_valid(touched)) {
    for (std::size_t i = 0; i < touched.size(); ++i) walks_[touched[i]] = saved_walks[i];
    location_[v] = saved_v, location_[w] = saved_w;
    at_domain_vertex_[v] = saved_at_v, at_domain_vertex_[w] = saved_at_w;
    pinned_[v] = 1, pinned_[w] = 0;
    return 0.0;
  }
  return best.gain;
}

}  // namespace ism
