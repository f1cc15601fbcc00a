#pragma once
// The faces across each edge of a triangle list: the one adjacency builder
// for code that walks from face to face (charts of texture coordinates,
// boundary half-edges).
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <vector>

namespace ism {

/// The face across edge k of a face (from its corner k to corner k + 1) and
/// the corner of that face where the shared edge starts (its corner
/// `corner` is the first face's corner k + 1); face -1 on a boundary edge.
struct FaceAcross {
  int face = -1, corner = -1;
};

/// For every face, the faces across its three edges. The faces need not be
/// closed or manifold; where a directed edge is used by several faces, a
/// face across it is the last of them in the list.
std::vector<std::array<FaceAcross, 3>> faces_across(const std::vector<Triangle>& triangles);

}  // namespace ism
