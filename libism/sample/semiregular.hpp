#pragma once
// Semi-regular remeshes (paper §6.2, DESIGN.md §5 "Base mesh"): every face of
// a base mesh sampled on the barycentric grid of N = 2^levels subdivisions,
// the samples shared along base edges, so the result is watertight and has
// exact subdivision connectivity (levels times 1-to-4 splits of the base).
#include "mesh/triangle_mesh.hpp"
#include "sample/unfold.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace ism {

/// Where a vertex of semiregular_mesh() is sampled: grid point (i, j) of
/// base face `face`, i.e. weights ((N-i-j)/N, i/N, j/N) of its corners 0, 1,
/// 2. A vertex shared by several faces (base vertex, base edge vertex) is
/// sited on the first face that holds it; face -1 for a base vertex on no face.
struct SemiregularSite {
  int face = -1;
  int i = 0, j = 0;
};

/// The connectivity of semiregular_mesh() and where each vertex is sampled,
/// without sampling. Throws std::invalid_argument as semiregular_mesh().
struct SemiregularLayout {
  int levels = 0;
  std::vector<SemiregularSite> sites;  // one per output vertex
  /// A vertex inside a base edge of two faces: its grid point on the second
  /// face; face -1 for any other vertex.
  std::vector<SemiregularSite> second_sites;
  /// Per base face, whether its edge k (corner k to k + 1) is on the base's
  /// boundary (held by that face alone): bit k.
  std::vector<unsigned char> boundary_edges;
  std::vector<Triangle> triangles;
  /// Barycentric weights of grid point (i, j), fractional points included.
  Eigen::Vector3d weights(double i, double j) const;
};
SemiregularLayout semiregular_layout(const TriangleMesh& base, int levels);

/// The semi-regular mesh of `base` at `levels` (0..10) subdivision levels.
/// `point(f, bary)` gives the position of the base-face point with
/// barycentric coordinates `bary` (weights of corners 0, 1, 2 of
/// base.triangles[f]); it is called exactly once per output vertex.
///
/// Vertex numbering, with N = 2^levels, V/E/F the base's vertex/edge/face
/// counts:
///  - [0, V): vertex i is base vertex i, sampled at the corner of the first
///    face (lowest index) that holds it.
///  - [V, V + E(N-1)): N-1 vertices per base edge. Edges are numbered in order
///    of first appearance when scanning faces f = 0.. and their edges
///    (corner k, corner k+1), k = 0, 1, 2. Edge e with endpoints a < b owns
///    vertices V + e(N-1) + j - 1, j = 1..N-1, at parameter j/N from a to b,
///    sampled once, on the face where the edge first appears.
///  - then (N-1)(N-2)/2 interior vertices per face, faces in order; in face f
///    the point with weights ((N-i-j)/N, i/N, j/N), i, j >= 1, i + j <= N-1,
///    comes in row-major order (j outer, i inner).
/// Triangles: N² per base face, faces in order, counter-clockwise as the
/// base face. A closed manifold base gives a closed manifold result of the
/// same genus; a base with boundary loops, a result with as many (each base
/// boundary edge split into N edges).
TriangleMesh semiregular_mesh(
    const TriangleMesh& base, int levels,
    const std::function<Vec3(int face, const Eigen::Vector3d& bary)>& point);

/// Undoes one level of 1-to-4 subdivision from connectivity alone. The first
/// `base_vertices` vertices of `fine` must be vertices of the coarse mesh
/// (e.g. the base vertices of semiregular_mesh()); the other coarse vertices
/// are found by walking straight through the valence-6 edge vertices (on a
/// boundary edge, through its edge vertex's open fan of four).
/// Succeeds only when `fine` is exactly the 1-to-4 split of a triangle mesh:
/// then `coarse` holds that mesh, its vertices being the even vertices of
/// `fine` in increasing index order (so the first `base_vertices` keep their
/// indices), with their positions. Returns false otherwise.
bool unsubdivide(const TriangleMesh& fine, std::size_t base_vertices, TriangleMesh& coarse);

/// Re-samples the vertices of folded triangles (unfold_samples(), unfold.hpp)
/// of `mesh`, made by semiregular_mesh(base, levels, point), at nearby points
/// of the base faces holding them: a quarter, half or three quarters of the
/// way to one of their grid neighbours. A vertex on the base's boundary (a
/// base boundary vertex, or a vertex inside a base boundary edge) moves only
/// along a base boundary edge, so it stays on the boundary; base vertices
/// move like the others. A move is kept when it lowers the number of folded
/// triangles it can change; rounds over the remaining folds repeat while any
/// move is kept (at most `max_rounds`). The connectivity is unchanged and
/// every vertex stays a value of `point`. Folds wider than these moves (a
/// crease of the mapped surface sharper than the grid) may stay. `point` is
/// called again for each tried position; one that throws is not tried.
/// Throws std::invalid_argument when `mesh` is not the semi-regular mesh of
/// `base` at `levels` (vertex or face count).
UnfoldReport unfold_semiregular(
    const TriangleMesh& base, int levels,
    const std::function<Vec3(int face, const Eigen::Vector3d& bary)>& point, TriangleMesh& mesh,
    int max_rounds = 8);

}  // namespace ism
