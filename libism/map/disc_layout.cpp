// InterSurfaceMap's discs of side 1 over one face of side 0, or over two
// faces across the edge they share, for the local re-embedding of several
// vertices at once (paper §5.1): laid out in that face's own layout (the
// second face unfolded across the edge, an isometry), where the map is a
// plain 2D problem, and moved back through the one transaction (apply)
// with the disc's edges redrawn straight in that chart.
#include "map/inter_surface_map.hpp"
#include "map/inter_surface_map_impl.hpp"
#include "mesh/rings.hpp"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace ism {

namespace {

// Adds face f of side 0 to the at most two faces a disc lies over; false
// (faces unchanged) where it would be a third, or f < 0 (on a vertex).
bool within_two(std::array<int, 2>& faces, int f) {
  if (f < 0) return false;
  if (faces[0] < 0 || f == faces[0]) return faces[0] = f, true;
  if (faces[1] < 0 || f == faces[1]) return faces[1] = f, true;
  return false;
}

}  // namespace

std::vector<int> InterSurfaceMap::rings_around(int side, int v, int rings) const {
  return ism::rings_around(v, rings, [this, side](int u) { return neighbours(side, u); });
}

std::vector<int> InterSurfaceMap::disc_around(int v, int rings) const {
  const MetaSide& S = meta_.side[1];
  std::array<int, 2> faces{-1, -1};
  return ism::rings_around(
      v, rings, [this](int u) { return neighbours(1, u); },
      [&](int u) { return within_two(faces, S.location[u].face); });
}

std::optional<InterSurfaceMap::DiscChart> InterSurfaceMap::disc_chart(
    const std::vector<int>& faces) const {
  const MetaSide& S = meta_.side[1];
  const MetaSide& T = meta_.side[0];
  DiscChart chart;
  int crossed = -1;  // the one edge of side 0 the disc's edges cross
  for (int f : faces) {
    if (!index_[1].residents[f].empty()) return std::nullopt;
    for (int k = 0; k < 3; ++k) {
      if (!within_two(chart.face, S.location[S.faces[f][k]].face)) return std::nullopt;
      const auto& list = S.crossings[S.face_edges[f][k]];
      if (list.size() > 1 || (list.size() == 1 && list[0].is_kink())) return std::nullopt;
      if (list.size() == 1) {
        if (crossed >= 0 && list[0].edge != crossed) return std::nullopt;
        crossed = list[0].edge;
      }
    }
  }
  if (chart.face[0] < 0) return std::nullopt;
  chart.layout[0] = meta_face_layout(T.lengths[chart.face[0]]);
  if (chart.face[1] < 0) return crossed < 0 ? std::optional<DiscChart>(chart) : std::nullopt;
  // The second face unfolded across the edge both share, which must be
  // the one the disc's edges cross.
  const auto& fe0 = T.face_edges[chart.face[0]];
  const int j = fe0[0] == crossed ? 0 : fe0[1] == crossed ? 1 : fe0[2] == crossed ? 2 : -1;
  if (crossed < 0 || j < 0) return std::nullopt;
  const auto& ef = index_[0].edge_faces[crossed];
  if (!((ef[0] == chart.face[0] && ef[1] == chart.face[1]) ||
        (ef[1] == chart.face[0] && ef[0] == chart.face[1])))
    return std::nullopt;
  const int a = T.faces[chart.face[0]][j], b = T.faces[chart.face[0]][(j + 1) % 3];
  const Vec2 pa = chart.layout[0][j], pb = chart.layout[0][(j + 1) % 3];
  const Triangle& g = T.faces[chart.face[1]];
  const int ia = g[0] == a ? 0 : g[1] == a ? 1 : 2, ib = g[0] == b ? 0 : g[1] == b ? 1 : 2;
  const auto across = layout_across(meta_face_layout(T.lengths[chart.face[1]]), ia, ib, pa, pb);
  if (!across) return std::nullopt;
  chart.layout[1] = *across;
  chart.edge = crossed;
  const bool forward = T.edges[crossed][0] == a;
  chart.edge_from = forward ? pa : pb;
  chart.edge_to = forward ? pb : pa;
  return chart;
}

