#pragma once
// Mean-value weights (Floater 2003) of triangles: the convex-combination
// weights that reproduce a planar triangulation and, on a surface, give the
// shape-preserving flattening used by the map's re-embeddings.
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <functional>
#include <vector>

namespace ism {

/// Per face t and corner c, the weights of the two edges leaving that
/// corner: weights[t][c][m] for the edge to corner (c + 1 + m) mod 3. The
/// weight of an edge seen from vertex i is the sum over its two faces.
using CornerWeights = std::vector<std::array<std::array<double, 2>, 3>>;

/// Mean-value weights of the triangles given by their corner points:
/// tan(α/2) / |e| for each edge e leaving a corner of angle α. Positive for
/// any non-degenerate triangle.
CornerWeights mean_value_weights(const std::vector<Triangle>& faces,
                                 const std::function<std::array<Vec3, 3>(int)>& corners);

}  // namespace ism
