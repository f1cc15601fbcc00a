// validate() and the stretch measures: both read the overlay's pieces.
#include "map/overlay.hpp"
#include "map/surface_map.hpp"
#include "mesh/edge_key.hpp"
#include "metrics/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <tuple>
#include <vector>

namespace ism {

std::optional<std::string> SurfaceMap::validate() const {
  const double total_domain = domain_.total_area();
  std::vector<double> covered(domain_.n_faces(), 0.0);
  double total_chart = 0.0;
  struct Crossing {
    std::uint64_t edge;  // the M¹ edge, undirected_edge_key
    double along;        // from its smaller vertex
    int half_edge;       // 3 t + k
    bool operator<(const Crossing& o) const {
      return std::tie(edge, along, half_edge) < std::tie(o.edge, o.along, o.half_edge);
    }
  };
  std::vector<Crossing> crossings;
  FaceChart chart;
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    auto name = [t] { return "face " + std::to_string(t); };
    if (!face_chart(int(t), chart)) return name() + ": its walks over M¹ do not close";
    const double area = 0.5 * orient(chart.corner[0], chart.corner[1], chart.corner[2]);
    if (!(area > 0))
      return name() + ": flipped or degenerate image (area " + std::to_string(area) + ")";
    total_chart += area;
    double pieces = 0.0;
    const bool ok = for_each_piece(*this, int(t), [&](const OverlayPiece& p) {
      pieces += p.area;
      covered[p.domain_face] += p.area;
    });
    if (!ok) return name() + ": its image is not in a flat region of M¹";
    if (std::abs(pieces - area) > 1e-9 * area + 1e-15 * total_domain)
      return name() + ": pieces cover " + std::to_string(pieces / area) + " of it";

    // Crossings of M¹ edges, recorded from M²'s side with the position along
    // the M¹ edge, to check their order afterwards.
    for (int k = 0; k < 3; ++k) {
      const EdgeWalk& w = walks_[t][k];
      int face = w.start_face;
      std::array<Vec2, 3> layout = chart.walk_layout[k];
      const Vec2 from = chart.corner[k], to = chart.corner[(k + 1) % 3];
      for (int i = 0; i < w.count; ++i) {
        const int e = w.exit(i);
        const Vec2 &a = layout[e], &b = layout[(e + 1) % 3];
        // Intersection of from->to with the M¹ edge a->b: parameter s on a->b.
        const double da = orient(from, to, a), db = orient(from, to, b);
        if (da * db > 0) return name() + ": a walk crosses an M¹ edge its segment misses";
        const double s = da / (da - db);
        const int u = domain_.mesh().triangles[face][e],
                  v = domain_.mesh().triangles[face][(e + 1) % 3];
        // Store by the undirected M¹ edge, s measured from its smaller vertex.
        const double along = u < v ? s : 1 - s;
        if (faces_[t][k] < faces_[t][(k + 1) % 3])
          crossings.push_back({undirected_edge_key(u, v), along, int(t) * 3 + k});
        layout = domain_.unfold(face, layout, e);
        face = domain_.neighbour(face, e);
      }
    }
  }
  if (std::abs(total_chart - total_domain) > 1e-9 * total_domain)
    return "the images of the faces cover " + std::to_string(total_chart / total_domain) +
           " of M¹ (not a bijection)";
  for (std::size_t f = 0; f < domain_.n_faces(); ++f)
    if (std::abs(covered[f] - domain_.face_area(int(f))) > 1e-9 * domain_.face_area(int(f)))
      return "M¹ face " + std::to_string(f) + " is covered " +
             std::to_string(covered[f] / domain_.face_area(int(f))) + " times";
  // Each M¹ edge's crossings in order along it (edges in key order).
  std::sort(crossings.begin(), crossings.end());
  for (std::size_t i = 1; i < crossings.size(); ++i)
    if (crossings[i].edge == crossings[i - 1].edge &&
        crossings[i].along - crossings[i - 1].along <= 0)
      return "two M² edges cross M¹ edge " + std::to_string(crossings[i].edge >> 32) + "-" +
             std::to_string(crossings[i].edge & 0xffffffffu) + " at the same point";
  // Both half-edges of an M² edge cross the same M¹ edges in opposite order.
  // (Half-edges in key order; of a repeated one the last face's walk.)
  std::vector<std::pair<std::uint64_t, const EdgeWalk*>> by_halfedge;
  by_halfedge.reserve(3 * faces_.size());
  for (std::size_t t = 0; t < faces_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      by_halfedge.push_back(
          {directed_edge_key(faces_[t][k], faces_[t][(k + 1) % 3]), &walks_[t][k]});
  std::stable_sort(by_halfedge.begin(), by_halfedge.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  auto last_of = [&](std::uint64_t key) -> const EdgeWalk* {
    const auto end = std::upper_bound(by_halfedge.begin(), by_halfedge.end(), key,
                                      [](std::uint64_t k, const auto& e) { return k < e.first; });
    return end != by_halfedge.begin() && std::prev(end)->first == key ? std::prev(end)->second
                                                                      : nullptr;
  };
  for (std::size_t i = 0; i < by_halfedge.size(); ++i) {
    if (i + 1 < by_halfedge.size() && by_halfedge[i + 1].first == by_halfedge[i].first)
      continue;  // (the last of a repeated half-edge stands for it)
    const std::pair<int, int> he{int(by_halfedge[i].first >> 32),
                                 int(by_halfedge[i].first & 0xffffffffu)};
    const EdgeWalk* w = by_halfedge[i].second;
    const EdgeWalk* twin_walk = last_of(directed_edge_key(he.second, he.first));
    if (!twin_walk) return "M² is not closed";
    if (he.first > he.second) continue;
    if (w->count != twin_walk->count)
      return "edge " + std::to_string(he.first) + "-" + std::to_string(he.second) +
             ": its half-edges cross different numbers of M¹ edges";
    if (w->count > 0) {
      const EdgeWalk r = reversed(*w);
      if (r.start_face != twin_walk->start_face || r.exits != twin_walk->exits)
        return "edge " + std::to_string(he.first) + "-" + std::to_string(he.second) +
               ": its half-edges cross different M¹ edges";
    }
  }
  return std::nullopt;
}

MapMeasures SurfaceMap::measures(const std::vector<char>& counted) const {
  std::vector<StretchPiece> pieces;
  pieces.reserve(faces_.size());
  FaceChart chart;
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    if (!counted.empty() && !counted[t]) continue;
    if (!face_chart(int(t), chart)) return {};
    // One affine map per M² face: its overlay pieces all share this
    // Jacobian, so the face stands for them with the summed areas.
    const Triangle& tri = faces_[t];
    const auto& c = chart.corner;
    pieces.push_back({{(c[1] - c[2]).norm(), (c[2] - c[0]).norm(), (c[0] - c[1]).norm()},
                      {(positions_[tri[1]] - positions_[tri[2]]).norm(),
                       (positions_[tri[2]] - positions_[tri[0]]).norm(),
                       (positions_[tri[0]] - positions_[tri[1]]).norm()}});
  }
  const SymmetricStretch s = symmetric_stretch(pieces);
  return {s.efficiency, s.forward_efficiency, s.backward_efficiency};
}

}  // namespace ism
