#pragma once
// Abstract domains M¹ as triangle meshes: their connectivity, and so the
// cyclic order of neighbours around each vertex, is what the path network
// and the progressive mesh must reproduce on the surface.
#include "mesh/triangle_mesh.hpp"

namespace ism::domain {

/// Regular octahedron with vertices 0..5 at +x, -x, +y, -y, +z, -z, outward.
TriangleMesh octahedron();

/// Flat 3×3 torus: vertex 3*row + col at (col/3, row/3) of the unit square
/// with opposite sides identified; 18 right-isosceles triangles, each grid
/// cell split along the diagonal from (col, row) to (col+1, row+1).
/// Positions are the parameter points (z = 0) and only meaningful locally.
TriangleMesh torus_3x3();

}  // namespace ism::domain
