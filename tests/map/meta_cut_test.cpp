// Triangulations of pieces (meta_cut.hpp): every one returned is valid on
// both sides, and pieces that need points added inside get them.
#include "map/meta_cut.hpp"
#include "map/domain_geometry.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace ism {
namespace {

// Every triangle positive on both sides and the triangles' areas summing to
// each polygon's area: a valid triangulation of both (a locally injective
// map of a disc whose boundary goes round once).
void expect_valid(const MetaPiece& piece, const PieceTriangulation& tri) {
  ASSERT_FALSE(tri.triangles.empty());
  for (int s = 0; s < 2; ++s) {
    ASSERT_GE(tri.points[s].size(), piece.corner[s].size());
    for (std::size_t i = 0; i < piece.corner[s].size(); ++i)
      EXPECT_EQ(tri.points[s][i], piece.corner[s][i]);
    double sum = 0;
    for (const auto& t : tri.triangles) {
      const double a = orient(tri.points[s][t[0]], tri.points[s][t[1]], tri.points[s][t[2]]);
      EXPECT_GT(a, 0) << "side " << s;
      sum += 0.5 * a;
    }
    EXPECT_NEAR(sum, polygon_area(piece.corner[s]), 1e-12);
  }
}

// A random counter-clockwise triangle with corners in [-1, 1]², twice its
// area above `min_twice_area`.
std::array<Vec2, 3> ccw_triangle_in_square(std::mt19937& rng, double min_twice_area) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::array<Vec2, 3> t;
  do {
    for (auto& p : t) p = Vec2(u(rng), u(rng));
  } while (!(orient(t[0], t[1], t[2]) > min_twice_area));
  return t;
}

MetaPiece piece_of(std::vector<Vec2> p, std::vector<Vec2> q) {
  MetaPiece piece;
  piece.area = {polygon_area(p), polygon_area(q)};
  piece.corner = {std::move(p), std::move(q)};
  return piece;
}

TEST(TriangulatePiece, ConvexPieceIsAFanOnItsCorners) {
  const MetaPiece piece =
      piece_of({{0, 0}, {2, 0}, {2, 1}, {0, 1}}, {{0, 0}, {1, 0}, {1, 1}, {0, 2}});
  const PieceTriangulation tri = triangulate_piece(piece);
  expect_valid(piece, tri);
  EXPECT_FALSE(tri.added);
  EXPECT_EQ(tri.triangles.size(), 2u);
}

