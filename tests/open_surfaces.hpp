#pragma once
// Open test surfaces cut from closed ones.
#include "mesh/triangle_mesh.hpp"

#include <functional>
#include <vector>

namespace ism::test {

/// The faces whose centroid satisfies `keep`, with the vertices they use
/// (re-indexed in order of first use).
inline TriangleMesh keep_faces(const TriangleMesh& mesh,
                               const std::function<bool(const Vec3&)>& keep) {
  TriangleMesh out;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (const Triangle& t : mesh.triangles) {
    const Vec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    if (!keep(c)) continue;
    Triangle u;
    for (int k = 0; k < 3; ++k) {
      if (index[t[k]] < 0) {
        index[t[k]] = int(out.positions.size());
        out.positions.push_back(mesh.positions[t[k]]);
      }
      u[k] = index[t[k]];
    }
    out.triangles.push_back(u);
  }
  return out;
}

}  // namespace ism::test
