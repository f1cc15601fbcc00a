// Stretch of affine pieces against values derived by hand (Sander et al. 2001,
// Schreiner et al. 2004).
#include "metrics/metrics.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using ism::SingularValues;
using ism::StretchPiece;
using ism::TriangleLengths;

constexpr double kTol = 1e-12;

TriangleLengths lengths_of(const Vector3d& v0, const Vector3d& v1, const Vector3d& v2) {
  return {(v2 - v1).norm(), (v0 - v2).norm(), (v1 - v0).norm()};
}
TriangleLengths lengths_of(const Vector2d& v0, const Vector2d& v1, const Vector2d& v2) {
  return {(v2 - v1).norm(), (v0 - v2).norm(), (v1 - v0).norm()};
}
TriangleLengths scaled(const TriangleLengths& t, double k) {
  return {k * t.l0, k * t.l1, k * t.l2};
}

/// Expected singular values of a 2x2 J from the eigenvalues of JᵀJ (trace/determinant form).
SingularValues expected_singular_values(const Eigen::Matrix2d& j) {
  const Eigen::Matrix2d jtj = j.transpose() * j;
  const double trace = jtj.trace(), det = jtj.determinant();
  const double root = std::sqrt(trace * trace / 4.0 - det);
  return {std::sqrt(trace / 2.0 + root), std::sqrt(trace / 2.0 - root)};
}

/// A fixed, irregular set of pieces: a 3x3-vertex planar grid (8 triangles)
/// mapped onto a distorted copy of it lifted into 3D.
std::vector<StretchPiece> distorted_pieces() {
  std::vector<Vector2d> domain;
  std::vector<Vector3d> range;
  const std::array<Vector3d, 9> offset = {
      Vector3d(0.00, 0.00, 0.00),  Vector3d(0.13, -0.05, 0.20), Vector3d(0.30, 0.02, -0.10),
      Vector3d(-0.07, 0.21, 0.05), Vector3d(0.25, 0.40, 0.33),  Vector3d(0.41, 0.17, -0.22),
      Vector3d(0.02, 0.36, 0.11),  Vector3d(0.19, 0.58, -0.04), Vector3d(0.77, 0.63, 0.28)};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      domain.emplace_back(x, y);
      range.push_back(Vector3d(1.3 * x, 0.8 * y, 0.0) + offset[3 * y + x]);
    }
  std::vector<StretchPiece> pieces;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      const int a = 3 * y + x, b = a + 1, c = a + 3, d = a + 4;
      for (const std::array<int, 3>& t : {std::array<int, 3>{a, b, d}, std::array<int, 3>{a, d, c}})
        pieces.push_back({lengths_of(domain[t[0]], domain[t[1]], domain[t[2]]),
                          lengths_of(range[t[0]], range[t[1]], range[t[2]])});
    }
  return pieces;
}

std::vector<StretchPiece> swapped(std::vector<StretchPiece> pieces) {
  for (StretchPiece& p : pieces) std::swap(p.domain, p.range);
  return pieces;
}

TEST(TriangleLayout, ReproducesTheLengths) {
  const TriangleLengths t =
      lengths_of(Vector2d(0.3, -1.0), Vector2d(2.0, 0.5), Vector2d(-0.4, 1.7));
  const auto v = ism::triangle_layout(t);
  EXPECT_EQ(v[0], Vector2d::Zero());
  EXPECT_EQ(v[1].y(), 0.0);
  EXPECT_GT(v[1].x(), 0.0);
  EXPECT_GT(v[2].y(), 0.0);
  EXPECT_NEAR((v[2] - v[1]).norm(), t.l0, kTol);
  EXPECT_NEAR((v[0] - v[2]).norm(), t.l1, kTol);
  EXPECT_NEAR((v[1] - v[0]).norm(), t.l2, kTol);
}

TEST(TriangleLayout, FlatLengthsGiveZeroHeightNotNaN) {
  // 1 + 1 = 2 exactly, and a slight violation of the triangle inequality.
  for (const TriangleLengths& t :
       {TriangleLengths{2.0, 1.0, 1.0}, TriangleLengths{2.0 + 1e-15, 1.0, 1.0}}) {
    const auto v = ism::triangle_layout(t);
    EXPECT_EQ(v[2].y(), 0.0);
    EXPECT_FALSE(std::isnan(v[2].x()));
    EXPECT_EQ(ism::triangle_area(t), 0.0);
  }
}

