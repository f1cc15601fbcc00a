#include "domain/domain.hpp"

namespace ism::domain {

TriangleMesh octahedron() {
  TriangleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Counter-clockwise seen from outside: the upper faces go +x, +y, -x, -y
  // around +z, the lower ones the other way around -z.
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

TriangleMesh torus_3x3() {
  TriangleMesh m;
  auto id = [](int row, int col) { return 3 * ((row + 3) % 3) + (col + 3) % 3; };
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) m.positions.push_back({col / 3.0, row / 3.0, 0.0});
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) {
      const int a = id(row, col), b = id(row, col + 1), c = id(row + 1, col + 1),
                d = id(row + 1, col);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

}  // namespace ism::domain
