#pragma once
// Boundary loops of a manifold triangle mesh, and the closed copy in which
// each loop is capped by a fan of triangles around a new centre vertex
// (paper §4): the tracers and the remeshers close open surfaces this way.
#include "mesh/triangle_mesh.hpp"

#include <vector>

namespace ism {

/// The boundary loops, each as its vertices in the order of the boundary
/// half-edges: no face holds loop[k] -> loop[k+1] (the surface is on the
/// left of that direction). Loops are ordered by their smallest vertex and
/// start there. Throws std::invalid_argument where the boundary is not a
/// set of simple loops (a vertex on the boundary twice, a loop that does
/// not close).
std::vector<std::vector<int>> boundary_loops(const TriangleMesh& mesh);

/// Length of the closed polygon through the loop's vertices.
double loop_length(const TriangleMesh& mesh, const std::vector<int>& loop);

/// The shape of a cap. The default is the paper's fan: every loop vertex
/// joined to the centre. With rings > 0 the fan is cut by that many
/// concentric rings of copies of the loop's vertices, ring r at r/(rings+1)
/// of the way to the centre, and lifted off the loop's plane into a dome of
/// height `height` × the loop's mean distance to its centroid (0: flat;
/// along the side the surface's orientation makes outward).
struct CapOptions {
  int rings = 0;
  double height = 0.0;
};

/// A surface with its boundary loops capped.
struct CappedMesh {
  /// The input's vertices, then one centre per loop (the loop's vertex
  /// centroid, lifted with the dome), then the ring vertices; the input's
  /// faces, then each loop's cap in loop order (the fan: face (loop[k],
  /// loop[k+1], centre)), oriented like the surface.
  TriangleMesh mesh;
  std::vector<std::vector<int>> loops;  // as boundary_loops()
  std::size_t input_vertices = 0, input_faces = 0;

  int centre(std::size_t loop) const { return int(input_vertices + loop); }
  bool is_cap_face(std::size_t f) const { return f >= input_faces; }
  bool is_centre(int v) const {
    return v >= int(input_vertices) && v < int(input_vertices + loops.size());
  }
};

/// Caps each of `loops` (boundary loops of `mesh` as boundary_loops()
/// gives them) as `options` says. The result is closed when the loops are
/// all of the mesh's boundary; it is a manifold when no two vertices of a
/// loop are joined by an edge of the mesh other than the loop's own (the
/// caller checks, e.g. when building its adjacency).
CappedMesh cap_boundary_loops(const TriangleMesh& mesh, std::vector<std::vector<int>> loops,
                              const CapOptions& options = {});

}  // namespace ism
