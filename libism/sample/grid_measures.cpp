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

std::size_t count_flipped_faces(const TriangleMesh& mesh) {
  const std::size_t nf = mesh.n_faces(), nv = mesh.n_vertices();
  std::vector<Vec3> normal(nf);
  for (std::size_t f = 0; f < nf; ++f) normal[f] = face_normal_scaled(mesh, f);

  // Faces around each vertex (compressed rows).
  std::vector<std::size_t> start(nv + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (int v : t) ++start[v + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::size_t> faces(start[nv]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (int v : mesh.triangles[f]) faces[fill[v]++] = f;
  }

  std::vector<char> flipped(nf, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf), [&](const auto& range) {
    std::vector<std::size_t> ring;
    for (std::size_t f = range.begin(); f != range.end(); ++f) {
      // Union of the faces around the three corners: a neighbour sharing an
      // edge must count once, not twice.
      ring.clear();
      for (int v : mesh.triangles[f])
        ring.insert(ring.end(), faces.begin() + start[v], faces.begin() + start[v + 1]);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      Vec3 sum = Vec3::Zero();
      for (std::size_t g : ring) sum += normal[g];
      flipped[f] = normal[f].dot(sum) < 0.0;
    }
  });
  return static_cast<std::size_t>(std::count(flipped.begin(), flipped.end(), 1));
}

}  // namespace ism::detail
