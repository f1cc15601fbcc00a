// Geodesic sphere (class I subdivision of the icosahedron) and the ellipsoid.
#include "shapes/shapes.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace ism::shapes {
namespace {

// Corners (0, +-1, +-phi) and their cyclic permutations. The faces are the
// triples at mutual distance 2 (the edge length), turned outward; deriving
// them avoids a hand-typed table.
TriangleMesh icosahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  for (double s : {-1.0, 1.0})
    for (double t : {-1.0, 1.0}) {
      m.positions.emplace_back(0.0, s, t * phi);
      m.positions.emplace_back(s, t * phi, 0.0);
      m.positions.emplace_back(t * phi, 0.0, s);
    }
  const int nv = static_cast<int>(m.positions.size());
  auto adjacent = [&](int a, int b) {
    return std::abs((m.positions[a] - m.positions[b]).squaredNorm() - 4.0) < 1e-9;
  };
  for (int a = 0; a < nv; ++a)
    for (int b = a + 1; b < nv; ++b)
      for (int c = b + 1; c < nv; ++c) {
        if (!adjacent(a, b) || !adjacent(b, c) || !adjacent(a, c)) continue;
        Triangle t{a, b, c};
        const Vec3& pa = m.positions[a];
        if ((m.positions[b] - pa).cross(m.positions[c] - pa).dot(pa) < 0) std::swap(t[1], t[2]);
        m.triangles.push_back(t);
      }
  return m;
}

// Splits every face into n^2 triangles. Points on an edge are created once,
// by whichever face meets the edge first, in the edge's (low, high) index
// direction, so both faces get the same indices and bitwise-equal positions.
TriangleMesh subdivide(const TriangleMesh& base, int n) {
  TriangleMesh out;
  out.positions = base.positions;
  std::map<std::pair<int, int>, int> edge_first;  // first of the n-1 points from low to high
  auto edge_point = [&](int u, int v, int t) {    // point t/n of the way from u to v, 0 < t < n
    const int lo = std::min(u, v), hi = std::max(u, v);
    auto [it, inserted] = edge_first.try_emplace({lo, hi}, static_cast<int>(out.positions.size()));
    if (inserted) {
      const Vec3 a = base.positions[lo], b = base.positions[hi];
      for (int s = 1; s < n; ++s) out.positions.push_back(a + (b - a) * (double(s) / n));
    }
    return it->second + (u == lo ? t : n - t) - 1;
  };

  std::vector<int> grid((n + 1) * (n + 1));
  for (const Triangle& f : base.triangles) {
    const auto [a, b, c] = f;
    const Vec3 pa = base.positions[a], pb = base.positions[b], pc = base.positions[c];
    // at(i, j) is the point a + i/n (b - a) + j/n (c - a), for i + j <= n.
    auto at = [&](int i, int j) -> int& { return grid[i * (n + 1) + j]; };
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        if (i == 0 && j == 0)
          at(i, j) = a;
        else if (i == n)
          at(i, j) = b;
        else if (j == n)
          at(i, j) = c;
        else if (j == 0)
          at(i, j) = edge_point(a, b, i);
        else if (i == 0)
          at(i, j) = edge_point(a, c, j);
        else if (i + j == n)
          at(i, j) = edge_point(b, c, j);
        else {
          at(i, j) = static_cast<int>(out.positions.size());
          out.positions.push_back(pa + (pb - pa) * (double(i) / n) + (pc - pa) * (double(j) / n));
        }
      }
    // The affine map (i, j) -> point keeps the orientation of (a, b, c).
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        out.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j + 2 <= n) out.triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  return out;
}

}  // namespace

TriangleMesh sphere(int target_faces, double radius) {
  const int n =
      std::max(1, static_cast<int>(std::lround(std::sqrt(std::max(target_faces, 0) / 20.0))));
  TriangleMesh mesh = subdivide(icosahedron(), n);
  // Central projection keeps each face inside its spherical triangle, so the
  // orientation stays outward and nothing folds.
  for (Vec3& p : mesh.positions) p = p.normalized() * radius;
  return mesh;
}

TriangleMesh ellipsoid(int target_faces, const Vec3& semi_axes) {
  TriangleMesh mesh = sphere(target_faces);
  for (Vec3& p : mesh.positions) p = p.cwiseProduct(semi_axes);
  return mesh;
}

}  // namespace ism::shapes