TEST(TriangulatePiece, CollinearCornersOnBothSidesGetAStar) {
  // Runs of collinear corners on different edges of each side: no fan works.
  const MetaPiece piece =
      piece_of({{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}, {{0, 0}, {2, 0}, {2, 1}, {2, 2}, {0, 2}});
  const PieceTriangulation tri = triangulate_piece(piece);
  expect_valid(piece, tri);
}

// Pairs of simple hexagons with no triangulation on their corners valid on
// both sides (found by a random search): a compatible triangulation needs
// points inside.
TEST(TriangulatePiece, PiecesWithNoCompatibleTriangulationOnTheirCornersGetAddedPoints) {
  const std::vector<std::array<std::vector<Vec2>, 2>> pairs = {{{{{0.741, 0.041},
                                                                  {-0.081, 1.052},
                                                                  {-0.533, 0.531},
                                                                  {0.179, -0.463},
                                                                  {-0.399, -0.824},
                                                                  {0.753, -0.566}},
                                                                 {{0.718, 0.127},
                                                                  {0.222, 0.062},
                                                                  {0.559, 0.729},
                                                                  {-0.88, 0.1},
                                                                  {-0.178, 0.375},
                                                                  {0.219, -0.072}}}},
                                                               {{{{0.047, 0.094},
                                                                  {0.693, 0.846},
                                                                  {-0.035, 0.156},
                                                                  {-0.644, 0.705},
                                                                  {-0.031, -0.951},
                                                                  {0.284, -0.003}},
                                                                 {{0.641, 0.262},
                                                                  {0.546, 0.428},
                                                                  {0.532, 1.191},
                                                                  {-1.042, 0.117},
                                                                  {-0.53, -1.323},
                                                                  {0.066, 0.321}}}},
                                                               {{{{0.56, 0.38},
                                                                  {-0.281, 0.4},
                                                                  {-0.071, -0.558},
                                                                  {0.776, -0.234},
                                                                  {0.841, -0.186},
                                                                  {0.429, -0.292}},
                                                                 {{0.346, -0.224},
                                                                  {0.136, 0.55},
                                                                  {-0.365, -1.204},
                                                                  {-0.268, -0.911},
                                                                  {-0.19, -0.723},
                                                                  {0.787, -0.21}}}}};
  for (const auto& [p, q] : pairs) {
    const MetaPiece piece = piece_of(p, q);
    const PieceTriangulation tri = triangulate_piece(piece);
    expect_valid(piece, tri);
    EXPECT_TRUE(tri.added);
    // The same from the other side: sides swapped give the same triangles.
    const PieceTriangulation swapped = triangulate_piece(piece_of(q, p));
    expect_valid(piece_of(q, p), swapped);
  }
}

// The same where one polygon is not star-shaped (its kernel is empty): no
// star either, only the overlay of the two sides' triangulations.
TEST(TriangulatePiece, PiecesWithNoStarGetTheOverlayOfBothTriangulations) {
  const std::vector<std::array<std::vector<Vec2>, 2>> pairs = {{{{{0.658, 0.157},
                                                                  {0.66, 0.336},
                                                                  {0.386, 0.332},
                                                                  {0.384, 0.455},
                                                                  {0.011, -0.702},
                                                                  {0.813, -0.126}},
                                                                 {{0.324, 0.465},
                                                                  {0.309, 0.061},
                                                                  {-0.756, 0.156},
                                                                  {-0.869, -0.601},
                                                                  {-0.801, -0.559},
                                                                  {0.368, -0.548}}}},
                                                               {{{{0.002, 0.279},
                                                                  {0.059, 0.698},
                                                                  {-0.472, -0.196},
                                                                  {0.258, -0.034},
                                                                  {-0.177, -0.507},
                                                                  {0.575, -0.061}},
                                                                 {{0.722, 0.443},
                                                                  {0.123, 0.256},
                                                                  {-0.324, 0.401},
                                                                  {-0.182, -0.402},
                                                                  {-0.744, -0.932},
                                                                  {0.139, -1.202}}}}};
  for (const auto& [p, q] : pairs) {
    const MetaPiece piece = piece_of(p, q);
    const PieceTriangulation tri = triangulate_piece(piece);
    expect_valid(piece, tri);
    EXPECT_TRUE(tri.added);
    EXPECT_TRUE(tri.cdt);
  }
}

TEST(TriangulatePiece, PolygonThatIsNotSimpleHasNone) {
  // A bow tie on one side.
  const MetaPiece piece =
      piece_of({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{0, 0}, {1, 1}, {1, 0}, {0, 1}});
  EXPECT_TRUE(triangulate_piece(piece).triangles.empty());
}

}  // namespace

// StretchMoments: triangles sharing one affine map A of the chart to side
// 0, each with its own map to side 1, give the same sums as
// triangle_stretch_terms of each triangle (A·c, B·c), for any A; a share
// of a triangle's moments is that share of its terms.
TEST(StretchMoments, SumsTheStretchTermsOfItsTriangles) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random_triangle = [&] { return ccw_triangle_in_square(rng, 0.05); };
  for (int trial = 0; trial < 20; ++trial) {
    StretchMoments moments;
    std::vector<std::array<Vec2, 3>> chart, other;
    for (int k = 0; k < 5; ++k) {
      chart.push_back(random_triangle());
      other.push_back(random_triangle());
      ASSERT_TRUE(moments.add(chart.back(), other.back()));
    }
    Eigen::Matrix2d A;
    do {
      A << u(rng), u(rng), u(rng), u(rng);
    } while (!(A.determinant() > 0.1));
    const Vec2 shift(u(rng), u(rng));
    double forward = 0, backward = 0;
    for (std::size_t k = 0; k < chart.size(); ++k) {
      std::array<Vec2, 3> side0;
      for (int j = 0; j < 3; ++j) side0[j] = A * chart[k][j] + shift;
      const StretchTerms t = triangle_stretch_terms(side0, other[k]);
      forward += t.forward, backward += t.backward;
    }
    const auto [x, y] = moments.evaluate(A);
    EXPECT_NEAR(x, forward, 1e-9 * forward);
    EXPECT_NEAR(y, backward, 1e-9 * backward);
    StretchMoments part;
    part.add(moments, 0.25);
    EXPECT_NEAR(part.evaluate(A)[0], 0.25 * forward, 1e-9 * forward);
  }
  StretchMoments none;
  EXPECT_FALSE(
      none.add({Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)}, {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}));
  EXPECT_EQ(none.area, 0);
}