TEST(StretchSingularValues, ScaledRotatedCopyHasUniformStretch) {
  const Vector3d v0(0.1, 0.2, 0.3), v1(1.4, -0.3, 0.9), v2(0.2, 1.1, -0.5);
  const TriangleLengths domain = lengths_of(v0, v1, v2);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.83, Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  for (double k : {0.25, 1.0, 3.7}) {
    const Vector3d shift(5.0, -1.0, 2.0);
    auto move = [&](const Vector3d& v) -> Vector3d { return k * rotation * v + shift; };
    const TriangleLengths range = lengths_of(move(v0), move(v1), move(v2));
    const SingularValues s = ism::stretch_singular_values(domain, range);
    EXPECT_NEAR(s.max, k, kTol * k);
    EXPECT_NEAR(s.min, k, kTol * k);
    EXPECT_NEAR(ism::l2_stretch(s), k, kTol * k);
    EXPECT_NEAR(ism::linf_stretch(s), k, kTol * k);

    const std::vector<StretchPiece> pieces = {{domain, range}};
    EXPECT_NEAR(ism::one_way_stretch(pieces).efficiency, 1.0, kTol);
    EXPECT_NEAR(ism::one_way_stretch(pieces).l2_normalized, 1.0, kTol);
    EXPECT_NEAR(ism::one_way_stretch(pieces).linf, 1.0, kTol);
    EXPECT_NEAR(ism::symmetric_stretch(pieces).efficiency, 1.0, kTol);
    EXPECT_NEAR(ism::symmetric_stretch(pieces).sum, 2.0, kTol);
  }
}

TEST(StretchSingularValues, RelabellingTheVerticesChangesNothing) {
  // The same permutation of the vertices on both sides is the same map.
  const TriangleLengths domain{1.0, 1.3, 0.9};
  const TriangleLengths range{2.1, 1.2, 1.7};
  const SingularValues reference = ism::stretch_singular_values(domain, range);
  std::array<int, 3> perm = {0, 1, 2};
  do {
    auto permute = [&](const TriangleLengths& t) {
      const std::array<double, 3> l = {t.l0, t.l1, t.l2};
      return TriangleLengths{l[perm[0]], l[perm[1]], l[perm[2]]};
    };
    const SingularValues s = ism::stretch_singular_values(permute(domain), permute(range));
    EXPECT_NEAR(s.max, reference.max, kTol);
    EXPECT_NEAR(s.min, reference.min, kTol);
    // Uniform scaling of a permuted copy of the same shape is still isometric up to scale.
    const SingularValues iso =
        ism::stretch_singular_values(permute(domain), scaled(permute(domain), 2.5));
    EXPECT_NEAR(iso.max, 2.5, kTol);
    EXPECT_NEAR(iso.min, 2.5, kTol);
  } while (std::next_permutation(perm.begin(), perm.end()));
}

TEST(StretchSingularValues, ShearMatchesEigenvaluesOfJtJ) {
  // Domain (0,0),(1,0),(0,1) -> range (0,0),(a,0),(s,b): J = [[a, s], [0, b]].
  const TriangleLengths domain = lengths_of(Vector2d(0, 0), Vector2d(1, 0), Vector2d(0, 1));
  for (const auto& [a, s, b] :
       {std::array<double, 3>{1.5, 0.7, 0.8}, std::array<double, 3>{0.3, -2.0, 1.1},
        std::array<double, 3>{1.0, 1.0, 1.0}}) {
    const TriangleLengths range = lengths_of(Vector2d(0, 0), Vector2d(a, 0), Vector2d(s, b));
    Eigen::Matrix2d j;
    j << a, s, 0.0, b;
    const SingularValues expected = expected_singular_values(j);
    const SingularValues got = ism::stretch_singular_values(domain, range);
    EXPECT_NEAR(got.max, expected.max, kTol) << "a=" << a << " s=" << s << " b=" << b;
    EXPECT_NEAR(got.min, expected.min, kTol) << "a=" << a << " s=" << s << " b=" << b;
    // Cross-check with Eigen's SVD and with det J = Γγ.
    const Eigen::Vector2d svd = j.jacobiSvd().singularValues();
    EXPECT_NEAR(got.max, svd(0), kTol);
    EXPECT_NEAR(got.min, svd(1), kTol);
    EXPECT_NEAR(got.max * got.min, a * b, kTol);
  }
}

