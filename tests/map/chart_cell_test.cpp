// Cells of the other side's content in a chart (chart_cell.hpp): their map,
// and the kinks of paper §5.1, Figure 4.
#include "map/chart_cell.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace ism {
namespace {

// Figure 4: in the chart the cell is a square (its top side holds a corner
// u half-way along); on the other side u is pushed down, below the middle,
// so the cell is concave there.
const std::vector<Vec2> kChart = {{0, 0}, {2, 0}, {2, 2}, {1, 2}, {0, 2}};
const std::vector<Vec2> kOther = {{0, 0}, {2, 0}, {2, 2}, {1, 0.8}, {0, 2}};

TEST(ChartCell, CornersThatFitOneAffineMapGiveAnAffineCell) {
  std::vector<Vec2> other;
  for (const Vec2& p : kChart) other.push_back(Vec2(3 + 0.5 * p.x() - 0.2 * p.y(), 0.7 * p.y()));
  const auto cell = make_chart_cell(kChart, other);
  ASSERT_TRUE(cell);
  EXPECT_TRUE(cell->affine);
  EXPECT_TRUE(cell_image(*cell, Vec2(0.5, 1.5)).isApprox(Vec2(3 + 0.25 - 0.3, 1.05), 1e-12));
  // Straight in the chart, straight on the other side.
  for (KinkRule rule : {KinkRule::follow_cells, KinkRule::where_needed})
    EXPECT_TRUE(cell_kinks(*cell, Vec2(0, 1.5), Vec2(2, 1.5), cell_image(*cell, Vec2(0, 1.5)),
                           cell_image(*cell, Vec2(2, 1.5)), rule)
                    .empty());
}

TEST(ChartCell, ConcaveOnTheOtherSideGetsATriangulationValidOnBoth) {
  const auto cell = make_chart_cell(kChart, kOther);
  ASSERT_TRUE(cell);
  EXPECT_FALSE(cell->affine);
  ASSERT_FALSE(cell->triangles.empty());
  for (int side = 0; side < 2; ++side) {
    const std::vector<Vec2>& points = side == 0 ? cell->tri_chart : cell->tri_other;
    double sum = 0;
    for (const auto& t : cell->triangles) {
      const double a = orient(points[t[0]], points[t[1]], points[t[2]]);
      EXPECT_GT(a, 0) << "side " << side;
      sum += 0.5 * a;
    }
    EXPECT_NEAR(sum, polygon_area(side == 0 ? kChart : kOther), 1e-12);
  }
  // Corners map to corners; the map is continuous across the diagonals.
  for (std::size_t i = 0; i < kChart.size(); ++i)
    EXPECT_TRUE(cell_image(*cell, kChart[i]).isApprox(kOther[i], 1e-12));
}

TEST(ChartCell, SegmentPassingTheConcaveCornerOnTheWrongSideBends) {
  // Figure 4: an edge crossing the cell above u in the chart. Its ends map
  // to (0, 1.5) and (2, 1.5); the straight segment between them passes
  // above u = (1, 0.8), outside the cell: it must bend below u.
  const auto cell = make_chart_cell(kChart, kOther);
  ASSERT_TRUE(cell);
  const Vec2 A(0, 1.5), B(2, 1.5);
  const Vec2 a = cell_image(*cell, A), b = cell_image(*cell, B);
  EXPECT_TRUE(a.isApprox(Vec2(0, 1.5), 1e-12));
  EXPECT_TRUE(b.isApprox(Vec2(2, 1.5), 1e-12));
  EXPECT_FALSE(segment_inside_polygon(kOther, a, b));
  std::vector<CellKink> kinks = cell_kinks(*cell, A, B, a, b, KinkRule::where_needed);
  ASSERT_FALSE(kinks.empty());
  std::sort(kinks.begin(), kinks.end(),
            [](const CellKink& x, const CellKink& y) { return x.u < y.u; });
  // Each kink on AB in the chart, its image the cell's map of it; the bent
  // path on the other side stays inside the cell, below u.
  std::vector<Vec2> path{a};
  for (const CellKink& k : kinks) {
    EXPECT_GT(k.u, 0);
    EXPECT_LT(k.u, 1);
    EXPECT_TRUE(k.chart.isApprox(A + k.u * (B - A), 1e-12));
    EXPECT_TRUE(k.other.isApprox(cell_image(*cell, k.chart), 1e-9));
    path.push_back(k.other);
  }
  path.push_back(b);
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    EXPECT_TRUE(segment_inside_polygon(kOther, path[i], path[i + 1])) << "segment " << i;
  const double lowest =
      std::min_element(path.begin(), path.end(), [](const Vec2& x, const Vec2& y) {
        return x.y() < y.y();
      })->y();
  EXPECT_LT(lowest, 0.8);
}

TEST(ChartCell, SegmentThatStaysInsideTheConcaveCellIsStraight) {
  // Below u on both sides: by the paper's rule no kink although the cell
  // is not affine (kinks only where the straight segment would leave it).
  const auto cell = make_chart_cell(kChart, kOther);
  ASSERT_TRUE(cell);
  const Vec2 A(0, 0.3), B(2, 0.3);
  const Vec2 a = cell_image(*cell, A), b = cell_image(*cell, B);
  EXPECT_TRUE(segment_inside_polygon(kOther, a, b));
  EXPECT_TRUE(cell_kinks(*cell, A, B, a, b, KinkRule::where_needed).empty());
  // Following the cell's map, the edge bends at the diagonals all the same.
  const std::vector<CellKink> kinks = cell_kinks(*cell, A, B, a, b, KinkRule::follow_cells);
  EXPECT_FALSE(kinks.empty());
  for (const CellKink& k : kinks) EXPECT_TRUE(k.other.isApprox(cell_image(*cell, k.chart), 1e-9));
}

TEST(ChartCell, SegmentEndsOnSidesDoNotCountAsLeaving) {
  // Ends on the sides they enter and leave by, rounded to either side of
  // them: inside. Through a corner, or crossing a side: not.
  const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (double e : {0.0, 1e-17, -1e-17, 1e-13, -1e-13}) {
    EXPECT_TRUE(segment_inside_polygon(square, Vec2(0.3, e), Vec2(e, 0.6))) << e;
    EXPECT_TRUE(segment_inside_polygon(square, Vec2(0.3, e), Vec2(0.8, 1 - e))) << e;
  }
  EXPECT_FALSE(segment_inside_polygon(square, Vec2(0.5, 0.5), Vec2(1.5, 0.5)));
  EXPECT_FALSE(segment_inside_polygon(kOther, Vec2(0.5, 1.5), Vec2(1.5, 1.5)));
  EXPECT_FALSE(segment_inside_polygon(kOther, Vec2(0, 0.8), Vec2(2, 0.8)));  // through u
}

}  // namespace
}  // namespace ism
