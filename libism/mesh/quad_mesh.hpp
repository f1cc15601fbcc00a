#pragma once
// The indexed quad mesh of grid remeshes: positions and quads whose corners
// run counter-clockwise seen from outside, like TriangleMesh's triangles.
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <vector>

namespace ism {

using Quad = std::array<int, 4>;

struct QuadMesh {
  std::vector<Vec3> positions;
  std::vector<Quad> quads;

  std::size_t n_vertices() const { return positions.size(); }
  std::size_t n_faces() const { return quads.size(); }
};

/// Two triangles per quad, split along the diagonal from corner 0 to corner
/// 2: quad q = (a, b, c, d) gives triangles 2q = (a, b, c) and 2q+1 = (a, c, d),
/// with the quad's orientation. Same vertices, same indices.
TriangleMesh triangulate(const QuadMesh& mesh);

}  // namespace ism
