#pragma once
// Faces and positions exactly as a file gave them: polygons of any size, no
// welding, no checks. Input validation turns a soup into a TriangleMesh.
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <vector>

namespace ism {

struct PolygonSoup {
  std::vector<Vec3> positions;
  std::vector<std::vector<int>> faces;  // 0-based indices into positions
  /// Texture coordinates (OBJ 'vt u v') and, per face, each corner's index
  /// into them (-1: the corner has none); both empty when the file has none,
  /// else `face_texcoords` has one list per face, as long as the face.
  std::vector<std::array<double, 2>> texcoords;
  std::vector<std::vector<int>> face_texcoords;
  /// Per-position colours, RGB in [0, 1] (PLY red green blue, integers
  /// scaled by 1/255; OBJ 'v x y z r g b'): one per position, or empty when
  /// the file has none (or not for every position).
  std::vector<Vec3> colors;
};

}  // namespace ism
