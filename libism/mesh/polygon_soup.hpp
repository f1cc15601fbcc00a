#pragma once
// Faces and positions exactly as a file gave them: polygons of any size, no
// welding, no checks. Input validation turns a soup into a TriangleMesh.
#include "mesh/triangle_mesh.hpp"

#include <vector>

namespace ism {

struct PolygonSoup {
  std::vector<Vec3> positions;
  std::vector<std::vector<int>> faces;  // 0-based indices into positions
};

}  // namespace ism