TEST(StretchSingularValues, AxisStretch) {
  // diag(2, 0.5): Γ = 2, γ = 0.5, area preserved.
  const TriangleLengths domain = lengths_of(Vector2d(0, 0), Vector2d(1, 0), Vector2d(0, 1));
  const TriangleLengths range = lengths_of(Vector2d(0, 0), Vector2d(2, 0), Vector2d(0, 0.5));
  const SingularValues s = ism::stretch_singular_values(domain, range);
  EXPECT_NEAR(s.max, 2.0, kTol);
  EXPECT_NEAR(s.min, 0.5, kTol);
  EXPECT_NEAR(ism::l2_stretch(s), std::sqrt((4.0 + 0.25) / 2.0), kTol);
  EXPECT_DOUBLE_EQ(ism::linf_stretch(s), s.max);

  const std::vector<StretchPiece> pieces = {{domain, range}};
  const ism::OneWayStretch one_way = ism::one_way_stretch(pieces);
  EXPECT_NEAR(one_way.l2_normalized, 2.125, kTol);  // A_D = A_M
  EXPECT_NEAR(one_way.efficiency, 1.0 / 2.125, kTol);
  EXPECT_NEAR(one_way.linf, 2.0, kTol);
  // The inverse diag(0.5, 2) has the same singular values.
  const ism::SymmetricStretch sym = ism::symmetric_stretch(pieces);
  EXPECT_NEAR(sym.sum, 2.0 * 2.125, kTol);
  EXPECT_NEAR(sym.efficiency, 1.0 / 2.125, kTol);
  EXPECT_NEAR(sym.forward_efficiency, sym.backward_efficiency, kTol);
}

TEST(OneWayStretch, ConformalPiecesWithUnequalScalesLoseEfficiency) {
  // Two equal domain triangles scaled by k1 = 1 and k2 = 2 (each conformal).
  // Forward: L2n² = 2 (k1⁴ + k2⁴) / (k1² + k2²)² = 34 / 25.
  // Backward: weights A_D, σ² = 1/k²: L2n² = (1/k1² + 1/k2²) / 2 · (k1² + k2²) / 2 = 25 / 16.
  const TriangleLengths t{1.0, 1.2, 0.9};
  const std::vector<StretchPiece> pieces = {{t, t}, {t, scaled(t, 2.0)}};
  const ism::OneWayStretch forward = ism::one_way_stretch(pieces);
  EXPECT_NEAR(forward.l2_normalized, 34.0 / 25.0, kTol);
  EXPECT_NEAR(forward.efficiency, 25.0 / 34.0, kTol);
  EXPECT_NEAR(forward.linf, 2.0 * std::sqrt(2.0 / 5.0), kTol);
  const ism::SymmetricStretch sym = ism::symmetric_stretch(pieces);
  EXPECT_NEAR(sym.sum, 34.0 / 25.0 + 25.0 / 16.0, kTol);
  EXPECT_NEAR(sym.efficiency, 2.0 / (34.0 / 25.0 + 25.0 / 16.0), kTol);
  EXPECT_NEAR(sym.backward_efficiency, 16.0 / 25.0, kTol);
}

