#include "metrics/metrics.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <stdexcept>

namespace ism {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The piece seen from one side: the map direction is `from` -> `to`.
struct Oriented {
  const TriangleLengths& from;
  const TriangleLengths& to;
};

Oriented orient(const StretchPiece& piece, bool inverse) {
  return inverse ? Oriented{piece.range, piece.domain} : Oriented{piece.domain, piece.range};
}

/// one_way_stretch of the map (inverse ? M -> D : D -> M), without copying the pieces.
OneWayStretch one_way_stretch_impl(std::span<const StretchPiece> pieces, bool inverse) {
  if (pieces.empty()) throw std::invalid_argument("stretch: no pieces given");
  double area_from = 0.0, area_to = 0.0;
  double weighted_sigma2 = 0.0;  // Σ A_to(T) σ²(T)
  double max_stretch = 0.0;      // max Γ(T)
  for (const StretchPiece& piece : pieces) {
    const Oriented side = orient(piece, inverse);
    const SingularValues s = stretch_singular_values(side.from, side.to);
    const double a_to = triangle_area(side.to);
    area_from += triangle_area(side.from);
    area_to += a_to;
    max_stretch = std::max(max_stretch, s.max);
    // An infinite stretch stays infinite even on a zero-area image (avoids 0 · inf = NaN).
    if (!std::isfinite(s.max)) continue;
    weighted_sigma2 += a_to * 0.5 * (s.max * s.max + s.min * s.min);
  }
  if (!(area_to > 0.0))
    throw std::invalid_argument("stretch: the pieces have zero total area on the range side");
  if (!std::isfinite(max_stretch)) return {kInfinity, 0.0, kInfinity};

  const double area_ratio = area_from / area_to;  // undoes the global scale of the map
  const double l2_normalized = weighted_sigma2 / area_to * area_ratio;
  return {l2_normalized, 1.0 / l2_normalized, max_stretch * std::sqrt(area_ratio)};
}

}  // namespace

double triangle_area(const TriangleLengths& t) {
  // Kahan, "Miscalculating area and angles of a needle-like triangle": sort
  // a >= b >= c and keep the parentheses; plain Heron loses all digits on slivers.
  std::array<double, 3> l = {t.l0, t.l1, t.l2};
  std::sort(l.begin(), l.end(), std::greater<>());
  const double a = l[0], b = l[1], c = l[2];
  const double product = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return product > 0.0 ? 0.25 * std::sqrt(product) : 0.0;
}

std::array<Eigen::Vector2d, 3> triangle_layout(const TriangleLengths& t) {
  const Eigen::Vector2d v0 = Eigen::Vector2d::Zero();
  if (!(t.l2 > 0.0)) return {v0, v0, Eigen::Vector2d(t.l1, 0.0)};  // v1 == v0: flat
  // x from the law of cosines; the height from the stable area rather than
  // sqrt(l1² - x²), which cancels badly and may go slightly negative.
  const double x = (t.l1 * t.l1 + t.l2 * t.l2 - t.l0 * t.l0) / (2.0 * t.l2);
  const double y = 2.0 * triangle_area(t) / t.l2;
  return {v0, Eigen::Vector2d(t.l2, 0.0), Eigen::Vector2d(x, y)};
}

SingularValues stretch_singular_values(const TriangleLengths& domain,
                                       const TriangleLengths& range) {
  const auto p = triangle_layout(domain);
  const auto q = triangle_layout(range);
  // Domain layout P = [p1 p2] = [[l2, x], [0, y]] with det = 2 A_D.
  const double det_p = p[1].x() * p[2].y();
  if (!(det_p > 0.0)) return {kInfinity, kInfinity};

  // Columns of J = Q P⁻¹ (Sander's Ss = ∂q/∂s, St = ∂q/∂t).
  const Eigen::Vector2d ss = q[1] / p[1].x();
  const Eigen::Vector2d st = (q[2] - q[1] * (p[2].x() / p[1].x())) / p[2].y();
  const double a = ss.squaredNorm(), b = ss.dot(st), c = st.squaredNorm();
  const double big = std::sqrt(0.5 * ((a + c) + std::hypot(a - c, 2.0 * b)));
  // γ from det J = Γ γ instead of the "-" root, which cancels when Γ >> γ.
  const double det_j = (q[1].x() * q[2].y()) / det_p;
  const double small = big > 0.0 ? std::min(big, det_j / big) : 0.0;
  return {big, small};
}

PieceAreas piece_areas(std::span<const StretchPiece> pieces) {
  PieceAreas total;
  for (const StretchPiece& piece : pieces) {
    total.domain += triangle_area(piece.domain);
    total.range += triangle_area(piece.range);
  }
  return total;
}

OneWayStretch one_way_stretch(std::span<const StretchPiece> pieces) {
  return one_way_stretch_impl(pieces, /*inverse=*/false);
}

SymmetricStretch symmetric_stretch(std::span<const StretchPiece> pieces) {
  const OneWayStretch forward = one_way_stretch_impl(pieces, /*inverse=*/false);
  const OneWayStretch backward = one_way_stretch_impl(pieces, /*inverse=*/true);
  const double sum = forward.l2_normalized + backward.l2_normalized;
  return {sum, 2.0 / sum, forward.efficiency, backward.efficiency};
}

double symmetric_piece_energy(const StretchPiece& piece, double area_domain_total,
                              double area_range_total) {
  // With A_D, A_M the totals, one_way_stretch gives
  //   L2n²(D->M) = (Σ_T A_M(T) σ²(T) / A_M) · (A_D / A_M) = Σ_T A_M(T) · A_D / A_M² · σ²(T),
  // and the inverse map has singular values 1/γ, 1/Γ and weights A_D(T), so
  //   L2n²(M->D) = Σ_T A_D(T) · A_M / A_D² · σ⁻²(T),  σ⁻² = (1/γ² + 1/Γ²) / 2.
  // Each term below is one T of both sums; it is evaluated exactly as
  // symmetric_stretch does (inverse singular values computed directly).
  const SingularValues forward = stretch_singular_values(piece.domain, piece.range);
  const SingularValues backward = stretch_singular_values(piece.range, piece.domain);
  if (!std::isfinite(forward.max) || !std::isfinite(backward.max)) return kInfinity;
  const double sigma2_forward = 0.5 * (forward.max * forward.max + forward.min * forward.min);
  const double sigma2_backward = 0.5 * (backward.max * backward.max + backward.min * backward.min);
  return triangle_area(piece.range) * area_domain_total / (area_range_total * area_range_total) *
             sigma2_forward +
         triangle_area(piece.domain) * area_range_total / (area_domain_total * area_domain_total) *
             sigma2_backward;
}

}  // namespace ism
