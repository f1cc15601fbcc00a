#pragma once
// The pieces of the overlay inside one M² face: the M¹ faces its chart
// triangle covers, each unfolded into the chart, with the convex piece they
// share. Used by validate(), the measures and the sampler.
#include "map/surface_map.hpp"

#include <functional>

namespace ism {

struct OverlayPiece {
  int domain_face;
  std::array<Vec2, 3> domain_layout;  // the M¹ face in the M² face's chart
  std::vector<Vec2> polygon;          // the piece, in the chart
  double area;
};

/// Calls `visit` for every piece of M² face t with positive area; returns
/// false if t has no valid chart.
bool for_each_piece(const SurfaceMap& map, int t,
                    const std::function<void(const OverlayPiece&)>& visit);

/// Convex polygon clipped by the triangle (a, b, c), counter-clockwise.
std::vector<Vec2> clip_to_triangle(std::vector<Vec2> polygon, const std::array<Vec2, 3>& triangle);
/// polygon_area(clip_to_triangle(polygon, triangle)), the same number,
/// without allocating (work arrays kept per thread). [lo, hi] is the
/// polygon's bounding box: when it lies apart from the triangle's by more
/// than 10⁻⁶ of the coordinates' size, the answer is 0 without clipping
/// (the clipping's rounding cannot bring a point across such a gap, so it
/// would return the empty polygon too).
double clipped_area(const std::vector<Vec2>& polygon, const Vec2& lo, const Vec2& hi,
                    const std::array<Vec2, 3>& triangle);

}  // namespace ism
