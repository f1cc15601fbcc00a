#pragma once
// A disc of one side of a map laid out in one chart, for the local
// re-embedding of several vertices at once (paper §5.1): SurfaceMap's and
// InterSurfaceMap's disc_layout / set_disc_layout, refine/disc_relaxation.hpp.
#include "map/domain_geometry.hpp"  // Vec2
#include "mesh/triangle_mesh.hpp"   // Triangle

#include <array>
#include <vector>

namespace ism {

/// A disc in one chart, its vertices and faces renumbered locally.
struct DiscLayout {
  std::vector<int> vertex;      // the map vertex of each local vertex
  std::vector<char> free;       // per local vertex: 1 if it may move
  std::vector<Vec2> position;   // per local vertex, in the chart
  std::vector<int> face;        // the map face of each local face
  std::vector<Triangle> local;  // the faces with local vertex indices
  // SurfaceMap's only: where the map's walks from each corner of each face
  // start, in the chart (the M¹ face and its layout): the fixed ends' starts
  // when installing.
  std::vector<std::array<int, 3>> walk_face;
  std::vector<std::array<std::array<Vec2, 3>, 3>> walk_layout;
};

}  // namespace ism
