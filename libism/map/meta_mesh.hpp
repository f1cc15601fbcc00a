#pragma once
// The meta-mesh of a map (DESIGN.md §4) in symmetric form: two triangle
// meshes, each with a per-face metric, each vertex located on the other mesh
// and each edge's ordered crossings with the other mesh's edges, stored the
// same way for both, so that either mesh can be read as the domain. Built
// from a SurfaceMap (which stores the map from M²'s side only), validated
// and measured from its pieces without reference to that SurfaceMap: the
// check that both sides describe one overlay, and the form in which a map
// leaves the library (write_meta_mesh).
#include "map/surface_map.hpp"
#include "mesh/edge_key.hpp"

#include <algorithm>
#include <array>
#include <compare>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ism {

/// Where a vertex of one mesh lies on the other: exactly on its vertex
/// `vertex`, or inside its face `face` at barycentric coordinates `bary`, or
/// (a boundary vertex of an open map) on a boundary edge `edge` of the other
/// mesh at parameter `t` in (0, 1) from the edge's first vertex
/// (MetaSide::edges[edge][0]); `face` and `bary` then name the same point in
/// that edge's one face (set_edge_location), so that a reader of points on
/// faces needs no case of its own.
struct MetaLocation {
  int vertex = -1;
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  int edge = -1;
  double t = 0;
  bool on_edge() const { return edge >= 0; }
};

/// A point where an edge's image on the other mesh breaks: `here` is the
/// parameter along this edge (0 at its first vertex, 1 at its second). A
/// crossing with edge `edge` (>= 0) of the other mesh at parameter `there`
/// along it (measured the same way), or a kink (`edge` == -1, paper §5.1:
/// the image bends inside face `face` of the other mesh, at barycentric
/// coordinates `bary`). Between two consecutive points the image is straight
/// in the face of the other mesh that holds it.
struct MetaCrossing {
  int edge;
  double here, there;
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  bool is_kink() const { return edge < 0; }
};

/// One mesh of a meta-mesh.
struct MetaSide {
  std::vector<Triangle> faces;
  /// The face's metric: lengths[f][k] is the edge from corner k to k+1.
  std::vector<FaceLengths> lengths;
  /// Undirected edges, first vertex < second, and face_edges[f][k] the edge
  /// from corner k to corner k+1 of face f.
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> face_edges;
  /// Per vertex (unused vertices: vertex and face -1).
  std::vector<MetaLocation> location;
  /// Per edge, ordered by `here`.
  std::vector<std::vector<MetaCrossing>> crossings;
  /// Per vertex, for a side that is an embedded surface (empty for an
  /// abstract domain): the lengths of new faces are taken from them.
  std::vector<Vec3> positions;

  std::size_t n_vertices() const { return location.size(); }
};

/// The point of an embedded side (positions given) at a location on it:
/// its vertex, or the barycentric combination of its face's corners.
inline Vec3 point_at(const MetaSide& side, const MetaLocation& at) {
  if (at.vertex >= 0) return side.positions[std::size_t(at.vertex)];
  const Triangle& t = side.faces[std::size_t(at.face)];
  return at.bary[0] * side.positions[std::size_t(t[0])] +
         at.bary[1] * side.positions[std::size_t(t[1])] +
         at.bary[2] * side.positions[std::size_t(t[2])];
}

/// `loc` on edge e of `other` at parameter t, in face f of `other` (the
/// face holding e: a boundary edge has one): edge, t, face and bary set,
/// vertex -1. Throws std::invalid_argument if e is not an edge of f.
void set_edge_location(MetaLocation& loc, const MetaSide& other, int f, int e, double t);

/// side[0] is M¹ (the domain of a SurfaceMap), side[1] M² (the surface).
struct MetaMesh {
  std::array<MetaSide, 2> side;
};

/// The meta-mesh of a map at its current resolution. M²'s metric is the
/// lengths of its 3D edges, its positions the map's; its vertex numbers are
/// the map's (vertices not yet split off are unused). Nothing if the map
/// does not validate.
std::optional<MetaMesh> meta_mesh(const SurfaceMap& map);

/// The same meta-mesh with the two sides exchanged.
MetaMesh swapped(const MetaMesh& meta);

/// Fills edges and face_edges of a side from its faces; false (nothing
/// filled) if two faces share an edge the same way, or an edge has no twin
/// and `allow_boundary` is false (with it, an edge of one face is a
/// boundary edge: a side of an open map).
bool build_edges(MetaSide& side, bool allow_boundary = false);

