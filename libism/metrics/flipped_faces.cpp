// Flipped faces of a remesh: the fold test of Praun & Hoppe's geometry
// images, usable on any triangle mesh.
#include "metrics/metrics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace ism {

std::size_t flipped_faces(const TriangleMesh& mesh) {
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

}  // namespace ism
