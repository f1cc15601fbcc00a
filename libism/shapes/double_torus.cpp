// Genus-2 surface: the rounded boundary of a voxel slab with two holes.
#include "shapes/shapes.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace ism::shapes {
namespace {

using Vec3i = Eigen::Vector3i;

// 5 x 3 x 1 unit cells with through-holes at (1, 1) and (3, 1). No two solid
// cells meet only along an edge or at a corner, so the boundary is a
// 2-manifold; V - E + F = -2 for it, i.e. genus 2.
const Vec3i kSlab(5, 3, 1);
bool solid(const Vec3i& c) {
  if ((c.array() < 0).any() || (c.array() >= kSlab.array()).any()) return false;
  return !(c.y() == 1 && (c.x() == 1 || c.x() == 3));
}

// The unit square origin + [0, 1] e_u + [0, 1] e_v, with e_u x e_v outward.
struct Square {
  Vec3i origin;
  int u, v;
};

std::vector<Square> boundary_squares() {
  std::vector<Square> squares;
  for (int x = 0; x < kSlab.x(); ++x)
    for (int y = 0; y < kSlab.y(); ++y)
      for (int z = 0; z < kSlab.z(); ++z) {
        const Vec3i cell(x, y, z);
        if (!solid(cell)) continue;
        for (int a = 0; a < 3; ++a) {
          const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
          if (!solid(cell + Vec3i::Unit(a))) squares.push_back({cell + Vec3i::Unit(a), b, c});
          if (!solid(cell - Vec3i::Unit(a))) squares.push_back({cell, c, b});
        }
      }
  return squares;
}

// Every boundary square split into k x k sub-squares of two triangles, at
// the voxel positions. Vertices are keyed by their coordinates on the
// k-refined integer lattice, so squares that meet share them exactly.
struct Tessellation {
  struct Home {
    int square, i, j;  // the vertex is squares[square].origin * k + i e_u + j e_v
  };
  int k = 1;
  TriangleMesh mesh;
  std::vector<Home> home;                     // per vertex
  std::unordered_map<long long, int> vertex;  // lattice key -> vertex

  long long key(const Vec3i& p) const {
    const Vec3i size = kSlab * k + Vec3i::Ones();
    return (static_cast<long long>(p.x()) * size.y() + p.y()) * size.z() + p.z();
  }
  Vec3i lattice_point(const Square& s, int i, int j) const {
    return s.origin * k + i * Vec3i::Unit(s.u) + j * Vec3i::Unit(s.v);
  }
};

Tessellation tessellate(const std::vector<Square>& squares, int k) {
  Tessellation t;
  t.k = k;
  const Vec3 centre = 0.5 * kSlab.cast<double>();
  auto vertex = [&](int s, int i, int j) {
    const Vec3i p = t.lattice_point(squares[s], i, j);
    auto [it, inserted] = t.vertex.try_emplace(t.key(p), static_cast<int>(t.mesh.n_vertices()));
    if (inserted) {
      t.mesh.positions.push_back(p.cast<double>() / k - centre);
      t.home.push_back({s, i, j});
    }
    return it->second;
  };
  for (int s = 0; s < static_cast<int>(squares.size()); ++s)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const int q00 = vertex(s, i, j), q10 = vertex(s, i + 1, j);
        const int q11 = vertex(s, i + 1, j + 1), q01 = vertex(s, i, j + 1);
        t.mesh.triangles.push_back({q00, q10, q11});
        t.mesh.triangles.push_back({q00, q11, q01});
      }
  return t;
}

// Explicit umbrella-operator (uniform Laplacian) smoothing.
void smooth(TriangleMesh& mesh, int iterations, double lambda) {
  // In a closed oriented manifold each directed edge v -> w lies in exactly
  // one face, so this lists every neighbour once.
  std::vector<std::vector<int>> ring(mesh.n_vertices());
  for (const Triangle& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) ring[t[c]].push_back(t[(c + 1) % 3]);
  std::vector<Vec3>& x = mesh.positions;
  std::vector<Vec3> next(x.size());
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t v = 0; v < x.size(); ++v) {
      Vec3 mean = Vec3::Zero();
      for (int w : ring[v]) mean += x[w];
      mean /= static_cast<double>(ring[v].size());
      next[v] = x[v] + lambda * (mean - x[v]);
    }
    std::swap(x, next);
  }
}

// True when every face keeps a normal within 90 degrees of its voxel one.
bool no_flips(const TriangleMesh& voxels, const TriangleMesh& smoothed) {
  for (std::size_t f = 0; f < voxels.n_faces(); ++f)
    if (!(face_normal_scaled(voxels, f).dot(face_normal_scaled(smoothed, f)) > 0.0)) return false;
  return true;
}

// Smoothing runs on at most kMaxCoarse x kMaxCoarse sub-squares per voxel
// face: with kStrength k^2 steps the cost grows like k^4, too slow for big meshes.
constexpr int kMaxCoarse = 12;
// A step with edge length h = 1/k diffuses by about lambda h^2 / 2, so
// kStrength k^2 steps round every resolution alike (diffusion length about
// sqrt(lambda kStrength) voxels). Uniform Laplacian steps, not Taubin: Taubin's
// pass band is in per-edge units, so at fine resolutions it would keep the
// voxel corners.
constexpr double kLambda = 0.5, kStrength = 1.0;

TriangleMesh rounded_slab(int k, double strength) {
  const std::vector<Square> squares = boundary_squares();
  const int kc = std::min(k, kMaxCoarse);
  Tessellation coarse = tessellate(squares, kc);
  smooth(coarse.mesh, static_cast<int>(std::lround(strength * kc * kc)), kLambda);
  if (k == kc) return coarse.mesh;

  // Finer meshes: take the positions bilinearly from the smoothed coarse
  // sub-square the vertex lies in, then smooth away the creases between the
  // coarse sub-squares (a diffusion length of about one coarse edge).
  Tessellation fine = tessellate(squares, k);
  for (std::size_t v = 0; v < fine.mesh.n_vertices(); ++v) {
    const auto [s, i, j] = fine.home[v];
    const int ci = std::min(i * kc / k, kc - 1), cj = std::min(j * kc / k, kc - 1);
    const double fi = double(i) * kc / k - ci, fj = double(j) * kc / k - cj;
    auto at = [&](int di, int dj) {
      const Vec3i p = coarse.lattice_point(squares[s], ci + di, cj + dj);
      return coarse.mesh.positions[coarse.vertex.at(coarse.key(p))];
    };
    fine.mesh.positions[v] = (1 - fi) * ((1 - fj) * at(0, 0) + fj * at(0, 1)) +
                             fi * ((1 - fj) * at(1, 0) + fj * at(1, 1));
  }
  const double ratio = double(k) / kc;
  smooth(fine.mesh, static_cast<int>(std::lround(std::min(strength * k * k, ratio * ratio))),
         kLambda);
  return fine.mesh;
}

}  // namespace

TriangleMesh double_torus(int target_faces) {
  const int k =
      std::max(1, static_cast<int>(std::lround(std::sqrt(std::max(target_faces, 0) / 100.0))));
  const TriangleMesh voxels = tessellate(boundary_squares(), k).mesh;
  // Halve the smoothing in the unexpected case that it flips a face.
  for (double strength = kStrength; strength > 1e-3; strength /= 2) {
    TriangleMesh mesh = rounded_slab(k, strength);
    if (no_flips(voxels, mesh)) return mesh;
  }
  return voxels;
}

}  // namespace ism::shapes
