#include "sample/torus_grid.hpp"

#include "sample/grid_measures.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>

namespace ism {

namespace {

// Cells per side of domain::torus_3x3().
constexpr int kCells = 3;

// The face and weights of the point with local coordinates (x, y) in
// [0, 1]² of cell (row, col); faces and corners as domain::torus_3x3().
TorusPoint cell_point(int row, int col, double x, double y) {
  const int cell_face = 2 * (kCells * row + col);
  if (x >= y) return {cell_face, {1.0 - x, x - y, y}};  // (0,0), (1,0), (1,1)
  return {cell_face + 1, {1.0 - y, x, y - x}};          // (0,0), (1,1), (0,1)
}

// Cell index and local coordinate in [0, 1] of a parameter coordinate.
std::pair<int, double> wrap(double s) {
  double f = s - std::floor(s);
  if (f >= 1.0) f = 0.0;  // a tiny negative s rounds up to 1
  const double scaled = kCells * f;
  const int cell = std::min(static_cast<int>(scaled), kCells - 1);
  return {cell, scaled - cell};
}

// Cell index and local coordinate of grid line k of n, from the integers:
// 3k/n = cell + remainder/n.
std::pair<int, double> grid_wrap(int k, int n) {
  const std::int64_t scaled = std::int64_t(kCells) * k;
  const int cell = static_cast<int>(scaled / n);
  return {cell, static_cast<double>(scaled - std::int64_t(cell) * n) / n};
}

void check_size(int columns, int rows) {
  if (!is_torus_grid_size(columns, rows))
    throw std::invalid_argument("torus grid size " + std::to_string(columns) + "x" +
                                std::to_string(rows) +
                                " is not U x V with U, V >= 3 and U*V <= 2^26");
}

void check_grid(const TorusGrid& grid) {
  check_size(grid.columns, grid.rows);
  const std::size_t expected = static_cast<std::size_t>(grid.columns) * grid.rows;
  if (grid.points.size() != expected)
    throw std::invalid_argument("torus grid has " + std::to_string(grid.points.size()) +
                                " points, expected U*V = " + std::to_string(expected));
}

}  // namespace

TorusPoint torus_point(double s, double t) {
  if (!std::isfinite(s) || !std::isfinite(t))
    throw std::invalid_argument("torus_point: non-finite parameter point");
  const auto [col, x] = wrap(s);
  const auto [row, y] = wrap(t);
  return cell_point(row, col, x, y);
}

TorusPoint torus_grid_point(int columns, int rows, int column, int row) {
  const auto [cell_col, x] = grid_wrap(column, columns);
  const auto [cell_row, y] = grid_wrap(row, rows);
  return cell_point(cell_row, cell_col, x, y);
}

Eigen::Vector2d torus_parameter_point(const TorusPoint& p) {
  if (p.face < 0 || p.face >= 2 * kCells * kCells)
    throw std::invalid_argument("torus face " + std::to_string(p.face) + " out of range");
  const int cell = p.face / 2, row = cell / kCells, col = cell % kCells;
  // Local corner coordinates of the two faces of a cell.
  const bool lower = p.face % 2 == 0;
  const Eigen::Vector2d c1 = lower ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(1, 1);
  const Eigen::Vector2d c2 = lower ? Eigen::Vector2d(1, 1) : Eigen::Vector2d(0, 1);
  const Eigen::Vector2d local = p.bary[1] * c1 + p.bary[2] * c2;
  return (Eigen::Vector2d(col, row) + local) / kCells;
}

bool is_torus_grid_size(int columns, int rows) {
  return columns >= 3 && rows >= 3 &&
         static_cast<std::int64_t>(columns) * rows <= (std::int64_t(1) << 26);
}

TorusGrid sample_torus_grid(int columns, int rows,
                            const std::function<Vec3(const TorusPoint&)>& surface_point) {
  check_size(columns, rows);
  TorusGrid grid;
  grid.columns = columns;
  grid.rows = rows;
  grid.points.assign(static_cast<std::size_t>(columns) * rows, Vec3::Zero());
  // Each point is written by exactly one task: deterministic.
  tbb::parallel_for(0, rows, [&](int row) {
    for (int col = 0; col < columns; ++col)
      grid.at(row, col) = surface_point(torus_grid_point(columns, rows, col, row));
  });
  return grid;
}

QuadMesh torus_grid_mesh(const TorusGrid& grid) {
  check_grid(grid);
  const int u = grid.columns, v = grid.rows;
  QuadMesh mesh;
  mesh.positions = grid.points;
  mesh.quads.reserve(grid.points.size());
  auto vertex = [&](int row, int col) { return (row % v) * u + col % u; };
  for (int row = 0; row < v; ++row)
    for (int col = 0; col < u; ++col)
      mesh.quads.push_back(
          {vertex(row, col), vertex(row, col + 1), vertex(row + 1, col + 1), vertex(row + 1, col)});
  return mesh;
}

namespace {

// Whether quad (row, col) of the grid is split along a–c (else b–d).
bool split_along_ac(const TorusGrid& grid, int row, int col) {
  const int next_row = (row + 1) % grid.rows, next_col = (col + 1) % grid.columns;
  return (grid.at(next_row, next_col) - grid.at(row, col)).squaredNorm() <=
         (grid.at(next_row, col) - grid.at(row, next_col)).squaredNorm();
}

}  // namespace

TriangleMesh torus_grid_triangles(const TorusGrid& grid) {
  const QuadMesh quads = torus_grid_mesh(grid);
  TriangleMesh out;
  out.positions = quads.positions;
  out.triangles.reserve(2 * quads.quads.size());
  for (int row = 0; row < grid.rows; ++row)
    for (int col = 0; col < grid.columns; ++col) {
      const Quad& q = quads.quads[grid.index(row, col)];
      if (split_along_ac(grid, row, col)) {
        out.triangles.push_back({q[0], q[1], q[2]});
        out.triangles.push_back({q[0], q[2], q[3]});
      } else {
        out.triangles.push_back({q[0], q[1], q[3]});
        out.triangles.push_back({q[1], q[2], q[3]});
      }
    }
  return out;
}

double torus_grid_efficiency(const TorusGrid& grid) {
  check_grid(grid);
  const int u = grid.columns, v = grid.rows;
  // Every flat triangle of one kind is the same: legs 1/U along s, 1/V along t.
  const Vec3 origin(0, 0, 0), along_s(1.0 / u, 0, 0), diagonal(1.0 / u, 1.0 / v, 0),
      along_t(0, 1.0 / v, 0);
  const TriangleLengths lower = detail::triangle_lengths(origin, along_s, diagonal);
  const TriangleLengths upper = detail::triangle_lengths(origin, diagonal, along_t);
  // Split along the other diagonal, b–d.
  const TriangleLengths left = detail::triangle_lengths(origin, along_s, along_t);
  const TriangleLengths right = detail::triangle_lengths(along_s, diagonal, along_t);
  return detail::grid_efficiency(
      v,
      [&](int row, std::vector<StretchPiece>& pieces) {
        const int next_row = (row + 1) % v;
        for (int col = 0; col < u; ++col) {
          const int next_col = (col + 1) % u;
          const Vec3 &a = grid.at(row, col), &b = grid.at(row, next_col),
                     &c = grid.at(next_row, next_col), &d = grid.at(next_row, col);
          if (split_along_ac(grid, row, col)) {
            pieces.push_back({lower, detail::triangle_lengths(a, b, c)});
            pieces.push_back({upper, detail::triangle_lengths(a, c, d)});
          } else {
            pieces.push_back({left, detail::triangle_lengths(a, b, d)});
            pieces.push_back({right, detail::triangle_lengths(b, c, d)});
          }
        }
      },
      "torus_grid_efficiency");
}

std::size_t torus_grid_flipped_triangles(const TorusGrid& grid) {
  return flipped_faces(torus_grid_triangles(grid));
}

UnfoldReport unfold_torus_grid(TorusGrid& grid,
                               const std::function<Vec3(const TorusPoint&)>& surface_point,
                               int max_rounds) {
  check_grid(grid);
  const int u = grid.columns, v = grid.rows;
  // The eight grid neighbours' directions (columns, rows).
  static constexpr int kDirections[8][2] = {{1, 0}, {-1, 0},  {0, 1},  {0, -1},
                                            {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  static constexpr double kSteps[3] = {0.25, 0.5, 0.75};
  auto candidates = [&](int x, std::vector<Vec3>& out) {
    const int row = x / u, col = x % u;
    for (double step : kSteps)
      for (const auto& d : kDirections) {
        try {
          out.push_back(
              surface_point(torus_point((col + step * d[0]) / u, (row + step * d[1]) / v)));
        } catch (const std::exception&) {
        }
      }
  };
  const std::vector<Vec3> given = grid.points;
  UnfoldReport report;
  for (int pass = 0; pass < 3; ++pass) {
    TriangleMesh mesh = torus_grid_triangles(grid);
    const UnfoldReport r =
        unfold_samples(mesh, candidates, {.max_rounds = max_rounds, .by_depth = true});
    // (The first pass's folds before are the grid's, counted on its triangles.)
    if (pass == 0) report.folds_before = report.folds_after = r.folds_before;
    if (r.moved_vertices == 0) break;
    TorusGrid moved{grid.columns, grid.rows, std::move(mesh.positions)};
    const std::size_t folds = torus_grid_flipped_triangles(moved);
    if (folds >= report.folds_after) break;
    grid = std::move(moved);
    report.folds_after = folds;
  }
  for (std::size_t x = 0; x < grid.points.size(); ++x)
    report.moved_vertices += grid.points[x] != given[x];
  return report;
}

}  // namespace ism
