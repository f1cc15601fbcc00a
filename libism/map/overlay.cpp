#include "map/overlay.hpp"

#include <algorithm>
#include <cmath>

namespace ism {

namespace {

/// One step of the clipping: the part of `in` left of (or on) a -> b.
void clip_by_line(const std::vector<Vec2>& in, const Vec2& a, const Vec2& b,
                  std::vector<Vec2>& out) {
  out.clear();
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Vec2& p = in[i];
    const Vec2& q = in[(i + 1) % in.size()];
    const double sp = orient(a, b, p), sq = orient(a, b, q);
    if (sp >= 0) out.push_back(p);
    if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
  }
}

}  // namespace

std::vector<Vec2> clip_to_triangle(std::vector<Vec2> polygon, const std::array<Vec2, 3>& triangle) {
  std::vector<Vec2> out;
  for (int k = 0; k < 3 && !polygon.empty(); ++k) {
    clip_by_line(polygon, triangle[k], triangle[(k + 1) % 3], out);
    std::swap(polygon, out);
  }
  return polygon;
}

double clipped_area(const std::vector<Vec2>& polygon, const Vec2& lo, const Vec2& hi,
                    const std::array<Vec2, 3>& triangle) {
  const Vec2 t_lo = triangle[0].cwiseMin(triangle[1]).cwiseMin(triangle[2]);
  const Vec2 t_hi = triangle[0].cwiseMax(triangle[1]).cwiseMax(triangle[2]);
  const double size = std::max({lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff(),
                                t_lo.cwiseAbs().maxCoeff(), t_hi.cwiseAbs().maxCoeff()});
  if (boxes_apart(lo, hi, t_lo, t_hi, 1e-6 * size)) return 0.0;
  thread_local std::vector<Vec2> one, two;
  clip_by_line(polygon, triangle[0], triangle[1], one);
  if (one.empty()) return polygon_area(one);
  clip_by_line(one, triangle[1], triangle[2], two);
  if (two.empty()) return polygon_area(two);
  clip_by_line(two, triangle[2], triangle[0], one);
  return polygon_area(one);
}

bool for_each_piece(const SurfaceMap& map, int t,
                    const std::function<void(const OverlayPiece&)>& visit) {
  SurfaceMap::FaceChart chart;
  if (!map.face_chart(t, chart)) return false;
  const DomainGeometry& domain = map.domain();
  const std::vector<Vec2> triangle(chart.corner.begin(), chart.corner.end());
  const double area = std::abs(polygon_area(triangle));
  const double tiny = 1e-14 * std::max(area, domain.total_area() * 1e-12);
  // Breadth-first over the M¹ faces the triangle covers, unfolded into its
  // chart; a face is identified by its id and the position of its layout.
  std::vector<std::pair<int, std::array<Vec2, 3>>> queue{{chart.start_face, chart.start_layout}};
  // Copies of one M¹ face are told apart by where their layout sits.
  const double same = 1e-6 * std::sqrt(domain.total_area());
  std::vector<std::pair<int, Vec2>> seen;
  auto first_visit = [&](int f, const std::array<Vec2, 3>& l) {
    const Vec2 c = (l[0] + l[1] + l[2]) / 3.0;
    for (const auto& [g, d] : seen)
      if (g == f && (d - c).norm() < same) return false;
    seen.push_back({f, c});
    return true;
  };
  first_visit(chart.start_face, chart.start_layout);
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const auto [f, layout] = queue[i];
    OverlayPiece piece{f, layout, clip_to_triangle(triangle, layout), 0.0};
    piece.area = polygon_area(piece.polygon);
    if (piece.area <= tiny && i > 0) continue;  // touches only: do not spread from here
    if (piece.area > tiny) visit(piece);
    for (int k = 0; k < 3; ++k) {
      const auto next = domain.unfold(f, layout, k);
      const int g = domain.neighbour(f, k);
      if (first_visit(g, next)) queue.push_back({g, next});
    }
    if (queue.size() > 4 * domain.n_faces() + 64) return false;  // runaway: not a flat region
  }
  return true;
}

}  // namespace ism
