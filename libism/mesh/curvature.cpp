#include "mesh/curvature.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ism {

namespace {

// Vertex areas (a third of each incident face) and the undirected edges.
struct Neighbourhoods {
  std::vector<double> area;
  std::vector<std::vector<int>> adjacent;
};

Neighbourhoods neighbourhoods(const TriangleMesh& mesh) {
  Neighbourhoods n{std::vector<double>(mesh.n_vertices(), 0.0),
                   std::vector<std::vector<int>>(mesh.n_vertices())};
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const Triangle& t = mesh.triangles[f];
    const double a = face_area(mesh, f) / 3;
    for (int k = 0; k < 3; ++k) {
      n.area[t[k]] += a;
      // Each interior edge is seen from both faces; one direction suffices.
      n.adjacent[t[k]].push_back(t[(k + 1) % 3]);
      n.adjacent[t[(k + 1) % 3]].push_back(t[k]);
    }
  }
  for (auto& ring : n.adjacent) {
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  }
  return n;
}

// vertex_curvature() on neighbourhoods already built.
std::vector<double> curvature_of(const TriangleMesh& mesh, const Neighbourhoods& nb,
                                 int smoothing_rings) {
  const std::size_t nv = mesh.n_vertices();
  std::vector<Vec3> normal(nv, Vec3::Zero());
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    for (int v : mesh.triangles[f]) normal[v] += face_normal_scaled(mesh, f);
  for (Vec3& n : normal)
    if (n.norm() > 0) n.normalize();

  std::vector<double> mean_square(nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (nb.adjacent[v].empty()) continue;
    double sum = 0.0;
    for (int w : nb.adjacent[v]) {
      const Vec3 e = mesh.positions[w] - mesh.positions[v];
      const double len2 = e.squaredNorm();
      if (len2 > 0) sum += std::pow(2 * normal[v].dot(e) / len2, 2);
    }
    mean_square[v] = sum / double(nb.adjacent[v].size());
  }
  for (int pass = 0; pass < smoothing_rings; ++pass) {
    std::vector<double> next(nv, 0.0);
    for (std::size_t v = 0; v < nv; ++v) {
      double weight = nb.area[v], sum = nb.area[v] * mean_square[v];
      for (int w : nb.adjacent[v]) weight += nb.area[w], sum += nb.area[w] * mean_square[w];
      next[v] = weight > 0 ? sum / weight : 0.0;
    }
    mean_square.swap(next);
  }
  for (double& k : mean_square) k = std::sqrt(k);
  return mean_square;
}

}  // namespace

std::vector<double> vertex_curvature(const TriangleMesh& mesh, int smoothing_rings) {
  return curvature_of(mesh, neighbourhoods(mesh), smoothing_rings);
}

std::vector<double> curvature_density(const TriangleMesh& mesh, double weight,
                                      int smoothing_rings) {
  if (!(weight >= 0)) throw std::invalid_argument("curvature_density: weight must be >= 0");
  std::vector<double> density(mesh.n_vertices(), 1.0);
  if (weight == 0) return density;
  const Neighbourhoods nb = neighbourhoods(mesh);
  const std::vector<double> kappa = curvature_of(mesh, nb, smoothing_rings);
  double area = 0.0, sum = 0.0;
  for (std::size_t v = 0; v < kappa.size(); ++v)
    area += nb.area[v], sum += nb.area[v] * kappa[v] * kappa[v];
  const double rms = area > 0 ? std::sqrt(sum / area) : 0.0;
  if (!(rms > 0)) return density;  // flat: nothing to prefer
  for (std::size_t v = 0; v < kappa.size(); ++v) density[v] += weight * kappa[v] / rms;
  return density;
}

}  // namespace ism
