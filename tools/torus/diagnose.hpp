#pragma once
// Diagnostic of flipped grid triangles (ISM_TORUS_DIAGNOSE=FILE): for every
// grid triangle the fold test flags, where it is on the surface and the
// Jacobian singular values (domain -> surface, unit-square metric) of the
// map faces its corners sample; plus the map's anisotropy distribution.
#include "map/map.hpp"
#include "metrics/metrics.hpp"
#include "sample/torus_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace ism::diagnose {

struct FaceStretch {
  double big = 0, small = 0;  // singular values Γ >= γ
  double area_m = 0;
};

// Singular values of the domain -> surface Jacobian of each face of a flat-torus map.
inline std::vector<FaceStretch> face_stretches(const SurfaceMap& map) {
  std::vector<FaceStretch> out(map.n_faces());
  const auto layout = map.flat_layout();
  if (!layout) return out;
  const auto& x = map.positions();
  const auto& faces = map.faces();
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Vec2 a = layout->corner(faces, int(t), 0);
    Eigen::Matrix2d d;
    d << layout->corner(faces, int(t), 1) - a, layout->corner(faces, int(t), 2) - a;
    Eigen::Matrix<double, 3, 2> q;
    q << x[faces[t][1]] - x[faces[t][0]], x[faces[t][2]] - x[faces[t][0]];
    const Eigen::Matrix<double, 3, 2> j = q * d.inverse();
    const double frob = j.squaredNorm();
    const double area_m = 0.5 * q.col(0).cross(q.col(1)).norm();
    const double det = area_m / (0.5 * d.determinant());
    const double disc = std::sqrt(std::max(0.0, frob * frob - 4 * det * det));
    out[t].big = std::sqrt(0.5 * (frob + disc));
    out[t].small = det / out[t].big;
    out[t].area_m = area_m;
  }
  return out;
}

inline void write(const SurfaceMap& map, const TorusGrid& grid, const char* path) {
  FILE* f = std::fopen(path, "w");
  if (!f) return;
  const auto st = face_stretches(map);
  double total = 0;
  for (const auto& s : st) total += s.area_m;
  // Area share above anisotropy thresholds.
  for (double k : {2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    double a = 0;
    int n = 0;
    for (const auto& s : st)
      if (s.big > k * s.small) a += s.area_m, ++n;
    std::fprintf(f, "aniso>%g: %d faces, %.5f of area\n", k, n, a / total);
  }
  // The fold test per triangle (as flipped_faces).
  const TriangleMesh mesh = triangulate(torus_grid_mesh(grid));
  const std::size_t nf = mesh.n_faces();
  std::vector<Vec3> normal(nf);
  for (std::size_t t = 0; t < nf; ++t) normal[t] = face_normal_scaled(mesh, t);
  std::vector<std::vector<std::size_t>> around(mesh.n_vertices());
  for (std::size_t t = 0; t < nf; ++t)
    for (int v : mesh.triangles[t]) around[v].push_back(t);
  const MapSampler sampler(map);
  const int u = grid.columns, v = grid.rows;
  for (std::size_t t = 0; t < nf; ++t) {
    std::vector<std::size_t> ring;
    for (int w : mesh.triangles[t]) ring.insert(ring.end(), around[w].begin(), around[w].end());
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    Vec3 sum = Vec3::Zero();
    for (std::size_t g : ring) sum += normal[g];
    if (!(normal[t].dot(sum) < 0)) continue;
    const int quad = int(t / 2), row = quad / u, col = quad % u;
    const Vec3 c = (mesh.positions[mesh.triangles[t][0]] + mesh.positions[mesh.triangles[t][1]] +
                    mesh.positions[mesh.triangles[t][2]]) /
                   3;
    const auto& tri = mesh.triangles[t];
    const Vec3 &p0 = mesh.positions[tri[0]], &p1 = mesh.positions[tri[1]],
               &p2 = mesh.positions[tri[2]];
    const double l0 = (p2 - p1).norm(), l1 = (p0 - p2).norm(), l2 = (p1 - p0).norm();
    const double lmax = std::max({l0, l1, l2});
    std::fprintf(f,
                 "flip tri %zu row %d col %d half %zu centre %.4f %.4f %.4f area %.3g cos %.3f "
                 "edges %.3g %.3g %.3g aspect %.1f\n",
                 t, row, col, t % 2, c.x(), c.y(), c.z(), 0.5 * normal[t].norm(),
                 normal[t].normalized().dot(sum.normalized()), l0, l1, l2,
                 lmax * lmax / (normal[t].norm() + 1e-300));
    for (int w : mesh.triangles[t]) {
      const int r = w / u, k = w % u;
      const auto s = sampler.surface_point(torus_grid_point(u, v, k, r).face,
                                           torus_grid_point(u, v, k, r).bary);
      if (!s) continue;
      const FaceStretch& fs = st[s->face];
      const auto& mf = map.faces()[s->face];
      const Vec3& x0 = map.positions()[mf[0]];
      const Vec3 n = (map.positions()[mf[1]] - x0).cross(map.positions()[mf[2]] - x0).normalized();
      std::fprintf(f, "  surface normal . grid normal %.3f\n", n.dot(normal[t].normalized()));
      std::fprintf(f, "  corner (%d,%d) map face %d  sv %.4g %.4g ratio %.1f\n", r, k, s->face,
                   fs.big, fs.small, fs.big / fs.small);
    }
  }
  std::fclose(f);
}

}  // namespace ism::diagnose
