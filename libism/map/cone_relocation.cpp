// Releasing cone points of M¹. A cone (angle sum ≠ 2π) must sit on a vertex
// of M² for every one-ring to stay flat; it is released by moving it to a
// neighbouring vertex w when that lowers the symmetric energy: w goes onto
// the cone, the old vertex v becomes free and is optimised in its new
// one-ring. At coarse levels a step moves the cone far; later levels refine.
#include "map/surface_map.hpp"
#include "mesh/rings.hpp"

#include <algorithm>
#include <cmath>

namespace ism {

double SurfaceMap::relocate_cone(int v) {
  if (options_.cone_relaxation_rings > 0)
    return relocate_cone_relaxed(v, options_.cone_relaxation_rings, 2);
  return move_cone(v, -1).value_or(0.0);
}

std::optional<double> SurfaceMap::move_cone(int v, int to,
                                            std::vector<std::pair<double, int>>* estimates) {
  const int x = at_domain_vertex_[v];
  if (x < 0 || !domain_.is_cone(x) || is_fixed(x) || !options_.release_features)
    return std::nullopt;
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
  // With a forced target, any gain is taken (the caller relaxes and judges).
  if (to >= 0) best.gain = -HUGE_VAL;

  // Work lists, their storage reused from candidate to candidate.
  Ring candidate;
  std::vector<std::array<int, 3>> slots;
  std::vector<int> w_vertices, w_faces;
  std::vector<Vec2> w_ring, ring;
  for (std::size_t j = 0; j < m; ++j) {
    const int w = around[j];
    if (at_domain_vertex_[w] >= 0 || pinned_[w] || (to >= 0 && w != to)) continue;
    // v's ring unwrapped from the vertex after w, so w comes last and its
    // own one-ring lies in one sheet of the cone's chart.
    if (!build_ring(v, candidate, around[(j + 1) % m])) continue;
    const std::size_t last = candidate.vertices.size() - 1;
    if (candidate.vertices[last] != w) continue;
    const WalkEnd w_end{candidate.end_face[last], candidate.end_layout[last]};
    const Vec2 pw = candidate.positions[last];

    // w's one-ring (ccw from v) in w's sheet, by w's own walks.
    w_vertices.clear(), w_ring.clear(), w_faces.clear();
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
    // v's faces: the corners of v, a and b in face i and its terms
    // (build_ring's) are the same wherever v goes; face_with's value, bit
    // for bit, for every point the search below tries.
    slots.clear();
    for (std::size_t i = 0; i <= last; ++i) {
      const int f = candidate.faces[i];
      slots.push_back({corner_of(f, v), corner_of(f, candidate.vertices[i]),
                       corner_of(f, candidate.vertices[(i + 1) % (last + 1)])});
    }
    auto v_face = [&](std::size_t i, const Vec2& pv, const Vec2& pa, const Vec2& pb) {
      std::array<Vec2, 3> corner;
      corner[slots[i][0]] = pv;
      corner[slots[i][1]] = pa;
      corner[slots[i][2]] = pb;
      return face_energy(candidate.terms[i], corner[0], corner[1], corner[2]);
    };
    double before = 0;
    for (std::size_t i = 0; i <= last; ++i) {
      // The face (v, w, next) wraps the cut: take `next` from w's sheet.
      const Vec2 pb = i == last ? w_ring.back() : candidate.positions[i + 1];
      before += v_face(i, Vec2::Zero(), candidate.positions[i], pb);
    }
    // w's faces without v: w_ring[k], w_ring[k+1] for k = 1 .. size-2.
    for (std::size_t k = 1; k + 1 < w_ring.size(); ++k)
      before +=
          face_with(w_faces[k], w, pw, w_vertices[k], w_ring[k], w_vertices[k + 1], w_ring[k + 1]);

    // After: w at the cone (origin), v free inside its new ring: the
    // vertices after w around v, then the origin (w) last.
    ring.assign(candidate.positions.begin(), candidate.positions.end());
    ring.back() = Vec2::Zero();
    auto energy_after_v = [&](const Vec2& p) {
      double e = 0;
      for (std::size_t i = 0; i <= last; ++i) {
        e += v_face(i, p, ring[i], ring[(i + 1) % (last + 1)]);
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
    if (estimates) {
      estimates->emplace_back(gain, w);
      continue;
    }
    if (to >= 0 ? gain > best.gain : gain > best.gain * (1 + 1e-12) && gain > 1e-12 * before) {
      best.gain = gain;
      best.w = w;
      best.pv = pv;
      best.v_ring = candidate;
      best.w_ring = w_ring;
      best.w_vertices = w_vertices;
      best.w_end = w_end;
    }
  }
  if (best.w < 0) return std::nullopt;

  // Commit: walks first (all-or-nothing), then the locations.
  const int w = best.w;
  const Ring& vr = best.v_ring;
  const std::size_t last = vr.vertices.size() - 1;
  ring.assign(vr.positions.begin(), vr.positions.end());
  ring.back() = Vec2::Zero();
  // v's new location: from the cone, in the wedge holding pv.
  int face = vr.centre_face;
  std::array<Vec2, 3> layout = vr.centre_layout;
  EdgeWalk scratch;
  WalkEnd at;
  if (!wedge_containing(x, face, layout, best.pv) ||
      !trace(face, layout, Vec2::Zero(), best.pv, scratch, at))
    return std::nullopt;
  best.pv = interior_point(at.layout, best.pv);
  // Walks v -> ring[i] (w is the origin, reached at the cone's corner).
  std::vector<EdgeWalk> from_v(last + 1);
  for (std::size_t i = 0; i <= last; ++i) {
    WalkEnd e;
    if (!trace(at.face, at.layout, best.pv, ring[i], from_v[i], e)) return std::nullopt;
  }
  // Walks u -> w for w's other neighbours, traced towards the cone in w's sheet.
  std::vector<EdgeWalk> to_w(best.w_vertices.size());
  for (std::size_t k = 1; k < best.w_vertices.size(); ++k) {
    const int u = best.w_vertices[k];
    const int f = face_after(w, u);
    const EdgeWalk& old = walks_[f][corner_of(f, w)];  // w -> u
    const WalkEnd e = follow(old, best.w_end.layout);
    WalkEnd end;
    if (!trace_from(u, e.face, e.layout, Vec2::Zero(), to_w[k], end)) return std::nullopt;
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
    return std::nullopt;
  }
  return best.gain;
}

// ------------------------------------------------- relocation with relaxation

std::vector<int> SurfaceMap::rings_around(int v, int rings) const {
  return ism::rings_around(v, rings, [this](int u) { return neighbours(u); });
}

SurfaceMap::RegionState SurfaceMap::save_region(const std::vector<int>& vertices) const {
  RegionState state;
  state.vertices = vertices;
  for (int u : vertices) {
    state.faces.insert(state.faces.end(), vertex_faces_[u].begin(), vertex_faces_[u].end());
    state.locations.push_back(location_[u]);
    state.at_domain_vertex.push_back(at_domain_vertex_[u]);
    state.pinned.push_back(pinned_[u]);
  }
  std::sort(state.faces.begin(), state.faces.end());
  state.faces.erase(std::unique(state.faces.begin(), state.faces.end()), state.faces.end());
  for (int f : state.faces) state.walks.push_back(walks_[f]);
  state.optimizations = optimizations_;
  state.single_face_rings = single_face_rings_;
  return state;
}

void SurfaceMap::restore_region(const RegionState& state) {
  for (std::size_t i = 0; i < state.vertices.size(); ++i) {
    const int u = state.vertices[i];
    location_[u] = state.locations[i];
    at_domain_vertex_[u] = state.at_domain_vertex[i];
    pinned_[u] = state.pinned[i];
  }
  for (std::size_t i = 0; i < state.faces.size(); ++i) walks_[state.faces[i]] = state.walks[i];
  optimizations_ = state.optimizations;
  single_face_rings_ = state.single_face_rings;
}

double SurfaceMap::relocate_cone_relaxed(int v, int rings, int passes) {
  const int x = at_domain_vertex_[v];
  if (x < 0 || !domain_.is_cone(x) || is_fixed(x) || !options_.release_features || rings < 1)
    return 0.0;
  // Only vertices of the region move, so only the faces around them change.
  const RegionState saved = save_region(rings_around(v, rings));
  const double before = faces_energy(saved.faces);
  auto move_and_relax = [&](int w) {
    if (!move_cone(v, w)) return HUGE_VAL;
    for (int pass = 0; pass < passes; ++pass)
      for (int u : saved.vertices) optimize_vertex(u);
    return faces_energy(saved.faces);
  };
  // Only the most promising moves by the unrelaxed estimate are relaxed.
  std::vector<std::pair<double, int>> estimates;
  move_cone(v, -1, &estimates);
  const std::size_t tried = std::min<std::size_t>(estimates.size(), 2);
  std::partial_sort(estimates.begin(), estimates.begin() + tried, estimates.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  double best = before;
  std::optional<RegionState> best_state;
  for (std::size_t i = 0; i < tried; ++i) {
    const double after = move_and_relax(estimates[i].second);
    if (after < best * (1 - 1e-12)) {
      best = after;
      best_state = save_region(saved.vertices);
    }
    restore_region(saved);
  }
  if (!best_state) return 0.0;
  restore_region(*best_state);
  return before - best;
}

}  // namespace ism