/// The invariants of DESIGN.md §4 checked on the meta-mesh alone, the same
/// way from both sides: every edge of one mesh runs through faces of the
/// other consistently with its crossings and end locations; crossings are
/// recorded by both edges with the same parameters and strictly ordered;
/// the pieces each face is cut into (the cells its arrangement of the other
/// mesh's edges forms, in the face's metric) have positive area and sum to
/// the face's area within 1e-9 relative; and the pieces of the two sides are
/// the same cells, each once (the map is a bijection). An open map (sides
/// with boundary edges) also needs its boundaries to correspond: each
/// boundary vertex on a boundary vertex or boundary edge of the other side,
/// each interior vertex off the other side's boundary, no break point on a
/// boundary edge. The first violation.
std::optional<std::string> validate(const MetaMesh& meta);

/// Identity of a vertex of the overlay (a meta-vertex), the same from both
/// sides: a vertex (kind 0: side a, vertex b; a vertex of one mesh on a
/// vertex of the other is side 0's), a crossing (kind 1: side 0 edge a,
/// side 1 edge b, the c-th crossing of the two along a), or a kink (kind 2:
/// side a, edge b, the c-th kink of that edge).
struct NodeKey {
  int kind = 0, a = 0, b = 0, c = 0;
  auto operator<=>(const NodeKey&) const = default;
};

/// A piece of the overlay: a cell lying in one face of each mesh, its
/// corners (meta-vertices, counter-clockwise, smallest first) laid out in
/// both faces' canonical layouts (meta_face_layout). Not always convex: the
/// map on it is affine on each triangle of triangulate_piece (meta_cut.hpp).
struct MetaPiece {
  std::vector<NodeKey> nodes;
  std::array<int, 2> face;
  std::array<std::vector<Vec2>, 2> corner;
  std::array<double, 2> area;
};
/// The pieces of a valid meta-mesh, ordered by their corners; nothing if it
/// does not validate.
std::optional<std::vector<MetaPiece>> meta_pieces(const MetaMesh& meta);
/// The layout of a face with these lengths in which pieces and barycentric
/// coordinates are given: corner 0 at the origin, corner 1 on +x,
/// counter-clockwise.
std::array<Vec2, 3> meta_face_layout(const FaceLengths& lengths);
/// A face's layout G moved rigidly so that its corners ia and ib land on pa
/// and pb (the face unfolded across that edge; |G[ib] − G[ia]| should equal
/// |pb − pa|, the rotation is scaled by their ratio otherwise); nothing if
/// G's edge has no length.
std::optional<std::array<Vec2, 3>> layout_across(const std::array<Vec2, 3>& G, int ia, int ib,
                                                 const Vec2& pa, const Vec2& pb);

/// Stretch measures over the pieces, side[0] read as the domain; nothing if
/// the meta-mesh does not validate. For a meta-mesh of a SurfaceMap they
/// agree with SurfaceMap::measures(), which works on whole M² faces.
std::optional<MapMeasures> measures(const MetaMesh& meta);
/// The same from pieces already cut (meta_pieces), side 0 the domain, over
/// the pieces in faces f of side 1 with counted[f] set (all when empty; the
/// surface's faces that are the input's, where caps close it).
MapMeasures measures(std::span<const MetaPiece> pieces, const std::vector<char>& counted = {});

/// Counts of a meta-mesh's elements.
struct MetaMeshSize {
  std::size_t crossings = 0;          // edge pairs that cross
  std::size_t vertices_inside = 0;    // vertices inside a face of the other mesh
  std::size_t shared_vertices = 0;    // vertices of both meshes at one point
  std::size_t on_boundary_edges = 0;  // vertices on a boundary edge of the other mesh
  std::size_t kinks = 0;              // kink points of either mesh's edges
  std::size_t pieces = 0;
  /// Pieces that are not a fan of their corners (triangulate_piece: a star,
  /// a constrained Delaunay or other triangulation of a non-convex piece),
  /// and the points added inside pieces (where the map bends inside a piece).
  std::size_t triangulated_pieces = 0, points_inside_pieces = 0;
};
MetaMeshSize meta_mesh_size(const MetaMesh& meta);
/// The same with the pieces already cut (meta_pieces): no second cut.
MetaMeshSize meta_mesh_size(const MetaMesh& meta, std::span<const MetaPiece> pieces);

/// Writes a meta-mesh as text (format in the README, "Meta-mesh files"),
/// every number exactly: version 3 (with records of vertices on boundary
/// edges) for an open map, else version 2 (with kink records) when any
/// edge's image has a kink, version 1 otherwise. Returns false if the file
/// cannot be written.
bool write_meta_mesh(const MetaMesh& meta, const std::filesystem::path& path);
/// Reads what write_meta_mesh wrote, version 1, 2 or 3 (validate() it before
/// use). Throws io::FileError naming the file and line of the first
/// malformed record.
MetaMesh read_meta_mesh(const std::filesystem::path& path);

}  // namespace ism