// CornerStretch: the energy of a triangle as a function of one corner is
// triangle_energy's (either side moving, any corner, a forward weight and
// unequal total areas), and its gradient and Hessian are the energy's
// (central differences); not positive where the moving triangle is not.
TEST(CornerStretch, IsTheTriangleEnergyOfOneCornerWithItsDerivatives) {
  std::mt19937 rng(11);
  auto random_triangle = [&] { return ccw_triangle_in_square(rng, 0.1); };
  EnergyTerms terms{2.5, 0.7, 0.3};
  int penalised = 0;
  for (int trial = 0; trial < 48; ++trial) {
    const int moving = trial % 2, k = (trial / 2) % 3;
    // The second half with the anisotropy penalty: half of it with the onset
    // low (most triangles past it), half with it out of reach.
    terms.anisotropy_weight = trial < 24 ? 0.0 : 0.8;
    terms.anisotropy_onset = trial < 36 ? 2.2 : 1e3;
    const double weight = 0.5 + 0.1 * trial;
    const std::array<Vec2, 3> p = random_triangle(), q = random_triangle();
    const auto c = corner_stretch(p, q, moving, k, terms, weight);
    ASSERT_TRUE(c);
    auto energy_at = [&](const Vec2& x) {
      std::array<Vec2, 3> pp = p, qq = q;
      (moving == 0 ? pp : qq)[k] = x;
      return triangle_energy(pp, qq, terms, weight);
    };
    const Vec2 x = (moving == 0 ? p : q)[k];
    Vec2 g;
    Eigen::Matrix2d h;
    const double e = c->derivatives(x, g, h);
    if (trial >= 24) {
      EnergyTerms plain = terms;
      plain.anisotropy_weight = 0;
      penalised += e > triangle_energy(p, q, plain, weight) * (1 + 1e-9);
    }
    EXPECT_NEAR(e, energy_at(x), 1e-12 * e);
    EXPECT_DOUBLE_EQ(c->value(x), e);
    const double step = 1e-5;
    for (int i = 0; i < 2; ++i) {
      Vec2 d = Vec2::Zero();
      d[i] = step;
      const double numeric = (energy_at(x + d) - energy_at(x - d)) / (2 * step);
      EXPECT_NEAR(g[i], numeric, 1e-5 * (std::abs(numeric) + e)) << trial;
      Vec2 gp, gm;
      Eigen::Matrix2d unused;
      c->derivatives(x + d, gp, unused);
      c->derivatives(x - d, gm, unused);
      const Vec2 column = (gp - gm) / (2 * step);
      EXPECT_NEAR(h(0, i), column[0], 1e-5 * (h.norm() + e)) << trial;
      EXPECT_NEAR(h(1, i), column[1], 1e-5 * (h.norm() + e)) << trial;
    }
    EXPECT_NEAR(h(0, 1), h(1, 0), 1e-12 * h.norm());
    // Beyond the opposite edge the moving triangle is folded.
    const std::array<Vec2, 3>& tri = moving == 0 ? p : q;
    const Vec2 folded = tri[(k + 1) % 3] + tri[(k + 2) % 3] - x;
    EXPECT_EQ(c->value(folded), HUGE_VAL);
  }
  EXPECT_GE(penalised, 6);
  EXPECT_LE(penalised, 12);
  // The fixed triangle must be positive.
  const std::array<Vec2, 3> good{Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)},
      bad{Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)};
  EXPECT_FALSE(corner_stretch(good, bad, 0, 0, terms));
  EXPECT_TRUE(corner_stretch(bad, good, 0, 0, terms));
}

}  // namespace ism
