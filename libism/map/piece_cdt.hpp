#pragma once
// Constrained Delaunay triangulation of a simple polygon (CGAL's 2D CDT,
// compiled alone in piece_cdt.cpp so that CGAL's flags stay in that file).
#include <Eigen/Core>

#include <array>
#include <optional>
#include <vector>

namespace ism {

/// The triangles of the constrained Delaunay triangulation of the simple
/// polygon `polygon` (counter-clockwise, no repeated point), as corner
/// indices, counter-clockwise; nothing if the polygon is not simple or the
/// triangulation does not consist of exactly n - 2 triangles on its corners.
std::optional<std::vector<std::array<int, 3>>> polygon_cdt(
    const std::vector<Eigen::Vector2d>& polygon);

}  // namespace ism