TEST(SymmetricStretch, InvariantToSwapAndScale) {
  const std::vector<StretchPiece> pieces = distorted_pieces();
  const ism::SymmetricStretch reference = ism::symmetric_stretch(pieces);
  EXPECT_LT(reference.efficiency, 1.0 - 1e-3);
  EXPECT_GT(reference.efficiency, 0.0);
  EXPECT_LE(reference.forward_efficiency, 1.0);
  EXPECT_LE(reference.backward_efficiency, 1.0);
  EXPECT_LE(ism::one_way_stretch(pieces).efficiency, 1.0);
  EXPECT_NEAR(ism::one_way_stretch(pieces).efficiency, reference.forward_efficiency, kTol);

  const ism::SymmetricStretch swap = ism::symmetric_stretch(swapped(pieces));
  EXPECT_NEAR(swap.sum, reference.sum, kTol * reference.sum);
  EXPECT_NEAR(swap.efficiency, reference.efficiency, kTol);
  EXPECT_NEAR(swap.forward_efficiency, reference.backward_efficiency, kTol);
  EXPECT_NEAR(swap.backward_efficiency, reference.forward_efficiency, kTol);
  EXPECT_LE(ism::one_way_stretch(swapped(pieces)).efficiency, 1.0);

  for (const auto& [kd, km] : {std::array<double, 2>{1.0, 2.5}, std::array<double, 2>{0.3, 1.0},
                               std::array<double, 2>{7.0, 0.01}}) {
    std::vector<StretchPiece> rescaled = pieces;
    for (StretchPiece& p : rescaled) p = {scaled(p.domain, kd), scaled(p.range, km)};
    const ism::SymmetricStretch s = ism::symmetric_stretch(rescaled);
    EXPECT_NEAR(s.sum, reference.sum, kTol * reference.sum);
    EXPECT_NEAR(s.forward_efficiency, reference.forward_efficiency, kTol);
    EXPECT_NEAR(s.backward_efficiency, reference.backward_efficiency, kTol);
  }
}

TEST(SymmetricStretch, PieceEnergiesSumToTheTotal) {
  for (const std::vector<StretchPiece>& pieces :
       {distorted_pieces(), swapped(distorted_pieces())}) {
    const ism::PieceAreas areas = ism::piece_areas(pieces);
    double sum = 0.0;
    for (const StretchPiece& p : pieces)
      sum += ism::symmetric_piece_energy(p, areas.domain, areas.range);
    const double expected = ism::symmetric_stretch(pieces).sum;
    EXPECT_NEAR(sum, expected, kTol * expected);
  }
}

TEST(StretchDegenerate, ZeroAreaDomainGivesInfiniteStretch) {
  const TriangleLengths flat{2.0, 1.0, 1.0};  // collinear vertices
  const TriangleLengths good{1.0, 1.0, 1.0};
  const double inf = std::numeric_limits<double>::infinity();

  const SingularValues s = ism::stretch_singular_values(flat, good);
  EXPECT_EQ(s.max, inf);
  EXPECT_EQ(s.min, inf);
  EXPECT_EQ(ism::l2_stretch(s), inf);
  EXPECT_EQ(ism::stretch_singular_values(TriangleLengths{0.0, 0.0, 0.0}, good).max, inf);

  // A flat range is a finite (if singular) map: γ = 0.
  const SingularValues collapse = ism::stretch_singular_values(good, flat);
  EXPECT_TRUE(std::isfinite(collapse.max));
  EXPECT_EQ(collapse.min, 0.0);

  const std::vector<StretchPiece> pieces = {{good, good}, {flat, good}};
  const ism::OneWayStretch one_way = ism::one_way_stretch(pieces);
  EXPECT_EQ(one_way.l2_normalized, inf);
  EXPECT_EQ(one_way.linf, inf);
  EXPECT_EQ(one_way.efficiency, 0.0);
  const ism::SymmetricStretch sym = ism::symmetric_stretch(pieces);
  EXPECT_EQ(sym.sum, inf);
  EXPECT_EQ(sym.efficiency, 0.0);
  const ism::PieceAreas areas = ism::piece_areas(pieces);
  EXPECT_EQ(ism::symmetric_piece_energy(pieces[1], areas.domain, areas.range), inf);
  // Flat on both sides: still infinite, not NaN.
  EXPECT_EQ(ism::symmetric_piece_energy({flat, flat}, areas.domain, areas.range), inf);
}

TEST(StretchDegenerate, NoPiecesOrNoAreaThrows) {
  EXPECT_THROW(ism::one_way_stretch({}), std::invalid_argument);
  EXPECT_THROW(ism::symmetric_stretch({}), std::invalid_argument);
  const TriangleLengths flat{2.0, 1.0, 1.0};
  const std::vector<StretchPiece> flat_range = {{TriangleLengths{1, 1, 1}, flat}};
  EXPECT_THROW(ism::one_way_stretch(flat_range), std::invalid_argument);
}

}  // namespace
