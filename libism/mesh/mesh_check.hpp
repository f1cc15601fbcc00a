#pragma once
// Validation and light repair of an input mesh, shared by every tool.
//
// prepare_mesh() welds exactly coincident positions, triangulates polygons,
// drops faces that welding collapsed and unreferenced vertices, then measures
// the topology (components, boundary loops, manifoldness, orientability,
// genus). When the result is one orientable 2-manifold it also makes the
// orientation consistent and, for a closed surface, outward. Each repair and
// each defect is recorded in words a user can act on.
#include "mesh/polygon_soup.hpp"
#include "mesh/triangle_mesh.hpp"

#include <optional>
#include <string>
#include <vector>

namespace ism {

struct MeshCheck {
  // Sizes of the prepared mesh.
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t components = 0;
  std::size_t boundary_loops = 0;
  /// Each boundary loop (mesh/boundary.hpp order) of a manifold, orientable
  /// mesh: its vertex count and length. Empty otherwise.
  struct Loop {
    std::size_t vertices = 0;
    double length = 0;
  };
  std::vector<Loop> loops;
  long euler_characteristic = 0;
  std::optional<int> genus;  // defined for one orientable 2-manifold component
  bool orientable = true;
  double bounding_box_diagonal = 0.0;
  double area = 0.0;

  // Defects: non-finite coordinates, all faces of zero area, non-manifold
  // edges or vertices make the mesh unusable (as do no faces, several
  // components and a non-orientable surface); the rest is reported.
  std::size_t nonfinite_coordinates = 0;
  /// Every face has zero area (and `collinear`: all vertices lie on one line).
  bool zero_area = false;
  bool collinear = false;
  /// The file's faces, and the distinct positions their corners take: when
  /// welding left no face, these say why (all corners at one point, ...).
  std::size_t input_faces = 0;
  std::size_t distinct_positions = 0;
  std::size_t nonmanifold_edges = 0;
  std::size_t nonmanifold_vertices = 0;
  std::optional<int> example_nonmanifold_vertex;                // input vertex index, 0-based
  std::optional<std::pair<int, int>> example_nonmanifold_edge;  // input vertex indices
  std::size_t degenerate_faces = 0;                             // zero area, kept
  std::size_t duplicate_faces = 0;

  // Repairs done while preparing.
  std::size_t welded_vertices = 0;        // positions merged into an earlier identical one
  std::size_t triangulated_polygons = 0;  // faces with more than three corners
  std::size_t dropped_faces = 0;          // fewer than three distinct corners
  std::size_t unreferenced_vertices = 0;  // removed
  std::size_t reoriented_faces = 0;       // flipped to agree with their neighbours
  bool flipped_inward = false;            // closed surface turned outward

  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool closed() const { return boundary_loops == 0; }
  /// One orientable, connected 2-manifold with finite coordinates and faces,
  /// not all of zero area.
  bool valid_surface() const {
    return faces > 0 && nonfinite_coordinates == 0 && !zero_area && manifold() && orientable &&
           components == 1;
  }
  /// Repairs in words, e.g. "welded 79 coincident vertices".
  std::vector<std::string> repairs() const;
  /// Defects in words, the most serious first; empty for a valid surface.
  std::vector<std::string> defects() const;
  /// Things that are allowed but worth knowing (zero-area faces, ...).
  std::vector<std::string> warnings() const;
};

struct PreparedMesh {
  TriangleMesh mesh;
  MeshCheck check;
  /// Where the mesh came from: each triangle's face of the soup (a polygon
  /// gives several), and each soup position's vertex (-1: dropped).
  std::vector<int> face_origin;
  std::vector<int> position_vertex;
};

PreparedMesh prepare_mesh(const PolygonSoup& soup);

/// What a tool needs of its input surface.
struct MeshRequirements {
  std::string tool;     // named in the message, e.g. "gim-remesh"
  bool closed = false;  // no boundary
  /// What to do with an open surface when `closed` (appended after "; ").
  std::string closed_advice;
  std::optional<int> genus;  // exact genus wanted
  /// Fewest vertices the tool's domain needs, and why, e.g. 6 and "one per
  /// octahedron vertex".
  std::size_t min_vertices = 0;
  std::string min_vertices_reason;
};

/// The first unmet requirement as "5 boundary loops, gim-remesh needs a closed
/// surface" or "4 vertices, gim-remesh needs at least 6 (one per octahedron
/// vertex)", or nothing when the mesh is acceptable. A mesh that is not a
/// valid surface always fails, with its most serious defect.
std::optional<std::string> unmet_requirement(const MeshCheck& check, const MeshRequirements& needs);

}  // namespace ism
