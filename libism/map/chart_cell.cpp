#include "map/chart_cell.hpp"
#include "map/meta_cut.hpp"   // triangulate_piece
#include "map/meta_mesh.hpp"  // polygon_area

#include <algorithm>
#include <cmath>

namespace ism {

namespace {

/// Mean-value interpolation (Floater 2003) at p of values given at the
/// corners of a polygon around it.
Vec2 mean_value(const std::vector<Vec2>& poly, const std::vector<Vec2>& value, const Vec2& p) {
  const std::size_t n = poly.size();
  std::vector<double> tan_half(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Vec2 a = poly[j] - p, b = poly[(j + 1) % n] - p;
    const double ra = a.norm(), rb = b.norm();
    if (ra < 1e-300) return value[j];
    const double cross = a.x() * b.y() - a.y() * b.x();
    tan_half[j] = cross / (ra * rb + a.dot(b));
  }
  Vec2 sum = Vec2::Zero();
  double total = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double w = (tan_half[(j + n - 1) % n] + tan_half[j]) / (poly[j] - p).norm();
    sum += w * value[j];
    total += w;
  }
  return sum / total;
}

}  // namespace

std::optional<ChartCell> make_chart_cell(std::vector<Vec2> chart, std::vector<Vec2> other) {
  ChartCell cell;
  cell.chart = std::move(chart);
  cell.other = std::move(other);
  if (!cell.chart.empty()) {
    cell.lo = cell.hi = cell.chart[0];
    for (const Vec2& q : cell.chart) cell.lo = cell.lo.cwiseMin(q), cell.hi = cell.hi.cwiseMax(q);
  }
  const std::size_t n = cell.chart.size();
  if (n > 3) {
    const auto& P = cell.chart;
    const auto& Q = cell.other;
    std::size_t k = 2;
    while (k < n && std::abs(orient(P[0], P[1], P[k])) <= 1e-9 * polygon_area(P)) ++k;
    if (k == n) {
      cell.affine = false;
    } else {
      const double scale = std::sqrt(polygon_area(Q));
      for (std::size_t i = 0; i < n && cell.affine; ++i) {
        const Eigen::Vector3d b = barycentric(P[i], P[0], P[1], P[k]);
        cell.affine = (b[0] * Q[0] + b[1] * Q[1] + b[2] * Q[k] - Q[i]).norm() <= 1e-9 * scale;
      }
    }
  }
  if (!cell.affine) {
    MetaPiece both;
    both.corner = {cell.chart, cell.other};
    both.area = {polygon_area(cell.chart), polygon_area(cell.other)};
    PieceTriangulation tri = triangulate_piece(both);
    if (tri.triangles.empty()) return std::nullopt;
    cell.triangles = std::move(tri.triangles);
    cell.tri_chart = std::move(tri.points[0]);
    cell.tri_other = std::move(tri.points[1]);
  }
  return cell;
}

Vec2 cell_image(const ChartCell& cell, const Vec2& p) {
  if (cell.affine) return mean_value(cell.chart, cell.other, p);
  Eigen::Vector3d best = Eigen::Vector3d::Constant(-HUGE_VAL);
  std::array<int, 3> tri = cell.triangles.front();
  for (const auto& t : cell.triangles) {
    const Eigen::Vector3d b =
        barycentric(p, cell.tri_chart[t[0]], cell.tri_chart[t[1]], cell.tri_chart[t[2]]);
    if (b.minCoeff() > best.minCoeff()) best = b, tri = t;
  }
  return best[0] * cell.tri_other[tri[0]] + best[1] * cell.tri_other[tri[1]] +
         best[2] * cell.tri_other[tri[2]];
}

bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

bool inside_cell(const ChartCell& cell, const Vec2& p) {
  const Vec2 &lo = cell.lo, &hi = cell.hi;
  if (p.y() < lo.y() || p.y() >= hi.y()) return false;
  const double margin = 1e-9 * std::max({std::abs(lo.x()), std::abs(hi.x()), hi.x() - lo.x()});
  if (p.x() > hi.x() + margin || p.x() < lo.x() - margin) return false;
  return inside_polygon(cell.chart, p);
}

bool segment_inside_polygon(const std::vector<Vec2>& poly, const Vec2& a, const Vec2& b) {
  const double scale = (b - a).squaredNorm();
  if (!(scale > 0)) return false;
  const double tol = 1e-9 * scale;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &c = poly[j], &d = poly[i];
    const double o1 = orient(a, b, c), o2 = orient(a, b, d);
    const double o3 = orient(c, d, a), o4 = orient(c, d, b);
    const double side_tol = 1e-9 * std::sqrt(scale) * (d - c).norm();
    if (((o1 > tol && o2 < -tol) || (o1 < -tol && o2 > tol)) &&
        ((o3 > side_tol && o4 < -side_tol) || (o3 < -side_tol && o4 > side_tol)))
      return false;  // crosses side cd
    // Corner d on the open segment (not at an end).
    const double u = (d - a).dot(b - a) / scale;
    if (std::abs(o2) <= tol && u > 1e-9 && u < 1 - 1e-9) return false;
  }
  return inside_polygon(poly, 0.5 * (a + b));
}

std::vector<CellKink> cell_kinks(const ChartCell& cell, const Vec2& A, const Vec2& B, const Vec2& a,
                                 const Vec2& b, KinkRule rule) {
  std::vector<CellKink> kinks;
  if (cell.affine) return kinks;
  if (rule == KinkRule::where_needed && segment_inside_polygon(cell.other, a, b)) return kinks;
  const double length2 = (B - A).squaredNorm();
  const int n = int(cell.chart.size());
  for (const auto& tri : cell.triangles)
    for (int k = 0; k < 3; ++k) {
      const int c0 = tri[k], c1 = tri[(k + 1) % 3];
      // Each diagonal once (from its smaller end); the polygon's sides are
      // not diagonals.
      const bool side = c0 < n && c1 < n && ((c1 - c0 + n) % n == 1 || (c0 - c1 + n) % n == 1);
      if (c0 > c1 || side) continue;
      const Vec2 &C = cell.tri_chart[c0], &D = cell.tri_chart[c1];
      const double o1 = orient(A, B, C), o2 = orient(A, B, D);
      const double o3 = orient(C, D, A), o4 = orient(C, D, B);
      if (!(o1 * o2 < 0 && o3 * o4 < 0)) continue;
      const double lambda = o1 / (o1 - o2);
      const Vec2 x = C + lambda * (D - C);
      kinks.push_back({(x - A).dot(B - A) / length2, x,
                       cell.tri_other[c0] + lambda * (cell.tri_other[c1] - cell.tri_other[c0])});
    }
  return kinks;
}

}  // namespace ism
