// InterSurfaceMap's private parts reached from tests only (a friend of
// the class): the split's undo, the index, a large chart's energies, and
// refused split attempts (to drive the retries and the early release).
#pragma once

#include "map/inter_surface_map.hpp"
#include "map/inter_surface_map_impl.hpp"

#include <array>
#include <cmath>

namespace ism {

struct InterSurfaceMapTestAccess {
  static int split_and_undo(InterSurfaceMap& map, int side) { return map.try_split(side, false); }
  static const MetaIndex& index(const InterSurfaceMap& map) { return map.index_; }
  /// split_next's next n attempts find no place (without trying).
  static void refuse_split_attempts(InterSurfaceMap& map, int n) {
    map.refused_split_attempts_ = n;
  }
  /// The energy of v's ring with v moved by `offset` in its chart, as a
  /// large chart sums it (the pieces' stretch per face of s) and cell by
  /// cell; NaN if the chart is not large.
  static std::array<double, 2> large_chart_energies(const InterSurfaceMap& map, int s, int v,
                                                    const Vec2& offset) {
    InterSurfaceMap::Chart chart;
    if (!map.build_chart(s, v, chart) || !chart.large()) return {NAN, NAN};
    InterSurfaceMap::Layout layout;
    map.ring_layout(chart, layout);
    layout.inner[0].pos = chart.centre + offset;
    const double summed = map.evaluate(chart, layout, nullptr);
    for (auto& fragment : chart.fragments) fragment.summable = false;
    return {summed, map.evaluate(chart, layout, nullptr)};
  }
};

}  // namespace ism
