#pragma once
// The common refinement of a map's two meshes (the overlay) as one triangle
// mesh placed on either: every piece of the meta-mesh triangulated as the map
// is affine on it (triangulate_piece), so the same vertex and triangle lists
// lie on both surfaces and the map is the identity of indices between the
// two placements. The form Schmidt et al. 2020 publish maps in; itself a
// morph between the two surfaces.
#include "map/meta_mesh.hpp"

#include <array>
#include <span>
#include <vector>

namespace ism {

struct CommonRefinement {
  /// Counter-clockwise on both sides (as the meshes' faces are).
  std::vector<Triangle> triangles;
  /// Each vertex on side 0 and on side 1: first the overlay's vertices (the
  /// meta-vertices: vertices, crossings, kinks), then the points
  /// triangulate_piece added inside pieces.
  std::array<std::vector<Vec3>, 2> positions;
  /// Per triangle, the face of side 0 and of side 1 that holds it.
  std::vector<std::array<int, 2>> face;
  /// Per vertex that is a vertex of one of the meshes: {side, vertex};
  /// {-1, -1} for crossings, kinks and added points.
  std::vector<std::array<int, 2>> mesh_vertex;

  /// The refinement placed on side s as a mesh.
  TriangleMesh on_side(int s) const { return {positions[std::size_t(s)], triangles}; }
};

/// The common refinement of a valid meta-mesh from its pieces (meta_pieces).
/// Both sides must be embedded surfaces (positions given); throws
/// std::invalid_argument otherwise, or if a piece has no triangulation.
CommonRefinement common_refinement(const MetaMesh& meta, std::span<const MetaPiece> pieces);

}  // namespace ism
