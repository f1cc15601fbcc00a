#pragma once
// A cell of the other side's content laid out in a local chart (paper
// §5.1): its corners in the chart and in one face of the other side, the
// map between the two, and where a segment drawn straight in the chart must
// bend on the other side (kinks, paper Figure 4).
#include "map/domain_geometry.hpp"  // Vec2, orient, barycentric

#include <array>
#include <optional>
#include <vector>

namespace ism {

/// A cell: a simple polygon, counter-clockwise, given twice (corners in
/// the chart and the same corners in the other side's face). Its map is the
/// affine one when the corners fit one (within 1e-9 of the size), otherwise
/// the piecewise-affine map of a triangulation valid on both polygons
/// (triangulate_piece: fan, star, constrained Delaunay, or the overlay of
/// both, with points added inside when needed).
struct ChartCell {
  std::vector<Vec2> chart, other;
  bool affine = true;
  /// When not affine: triangles over `tri_chart` / `tri_other` (the corners
  /// first, then added points).
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec2> tri_chart, tri_other;
  Vec2 lo{0, 0}, hi{0, 0};  // bounding box of `chart` (set by make_chart_cell)
  bool operator==(const ChartCell&) const = default;
};

/// The cell of these corners (same count, both counter-clockwise with
/// positive area); nothing if its map is not affine and no triangulation
/// valid on both polygons is found.
std::optional<ChartCell> make_chart_cell(std::vector<Vec2> chart, std::vector<Vec2> other);

/// The image on the other side of a chart point inside the cell:
/// mean-value interpolation of the corners in an affine cell (exact there),
/// the affine map of the triangle holding it otherwise.
Vec2 cell_image(const ChartCell& cell, const Vec2& p);

/// Even-odd test of p against a polygon.
bool inside_polygon(const std::vector<Vec2>& polygon, const Vec2& p);
/// inside_polygon(cell.chart, p), the same answer: the cell's bounding box
/// first rejects only points whose crossing count is even (y outside
/// [lo.y, hi.y), or x beyond the box by far more than rounding).
bool inside_cell(const ChartCell& cell, const Vec2& p);

/// Whether the straight segment ab (ends on or inside the simple polygon)
/// stays inside it: it crosses no side, passes through no corner between
/// its ends, and its midpoint is inside. Near-touches of a corner count as
/// leaving; an end on a side (where the segment enters or leaves the
/// polygon: within 1e-9 of the lengths, rounding either way) does not count
/// as crossing it.
bool segment_inside_polygon(const std::vector<Vec2>& polygon, const Vec2& a, const Vec2& b);

/// A point where an edge bends on the other side.
struct CellKink {
  double u;    // parameter along the chart segment AB
  Vec2 chart;  // the point in the chart
  Vec2 other;  // its image in the other side's face
};

/// Where an edge drawn straight across a cell whose map is not affine bends
/// on the other side.
enum class KinkRule {
  /// The edge follows the cell's map: a kink at every diagonal of the
  /// cell's triangulation it crosses (the chart's view of the map, exact).
  follow_cells,
  /// Paper §5.1, Figure 4: straight on the other side between its mapped
  /// ends unless that segment leaves the cell (a concave corner on the
  /// wrong side); then as follow_cells.
  where_needed,
};

/// The kinks of an edge drawn straight in the chart from A to B through
/// the cell (A and B on its boundary or inside it), its ends mapped to a and
/// b on the other side: where AB crosses the diagonals of the cell's
/// triangulation, as `rule` says; none in an affine cell. In no particular
/// order.
std::vector<CellKink> cell_kinks(const ChartCell& cell, const Vec2& A, const Vec2& B, const Vec2& a,
                                 const Vec2& b, KinkRule rule);

}  // namespace ism
