#pragma once
// Path networks built by construction, without path tracing: every face of a
// domain is split into a regular grid of n^2 triangles (n = 2^levels, the
// connectivity of `levels` rounds of 1-to-4 subdivision), grid points on a
// domain edge are shared by its two faces, and the grid is embedded on the
// unit sphere (octahedron) or on a torus R = 2, r = 1 (flat 3x3 torus). The
// features are the domain's vertices, the paths its subdivided edges.
#include "domain/domain.hpp"
#include "partition/partition.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace ism::test {

enum class Embedding { sphere, torus };

struct GridOptions {
  int levels = 3;
  /// Moves grid points inside their face (or along their edge) by up to this
  /// fraction of a grid step: irregular triangles, same network.
  double irregularity = 0.0;
  /// Moves every vertex off the surface along the normal by up to this
  /// fraction of a grid step.
  double normal_jitter = 0.0;
  /// Replaces every position by a random point in [-1, 1]^3: the network is
  /// intact but the geometry is garbage, so collapses must flip faces.
  bool scramble = false;
  unsigned seed = 7;
};

struct SyntheticNetwork {
  TriangleMesh domain;
  PathNetwork network;
};

inline Vec3 torus_point(double u, double v) {
  const double theta = 2.0 * M_PI * u, phi = 2.0 * M_PI * v;
  const double rho = 2.0 + std::cos(phi);
  return {rho * std::cos(theta), rho * std::sin(theta), std::sin(phi)};
}

inline Vec3 torus_normal(double u, double v) {
  const double theta = 2.0 * M_PI * u, phi = 2.0 * M_PI * v;
  return {std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta), std::sin(phi)};
}

inline SyntheticNetwork grid_network(Embedding embedding, const GridOptions& options) {
  SyntheticNetwork out;
  out.domain = embedding == Embedding::sphere ? domain::octahedron() : domain::torus_3x3();
  const TriangleMesh& domain = out.domain;
  const int n = 1 << options.levels;
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);

  PathNetwork& net = out.network;
  TriangleMesh& surface = net.surface;

  // Point with barycentric weights (1-s-t, s, t) on face f, with its normal.
  auto embed = [&](int f, double s, double t) -> std::pair<Vec3, Vec3> {
    const Triangle& tri = domain.triangles[f];
    const double w0 = 1.0 - s - t;
    if (embedding == Embedding::sphere) {
      const Vec3 p = (w0 * domain.positions[tri[0]] + s * domain.positions[tri[1]] +
                      t * domain.positions[tri[2]])
                         .normalized();
      return {p, p};
    }
    // Unwrap the corners' (u, v) next to the first one across the seams.
    Eigen::Vector2d uv[3];
    for (int k = 0; k < 3; ++k) {
      uv[k] = domain.positions[tri[k]].head<2>();
      for (int c = 0; c < 2; ++c) {
        if (uv[k][c] - uv[0][c] > 0.5) uv[k][c] -= 1.0;
        if (uv[k][c] - uv[0][c] < -0.5) uv[k][c] += 1.0;
      }
    }
    const Eigen::Vector2d p = w0 * uv[0] + s * uv[1] + t * uv[2];
    return {torus_point(p.x(), p.y()), torus_normal(p.x(), p.y())};
  };
  const double step = embedding == Embedding::sphere ? (M_PI / 2) / n : (2 * M_PI / 3) / n;
  auto add_vertex = [&](int f, double s, double t) {
    auto [p, normal] = embed(f, s, t);
    if (options.normal_jitter > 0) p += options.normal_jitter * step * unit(rng) * normal;
    surface.positions.push_back(p);
    return static_cast<int>(surface.positions.size()) - 1;
  };

  // Features first, so that feature i is surface vertex i.
  for (std::size_t i = 0; i < domain.n_vertices(); ++i) {
    int f = 0, corner = 0;
    for (std::size_t g = 0; g < domain.n_faces(); ++g)
      for (int k = 0; k < 3; ++k)
        if (domain.triangles[g][k] == static_cast<int>(i)) f = static_cast<int>(g), corner = k;
    net.features.push_back(add_vertex(f, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0));
  }
  net.original_vertices = 0;

  // Edge points keyed by (low, high, steps from low).
  std::map<std::tuple<int, int, int>, int> edge_points;
  auto edge_point = [&](int f, int a, int b, int from_a, double s, double t, double along_s,
                        double along_t) {
    const auto key = a < b ? std::make_tuple(a, b, from_a) : std::make_tuple(b, a, n - from_a);
    auto it = edge_points.find(key);
    if (it != edge_points.end()) return it->second;
    const double shift = options.irregularity * unit(rng) / n;
    return edge_points[key] = add_vertex(f, s + shift * along_s, t + shift * along_t);
  };

  for (std::size_t fi = 0; fi < domain.n_faces(); ++fi) {
    const int f = static_cast<int>(fi);
    const auto [a, b, c] = domain.triangles[f];
    // grid[i][j]: the point (1 - i/n - j/n) A + (i/n) B + (j/n) C.
    std::vector<std::vector<int>> grid(n + 1, std::vector<int>(n + 1, -1));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double s = double(i) / n, t = double(j) / n;
        int v;
        if (i == 0 && j == 0)
          v = net.features[a];
        else if (i == n)
          v = net.features[b];
        else if (j == n)
          v = net.features[c];
        else if (j == 0)
          v = edge_point(f, a, b, i, s, t, 1, 0);
        else if (i == 0)
          v = edge_point(f, a, c, j, s, t, 0, 1);
        else if (i + j == n)
          v = edge_point(f, b, c, j, s, t, -1, 1);
        else {
          const double ds = options.irregularity * unit(rng) / n;
          const double dt = options.irregularity * unit(rng) / n;
          v = add_vertex(f, s + ds, t + dt);
        }
        grid[i][j] = v;
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        surface.triangles.push_back({grid[i][j], grid[i + 1][j], grid[i][j + 1]});
        net.face_patch.push_back(f);
        if (i + j + 1 < n) {
          surface.triangles.push_back({grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]});
          net.face_patch.push_back(f);
        }
      }
  }

  // One path per domain edge (a < b), from features[a] to features[b].
  std::map<std::pair<int, int>, bool> edges;
  for (const Triangle& t : domain.triangles)
    for (int k = 0; k < 3; ++k)
      edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}] = true;
  for (const auto& [edge, unused] : edges) {
    const auto [a, b] = edge;
    net.domain_edges.push_back({a, b});
    std::vector<int> path{net.features[a]};
    for (int k = 1; k < n; ++k) path.push_back(edge_points.at({a, b, k}));
    path.push_back(net.features[b]);
    net.paths.push_back(path);
  }
  net.original_vertices = surface.n_vertices();
  if (options.scramble)
    for (Vec3& p : surface.positions) p = {unit(rng), unit(rng), unit(rng)};
  return out;
}

}  // namespace ism::test
