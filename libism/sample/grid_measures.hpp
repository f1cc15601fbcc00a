#pragma once
// Measures shared by the grid samplers of this folder (octahedral geometry
// images, torus grids); not part of the public interface.
#include "mesh/triangle_mesh.hpp"
#include "metrics/metrics.hpp"

#include <cstddef>
#include <functional>
#include <vector>

namespace ism::detail {

/// Edge lengths of the triangle (a, b, c) as TriangleLengths orders them.
inline TriangleLengths triangle_lengths(const Vec3& a, const Vec3& b, const Vec3& c) {
  return {(b - c).norm(), (c - a).norm(), (a - b).norm()};
}

/// One-way L2 stretch efficiency (as ism::one_way_stretch) of the map from
/// flat grid triangles to their images, without building the list of all
/// pieces: `pieces_of_row(row, out)` appends the pieces of one row of cells
/// (out arrives empty). Rows are measured in parallel and added up in row
/// order, so the result does not depend on the schedule. Throws
/// std::invalid_argument, message starting with `caller`, when the total
/// range area is zero.
double grid_efficiency(
    int rows, const std::function<void(int row, std::vector<StretchPiece>& out)>& pieces_of_row,
    const char* caller);

}  // namespace ism::detail
