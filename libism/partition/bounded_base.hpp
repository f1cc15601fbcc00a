#pragma once
// A base mesh with boundary loops made into a closed domain over which a
// surface with the same loops maps with its boundary exactly on the base's
// boundary edges (semireg on open surfaces).
//
// The map core places every surface vertex inside a domain face or on a
// domain vertex, so the surface's boundary vertices become domain vertices:
// each boundary edge of the base is subdivided at the surface boundary
// vertices between its two ends (at their arc-length fractions), the base
// faces that touch the boundary are triangulated over those points (an edge
// with several points fans them from an inner point: a domain vertex inside
// the face at an interior surface vertex near the boundary), and each loop
// is capped by a fan around a centre, as the surface's loops are by
// cap_boundary_loops(). Every boundary point and
// centre is a feature at its surface vertex and must stay there
// (`fixed`): the boundary edges' paths are then the surface's boundary edges
// themselves.
#include "mesh/boundary.hpp"
#include "mesh/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <utility>
#include <vector>

namespace ism {

struct BoundedBase {
  /// Closed: the base's vertices (same indices), then the boundary points,
  /// then the inner points, then one centre per loop (loop i of `capped`).
  TriangleMesh domain;
  /// Per domain face, the length of edge (corner k, corner k+1): the base's
  /// faces are unit equilateral triangles and their pieces keep that metric;
  /// each cap is a fan with equal spokes (flat at its centre when the
  /// boundary lengths allow).
  std::vector<std::array<double, 3>> lengths;
  /// Per domain vertex, its vertex of the capped surface.
  std::vector<int> features;
  /// Per domain vertex: 1 on a boundary loop or a centre.
  std::vector<char> fixed;
  /// Per domain face: 1 on a cap.
  std::vector<char> cap_face;
  /// Boundary points added (domain vertices on the surface's boundary that
  /// are not base vertices).
  std::size_t boundary_points = 0;
  /// Inner points added: domain vertices inside base faces, at interior
  /// surface vertices near the boundary, each fanning to the boundary
  /// points of one base boundary edge. Not fixed.
  std::size_t inner_points = 0;

  /// The edges of the caps (boundary edges and spokes), each once: their
  /// paths are the capped surface's own edges (PartitionOptions::direct_edges).
  std::vector<std::array<int, 2>> cap_edges() const;

  /// A point of base face f (barycentric coordinates, summing to 1) as a
  /// domain face and its barycentric coordinates there.
  std::pair<int, Eigen::Vector3d> locate(int f, const Eigen::Vector3d& bary) const;

  /// Per base face, the domain faces that tile it and their corners in the
  /// base face's barycentric coordinates.
  struct Piece {
    int face;
    std::array<Eigen::Vector3d, 3> corners;
  };
  std::vector<std::vector<Piece>> pieces;
};

/// The closed domain of `base` (an open manifold; base vertex i lies on
/// surface vertex features[i]) for `capped`, the surface with its loops
/// capped by fans (CapOptions{} : no rings). Throws PartitionError naming
/// the problem when the loops do not correspond: a different number of
/// loops, a base boundary vertex off the surface's boundary or an interior
/// base vertex on it, two base loops on one surface loop, a base loop
/// whose vertices follow its surface loop in another order or direction, or
/// a base boundary edge spanning both ends of a surface edge that joins two
/// vertices of its loop (an ear's tip not a base vertex: the faces between
/// would have no area in the domain).
BoundedBase bounded_base(const TriangleMesh& base, const std::vector<int>& features,
                         const CappedMesh& capped);

}  // namespace ism
