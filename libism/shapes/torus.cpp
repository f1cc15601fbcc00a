// Parametric torus.
#include "shapes/shapes.hpp"

#include <algorithm>
#include <cmath>

namespace ism::shapes {

TriangleMesh torus(int target_faces, double R, double r) {
  // Square cells: 2 pi R / n = 2 pi r / m, and 2 n m = target_faces.
  const double target = std::max(target_faces, 0);
  const int n = std::max(3, static_cast<int>(std::lround(std::sqrt(target * R / (2.0 * r)))));
  const int m = std::max(3, static_cast<int>(std::lround(target / (2.0 * n))));

  TriangleMesh mesh;
  mesh.positions.reserve(n * m);
  for (int i = 0; i < n; ++i) {
    const double theta = 2.0 * M_PI * i / n;  // around the z axis
    for (int j = 0; j < m; ++j) {
      const double phi = 2.0 * M_PI * j / m;  // around the tube
      const double rho = R + r * std::cos(phi);
      mesh.positions.emplace_back(rho * std::cos(theta), rho * std::sin(theta), r * std::sin(phi));
    }
  }
  // d/dtheta x d/dphi points away from the tube axis, so (i, j) -> (i+1, j) ->
  // (i+1, j+1) is counter-clockwise seen from outside.
  mesh.triangles.reserve(2 * n * m);
  auto index = [m](int i, int j) { return i * m + j; };
  for (int i = 0; i < n; ++i) {
    const int i1 = (i + 1) % n;
    for (int j = 0; j < m; ++j) {
      const int j1 = (j + 1) % m;
      mesh.triangles.push_back({index(i, j), index(i1, j), index(i1, j1)});
      mesh.triangles.push_back({index(i, j), index(i1, j1), index(i, j1)});
    }
  }
  return mesh;
}

}  // namespace ism::shapes
