#pragma once
// Internal to partition: the pieces of trace_compatible_networks() that do
// not need the network (boundary loops, topology, automatic features).
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <vector>

namespace ism::partition_detail {

/// Boundary loops, each as its vertices in the order of the boundary
/// half-edges: no face holds loop[k] -> loop[k+1] (the surface is on the
/// left of that direction). Loops are ordered by their smallest vertex.
/// Throws PartitionError where the boundary is not a set of simple loops.
std::vector<std::vector<int>> boundary_loops(const TriangleMesh& surface);

/// Genus of a connected orientable surface with `loops` boundary loops:
/// V - E + F = 2 - 2g - loops over the vertices that faces use.
int genus_of(const TriangleMesh& surface, std::size_t loops);

/// A set of surface vertices standing for one feature when distances are
/// measured from it: the vertex itself, or a boundary loop for its centre.
using Anchor = std::vector<int>;

/// `count` new feature pairs: each time the vertex of one surface farthest
/// (geodesically) from the features there are, paired with the vertex of
/// the other whose geodesic distances to those features (scaled by the
/// square root of each surface's area) match best; of the two ways round
/// the better match is kept. Without any feature yet, the first pair is
/// each surface's vertex farthest from its area centroid. Only vertices with
/// `allowed` set are chosen.
std::vector<std::array<int, 2>> automatic_pairs(const std::array<const TriangleMesh*, 2>& surfaces,
                                                const std::array<std::vector<Anchor>, 2>& anchors,
                                                const std::array<std::vector<char>, 2>& allowed,
                                                std::size_t count);

}  // namespace ism::partition_detail
