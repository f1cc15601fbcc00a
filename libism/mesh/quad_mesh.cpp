#include "mesh/quad_mesh.hpp"

namespace ism {

TriangleMesh triangulate(const QuadMesh& mesh) {
  TriangleMesh out;
  out.positions = mesh.positions;
  out.triangles.reserve(2 * mesh.quads.size());
  for (const Quad& q : mesh.quads) {
    out.triangles.push_back({q[0], q[1], q[2]});
    out.triangles.push_back({q[0], q[2], q[3]});
  }
  return out;
}

}  // namespace ism