std::optional<double> InterSurfaceMap::DiscChart::cross(const Vec2& p, const Vec2& q,
                                                        double clearance) const {
  // Where p -> q crosses the shared edge (its parameter along it), if it
  // does clear of both segments' ends.
  const Vec2 &a = edge_from, &b = edge_to;
  const double o1 = orient(p, q, a), o2 = orient(p, q, b), o3 = orient(a, b, p),
               o4 = orient(a, b, q);
  if (!((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0))) return std::nullopt;
  if (!((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return std::nullopt;
  const double lambda = o3 / (o3 - o4), mu = o1 / (o1 - o2);
  if (lambda < clearance || lambda > 1 - clearance || mu < clearance || mu > 1 - clearance)
    return std::nullopt;
  return mu;
}

std::optional<DiscLayout> InterSurfaceMap::disc_layout(const std::vector<int>& vertices) const {
  const MetaSide& S = meta_.side[1];
  std::vector<int> faces;
  for (int v : vertices)
    faces.insert(faces.end(), index_[1].vertex_faces[v].begin(), index_[1].vertex_faces[v].end());
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  if (faces.empty()) return std::nullopt;
  const auto chart = disc_chart(faces);
  if (!chart) return std::nullopt;
  const std::unordered_set<int> given(vertices.begin(), vertices.end());
  DiscLayout disc;
  std::unordered_map<int, int> local;
  for (int f : faces) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const int u = S.faces[f][k];
      const auto [it, added] = local.emplace(u, int(disc.vertex.size()));
      if (added) {
        const MetaLocation& loc = S.location[u];
        disc.vertex.push_back(u);
        disc.free.push_back(given.count(u) && !pinned_[1][u]);
        disc.position.push_back(
            from_barycentric(loc.bary, chart->layout[loc.face == chart->face[0] ? 0 : 1]));
      }
      t[k] = it->second;
    }
    disc.face.push_back(f);
    disc.local.push_back(t);
  }
  // An edge between fixed corners keeps its crossing: it must be where the
  // chart's straight segment crosses (else its faces are not one affine
  // map each in the chart).
  for (std::size_t i = 0; i < disc.face.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = disc.local[i][k], b = disc.local[i][(k + 1) % 3];
      const auto& list = S.crossings[S.face_edges[disc.face[i]][k]];
      if (disc.free[a] || disc.free[b] || list.empty()) continue;
      const bool forward = S.edges[S.face_edges[disc.face[i]][k]][0] == disc.vertex[a];
      const Vec2 &p = disc.position[forward ? a : b], &q = disc.position[forward ? b : a];
      const Vec2 at = p + list[0].here * (q - p);
      const Vec2 on = chart->edge_from + list[0].there * (chart->edge_to - chart->edge_from);
      if ((at - on).norm() > 1e-9 * (q - p).norm()) return std::nullopt;
    }
  return disc;
}

double InterSurfaceMap::set_disc_layout(const DiscLayout& disc) {
  const MetaSide& S = meta_.side[1];
  const auto chart = disc_chart(disc.face);
  if (!chart) return 0.0;
  const double clearance = Layout{}.clearance;
  Proposal proposal;
  std::vector<int> in(disc.vertex.size());  // face of side 0 holding each vertex
  for (std::size_t u = 0; u < disc.vertex.size(); ++u) {
    in[u] = S.location[disc.vertex[u]].face;
    if (!disc.free[u]) continue;
    in[u] = -1;
    for (int k = 0; k < 2 && in[u] < 0 && chart->face[k] >= 0; ++k) {
      const auto& L = chart->layout[k];
      const Eigen::Vector3d b = barycentric(disc.position[u], L[0], L[1], L[2]);
      if (!(b.minCoeff() >= clearance)) continue;  // (NaN too)
      proposal.locations[0].push_back(
          {disc.vertex[u], MetaLocation{-1, chart->face[k], b / b.sum()}});
      in[u] = chart->face[k];
    }
    if (in[u] < 0) return 0.0;
  }
  if (proposal.locations[0].empty()) return 0.0;
  if (chart->face[1] >= 0) {
    // Every edge with a free end drawn straight in the chart; the shared
    // edge's crossings with them replaced.
    std::vector<MetaCrossing> shared = meta_.side[0].crossings[chart->edge];
    std::vector<MetaCrossing> fresh;
    std::unordered_set<int> redrawn;
    for (std::size_t i = 0; i < disc.face.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int a = disc.local[i][k], b = disc.local[i][(k + 1) % 3];
        const int e = S.face_edges[disc.face[i]][k];
        if ((!disc.free[a] && !disc.free[b]) || !redrawn.insert(e).second) continue;
        const bool forward = S.edges[e][0] == disc.vertex[a];
        const Vec2 &p = disc.position[forward ? a : b], &q = disc.position[forward ? b : a];
        std::vector<MetaCrossing> list;
        if (in[a] != in[b]) {  // (over one face: no crossing, the face convex)
          const auto mu = chart->cross(p, q, clearance);
          if (!mu) return 0.0;
          const Vec2 at = chart->edge_from + *mu * (chart->edge_to - chart->edge_from);
          const double here = (at - p).dot(q - p) / (q - p).squaredNorm();
          list.push_back({chart->edge, here, *mu});
          fresh.push_back({e, *mu, here});
        }
        proposal.lists.push_back({e, std::move(list)});
      }
    std::erase_if(shared, [&](const MetaCrossing& c) { return redrawn.count(c.edge) > 0; });
    shared.insert(shared.end(), fresh.begin(), fresh.end());
    std::sort(shared.begin(), shared.end(),
              [](const MetaCrossing& x, const MetaCrossing& y) { return x.here < y.here; });
    proposal.other_lists.push_back({chart->edge, std::move(shared)});
  }
  const double before = faces_energy(1, disc.face);
  if (!(before < HUGE_VAL)) return 0.0;
  return apply(1, disc.face, proposal, before, true).value_or(0.0);
}

}  // namespace ism
