#include "map/sampler.hpp"

#include "map/overlay.hpp"

#include <algorithm>
#include <cmath>

namespace ism {

MapSampler::MapSampler(const SurfaceMap& map) : map_(map) {
  const DomainGeometry& domain = map.domain();
  grids_.resize(domain.n_faces());
  for (std::size_t t = 0; t < map.n_faces(); ++t) {
    SurfaceMap::FaceChart chart;
    if (!map.face_chart(int(t), chart)) continue;
    for_each_piece(map, int(t), [&](const OverlayPiece& piece) {
      // Rigid motion from the chart to the M¹ face's canonical frame.
      const auto& canonical = domain.layout(piece.domain_face);
      const Vec2 u = piece.domain_layout[1] - piece.domain_layout[0];
      const Vec2 w = canonical[1] - canonical[0];
      const double angle = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));
      Eigen::Matrix2d r;
      r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
      const Vec2 shift = canonical[0] - r * piece.domain_layout[0];
      Entry e{int(t), {}};
      for (int k = 0; k < 3; ++k) e.triangle[k] = r * chart.corner[k] + shift;
      grids_[piece.domain_face].entries.push_back(e);
    });
  }
  for (std::size_t f = 0; f < grids_.size(); ++f) {
    Grid& g = grids_[f];
    const auto& l = domain.layout(int(f));
    g.lo = l[0].cwiseMin(l[1]).cwiseMin(l[2]);
    g.hi = l[0].cwiseMax(l[1]).cwiseMax(l[2]);
    g.n = std::max(1, int(std::sqrt(double(g.entries.size()) / 2.0)));
    g.cells.assign(std::size_t(g.n) * g.n, {});
    const Vec2 size = (g.hi - g.lo) / g.n;
    for (std::size_t i = 0; i < g.entries.size(); ++i) {
      const auto& tri = g.entries[i].triangle;
      const Vec2 lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]);
      const Vec2 hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
      const int x0 = std::clamp(int(std::floor((lo.x() - g.lo.x()) / size.x())), 0, g.n - 1);
      const int x1 = std::clamp(int(std::floor((hi.x() - g.lo.x()) / size.x())), 0, g.n - 1);
      const int y0 = std::clamp(int(std::floor((lo.y() - g.lo.y()) / size.y())), 0, g.n - 1);
      const int y1 = std::clamp(int(std::floor((hi.y() - g.lo.y()) / size.y())), 0, g.n - 1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) g.cells[std::size_t(y) * g.n + x].push_back(int(i));
    }
  }
}

std::optional<SurfacePoint> MapSampler::surface_point(int domain_face,
                                                      const Eigen::Vector3d& bary) const {
  const Grid& g = grids_[domain_face];
  const auto& l = map_.domain().layout(domain_face);
  const Vec2 q = from_barycentric(bary, l);
  const Vec2 size = (g.hi - g.lo) / g.n;
  const int x = std::clamp(int(std::floor((q.x() - g.lo.x()) / size.x())), 0, g.n - 1);
  const int y = std::clamp(int(std::floor((q.y() - g.lo.y()) / size.y())), 0, g.n - 1);
  // The triangle that holds q best (largest smallest barycentric), so that
  // points on shared edges still find a face.
  int best = -1;
  Eigen::Vector3d best_bary;
  double best_min = -HUGE_VAL;
  for (int i : g.cells[std::size_t(y) * g.n + x]) {
    const auto& tri = g.entries[i].triangle;
    const Eigen::Vector3d b = barycentric(q, tri[0], tri[1], tri[2]);
    if (b.minCoeff() > best_min) best_min = b.minCoeff(), best = i, best_bary = b;
  }
  if (best < 0 || best_min < -1e-6) return std::nullopt;
  best_bary = best_bary.cwiseMax(0.0);
  best_bary /= best_bary.sum();
  const int t = g.entries[best].face;
  const Triangle& tri = map_.faces()[t];
  const auto& p = map_.positions();
  return SurfacePoint{
      t, best_bary, best_bary[0] * p[tri[0]] + best_bary[1] * p[tri[1]] + best_bary[2] * p[tri[2]]};
}

std::optional<DomainLocation> MapSampler::domain_point(int surface_face,
                                                       const Eigen::Vector3d& bary) const {
  std::optional<DomainLocation> found;
  SurfaceMap::FaceChart chart;
  if (!map_.face_chart(surface_face, chart)) return found;
  const Vec2 q = from_barycentric(bary, chart.corner);
  for_each_piece(map_, surface_face, [&](const OverlayPiece& piece) {
    const auto& l = piece.domain_layout;
    const Eigen::Vector3d b = barycentric(q, l[0], l[1], l[2]);
    if (!found && b.minCoeff() >= -1e-9) {
      Eigen::Vector3d c = b.cwiseMax(0.0);
      found = DomainLocation{piece.domain_face, c / c.sum()};
    }
  });
  return found;
}

}  // namespace ism
