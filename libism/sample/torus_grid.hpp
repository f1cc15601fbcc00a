#pragma once
// Torus grids (paper §6.4; DESIGN.md §5 "Torus"): the flat torus of
// domain::torus_3x3(), the unit square with opposite sides identified,
// sampled on a periodic U × V grid, and the grid read back as a closed
// genus-1 quad mesh in which every vertex has valence 4.
//
// Layout (the contract for every program that reads or writes our grids):
//
//  - A parameter point (s, t) is a point of the unit square, periodic with
//    period 1 in both; s runs along the columns of domain::torus_3x3() (its
//    x), t along its rows (its y).
//  - A U × V grid has U columns and V rows, U·V points and no repeated row
//    or column: point (row j, column i), 0 <= i < U, 0 <= j < V, is the
//    parameter point (i/U, j/V) and has index j·U + i (row-major). Column
//    U-1 is followed by column 0 again, row V-1 by row 0.
//  - The periodic geometry image is the grid as V rows × U columns of
//    pixels in the same order: pixel (row j, column i), row 0 first (at the
//    top of the picture), is grid point (j, i), so t grows downwards.
//  - Quad mesh: vertex j·U + i is grid point (j, i); quad j·U + i has the
//    corners (j, i), (j, i+1), (j+1, i+1), (j+1, i), indices modulo U and
//    V: counter-clockwise in (s, t), as the faces of torus_3x3(), so the
//    samples of a map that keeps the domain's orientation on an outward
//    surface give outward quads.
//  - Triangulation (torus_grid_triangles): quad q with corners a = (j, i),
//    b = (j, i+1), c = (j+1, i+1), d = (j+1, i) is split along its shorter
//    diagonal in space, a–c on a tie: triangles 2q = (a, b, c), 2q+1 =
//    (a, c, d), or 2q = (a, b, d), 2q+1 = (b, c, d). A grid quad is not
//    planar where the surface bends across it; the shorter diagonal follows
//    the bend, where the other one cuts across it and folds the pair (teapot
//    at 128²: 25 -> 7 folded triangles, the same samples).
//  - Domain faces: cell (row r, column c) of torus_3x3(), 0 <= r, c < 3,
//    covers [c/3, (c+1)/3] × [r/3, (r+1)/3]. Of its two faces, 2(3r+c)
//    (corners (c,r), (c+1,r), (c+1,r+1) in units of 1/3) is the half where
//    the local coordinates satisfy x >= y, 2(3r+c)+1 (corners (c,r),
//    (c+1,r+1), (c,r+1)) the half where y > x.
#include "mesh/quad_mesh.hpp"
#include "mesh/triangle_mesh.hpp"
#include "sample/unfold.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace ism {

/// A point of domain::torus_3x3(): a face and barycentric coordinates with
/// respect to that face's corners in its vertex order.
struct TorusPoint {
  int face = 0;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

/// The torus point of the parameter point (s, t), any finite reals, wrapped
/// into [0, 1)². A point on the side of a cell belongs to the cell on its
/// larger-s (larger-t) side; a point on a cell's diagonal to its face
/// 2(3r+c). Weights are >= 0 and sum to 1. Throws std::invalid_argument for
/// a non-finite s or t.
TorusPoint torus_point(double s, double t);

/// torus_point(column / columns, row / rows), computed from the integers so
/// that grid points on cell sides, diagonals and domain vertices are placed
/// exactly (with U and V multiples of 3, the nine domain vertices are grid
/// points). Requires 0 <= column < columns and 0 <= row < rows.
TorusPoint torus_grid_point(int columns, int rows, int column, int row);

/// The parameter point in [0, 1]² of a torus point (its face's cell, no
/// wrap): the inverse of torus_point up to the period.
Eigen::Vector2d torus_parameter_point(const TorusPoint& p);

/// True for grid sizes 3 <= U, V with U·V <= 2^26 (a closed manifold quad
/// mesh needs three rows and columns; the limit keeps indices in an int and
/// memory sane).
bool is_torus_grid_size(int columns, int rows);

/// The samples of a U × V grid, in the layout above.
struct TorusGrid {
  int columns = 0, rows = 0;  // U, V
  std::vector<Vec3> points;   // row-major, rows * columns

  Vec3& at(int row, int column) { return points[index(row, column)]; }
  const Vec3& at(int row, int column) const { return points[index(row, column)]; }
  std::size_t index(int row, int column) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) +
           static_cast<std::size_t>(column);
  }
};

/// Samples a surface over the flat torus: surface_point is called once per
/// grid point, at torus_grid_point(), concurrently from several threads (so
/// it must be thread-safe); the result does not depend on the schedule.
/// Throws std::invalid_argument unless is_torus_grid_size(columns, rows).
TorusGrid sample_torus_grid(int columns, int rows,
                            const std::function<Vec3(const TorusPoint&)>& surface_point);

/// The closed quad mesh of the grid (layout above): U·V vertices, U·V quads,
/// every vertex of valence 4, genus 1. Throws std::invalid_argument for a
/// bad size or point count.
QuadMesh torus_grid_mesh(const TorusGrid& grid);

/// The 2·U·V triangles of the grid, each quad split along its shorter
/// diagonal (layout above). Throws as torus_grid_mesh.
TriangleMesh torus_grid_triangles(const TorusGrid& grid);

/// One-way L2 stretch efficiency of the map from the flat grid triangles of
/// the unit square (legs 1/U and 1/V, split as torus_grid_triangles splits
/// each quad) to the triangles of torus_grid_triangles(), as image_efficiency() in sample.hpp: 1
/// for an isometry up to scale; lengths only, so a fold is not penalised (count those with
/// torus_grid_flipped_triangles). Throws std::invalid_argument for a bad
/// grid or one with zero total area.
double torus_grid_efficiency(const TorusGrid& grid);

/// Number of triangles of torus_grid_triangles() whose normal has a negative
/// dot product with the sum of the area-weighted normals of all triangles
/// sharing a vertex with it (itself included), across the wrap too, as
/// flipped_triangles() in sample.hpp. Zero-area triangles are never flipped.
std::size_t torus_grid_flipped_triangles(const TorusGrid& grid);

/// Re-samples the points of folded triangles of torus_grid_triangles(grid)
/// (unfold_samples(), unfold.hpp) at nearby parameter points: a quarter,
/// half or three quarters of the way towards each of their eight grid
/// neighbours (across the wrap too), through `surface_point` as
/// sample_torus_grid() calls it (again for each tried point; one that throws
/// is not tried). A quad's shorter diagonal may change when its corners
/// move, so the triangles are made again from the moved points and the
/// re-sampling repeated while the folds drop (at most three passes of
/// `max_rounds` rounds); a pass that does not lower
/// torus_grid_flipped_triangles() is dropped. The grid's layout is
/// unchanged; every point stays a value of `surface_point`. folds_before and
/// folds_after are torus_grid_flipped_triangles() of the grid as given and
/// as returned. Throws std::invalid_argument for a bad grid.
UnfoldReport unfold_torus_grid(TorusGrid& grid,
                               const std::function<Vec3(const TorusPoint&)>& surface_point,
                               int max_rounds = 8);

}  // namespace ism
