#include "sample/grid_measures.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ism::detail {

double grid_efficiency(
    int rows, const std::function<void(int row, std::vector<StretchPiece>& out)>& pieces_of_row,
    const char* caller) {
  // The sums of one_way_stretch, per row.
  struct Sums {
    double area_domain = 0.0, area_range = 0.0, weighted_sigma2 = 0.0;
  };
  std::vector<Sums> row_sums(std::max(rows, 0));
  tbb::parallel_for(0, rows, [&](int row) {
    std::vector<StretchPiece> pieces;
    pieces_of_row(row, pieces);
    Sums s;
    for (const StretchPiece& piece : pieces) {
      const SingularValues sv = stretch_singular_values(piece.domain, piece.range);
      const double a_range = triangle_area(piece.range);
      s.area_domain += triangle_area(piece.domain);
      s.area_range += a_range;
      s.weighted_sigma2 += a_range * 0.5 * (sv.max * sv.max + sv.min * sv.min);
    }
    row_sums[row] = s;
  });
  Sums total;
  for (const Sums& s : row_sums) {
    total.area_domain += s.area_domain;
    total.area_range += s.area_range;
    total.weighted_sigma2 += s.weighted_sigma2;
  }
  if (!(total.area_range > 0.0))
    throw std::invalid_argument(std::string(caller) + ": the grid has zero surface area");
  const double l2_normalized =
      total.weighted_sigma2 / total.area_range * (total.area_domain / total.area_range);
  return 1.0 / l2_normalized;
}

}  // namespace ism::detail
