#pragma once
// Quality measures for inter-surface maps and for approximating meshes:
//  - stretch of the piecewise-affine map between two triangulated surfaces
//    (Sander et al. 2001, "Texture mapping progressive meshes"), one-way and
//    symmetric (Schreiner et al. 2004, "Inter-surface mapping", §5.2);
//  - symmetric surface distance and PSNR as Hoppe's MeshDistance reports it.
//
// Stretch works on edge lengths only: a piece of the map is a triangle of the
// domain surface D and its image on the range surface M. Lengths suffice
// because the stretch is invariant to rigid motions of either triangle, and
// they are what the map core has at hand (pieces of a common overlay).
#include "mesh/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ism {

// ---------------------------------------------------------------------------
// Stretch of one affine piece.

/// Edge lengths of a triangle v0 v1 v2; l_i is the edge opposite vertex i:
/// l0 = |v1 v2|, l1 = |v2 v0|, l2 = |v0 v1|.
struct TriangleLengths {
  double l0 = 0.0, l1 = 0.0, l2 = 0.0;
};

/// Area from the lengths (Kahan's stable Heron formula; 0 when the lengths
/// violate the triangle inequality, so a flat piece is never "negative").
double triangle_area(const TriangleLengths& t);

/// Lays the triangle out in the plane: v0 at the origin, v1 on the +x axis,
/// v2 in the upper half plane (y >= 0). Lengths that barely violate the
/// triangle inequality (rounding) give y = 0 instead of a NaN.
std::array<Eigen::Vector2d, 3> triangle_layout(const TriangleLengths& t);

/// Singular values of a 2x2 Jacobian, max >= min >= 0 (Sander's Γ and γ).
struct SingularValues {
  double max = 0.0, min = 0.0;
};

/// Singular values of the Jacobian of the affine map that sends the domain
/// triangle onto the range triangle, vertex i to vertex i. A zero-area domain
/// triangle has no affine map: both values are +infinity.
/// Both triangles are laid out counter-clockwise, so a flip cannot be seen
/// from lengths; this is only a distortion measure.
SingularValues stretch_singular_values(const TriangleLengths& domain, const TriangleLengths& range);

/// Root-mean-square stretch over all directions, sqrt((Γ² + γ²) / 2).
inline double l2_stretch(const SingularValues& s) {
  return std::sqrt(0.5 * (s.max * s.max + s.min * s.min));
}
/// Worst-direction stretch Γ.
inline double linf_stretch(const SingularValues& s) {
  return s.max;
}

// ---------------------------------------------------------------------------
// Stretch summed over the pieces of a map D -> M.

/// One piece of the map: a domain triangle and its image.
struct StretchPiece {
  TriangleLengths domain;
  TriangleLengths range;
};

/// Total areas of a set of pieces on each side.
struct PieceAreas {
  double domain = 0.0, range = 0.0;
};
PieceAreas piece_areas(std::span<const StretchPiece> pieces);

/// Stretch of the map domain -> range, normalised for the global scale so that
/// any isometry up to a uniform scale scores exactly 1.
struct OneWayStretch {
  /// L2n² = (Σ A_M(T) σ²(T) / A_M) · (A_D / A_M), σ² = (Γ² + γ²) / 2. Always >= 1.
  double l2_normalized = 0.0;
  /// 1 / l2_normalized, in (0, 1]; 1 only for a conformal map with uniform area scale.
  double efficiency = 0.0;
  /// max_T Γ(T) · sqrt(A_D / A_M).
  double linf = 0.0;
};

/// Weights are RANGE areas A_M(T), as in Sander et al. 2001 and Hoppe's
/// spherical parametrization code (the stretch is averaged over the surface
/// being parametrised, not over the parameter domain).
/// Throws std::invalid_argument for no pieces or a zero total range area.
/// Any degenerate domain piece makes l2_normalized and linf infinite (efficiency 0).
OneWayStretch one_way_stretch(std::span<const StretchPiece> pieces);

/// Symmetric stretch of Schreiner et al. 2004 (§5.2): the normalised L2
/// stretch of the map plus that of its inverse.
///
/// The paper prints the per-triangle stretch as Γ² + γ² without the 1/2 of
/// Sander's (Γ² + γ²) / 2. We keep the 1/2: then each direction is >= 1, the
/// efficiency 2 / (L2n²(D->M) + L2n²(M->D)) has upper bound 1 as the paper
/// states, reached for an isometry up to scale (without the 1/2 an isometry
/// would score 0.5).
struct SymmetricStretch {
  double sum = 0.0;                  ///< L2n²(D->M) + L2n²(M->D), >= 2.
  double efficiency = 0.0;           ///< 2 / sum, in (0, 1].
  double forward_efficiency = 0.0;   ///< one_way_stretch(D->M).efficiency.
  double backward_efficiency = 0.0;  ///< one_way_stretch(M->D).efficiency.
};

/// Symmetric under swapping domain and range, invariant to scaling either side.
/// Throws std::invalid_argument for no pieces or a zero total area on either side.
SymmetricStretch symmetric_stretch(std::span<const StretchPiece> pieces);

/// Contribution of one piece to SymmetricStretch::sum, given the total areas
/// of all pieces; summing it over the pieces gives `sum` (up to rounding).
/// This is the energy the map optimiser lowers one vertex at a time.
double symmetric_piece_energy(const StretchPiece& piece, double area_domain_total,
                              double area_range_total);

// ---------------------------------------------------------------------------
// Folds.

/// Number of faces whose normal has a negative dot product with the sum of
/// the area-weighted normals of all faces sharing a vertex with it (itself
/// included): faces folded over their neighbours. Zero-area faces are never
/// flipped. The count Praun & Hoppe report for geometry images.
std::size_t flipped_faces(const TriangleMesh& mesh);

/// The test of flipped_faces(), face by face, on a mesh whose positions may
/// change: after moving vertex v, update_around(v). Keeps a reference to
/// `mesh` (which must outlive it, its connectivity unchanged) and the face
/// normals; const members may run concurrently, each with its own scratch.
class FoldTest {
 public:
  explicit FoldTest(const TriangleMesh& mesh);

  /// Whether face f is folded over the faces sharing a vertex with it.
  bool folded(std::size_t f, std::vector<std::size_t>& scratch) const;
  /// How far: the cosine between f's normal and the sum of the area-weighted
  /// normals of the faces sharing a vertex with it, negated and clamped at
  /// 0 (0: not folded, 1: turned right over). 0 for a zero-area face.
  double fold_depth(std::size_t f, std::vector<std::size_t>& scratch) const;
  /// The faces around vertex v.
  std::span<const std::size_t> faces_of(int v) const;
  /// The faces sharing a vertex with f (f included), sorted.
  void ring(std::size_t f, std::vector<std::size_t>& out) const;
  /// The faces whose test depends on where v is (those sharing a vertex
  /// with a face around v), sorted.
  void influenced(int v, std::vector<std::size_t>& out) const;
  /// Recomputes the normals of the faces around v.
  void update_around(int v);

 private:
  // The sum of the area-weighted normals of the faces sharing a vertex with f.
  Vec3 ring_normal(std::size_t f, std::vector<std::size_t>& scratch) const;
  const TriangleMesh& mesh_;
  std::vector<std::size_t> start_, faces_;  // faces around each vertex (rows)
  std::vector<Vec3> normal_;                // area-scaled
};

// ---------------------------------------------------------------------------
// Surface distance (Hoppe's MeshDistance definition of PSNR).

struct SurfaceDistanceOptions {
  /// Samples per surface are max(F_reference, F_other, min_samples).
  std::size_t min_samples = 0;
  /// Seed of the std::mt19937_64 that places the samples; same seed, same result.
  std::uint64_t seed = 1;
};

struct SurfaceDistance {
  double rms_a_to_b = 0.0;  ///< RMS distance from samples on the reference to the other mesh.
  double rms_b_to_a = 0.0;  ///< RMS distance from samples on the other mesh to the reference.
  double rms = 0.0;         ///< Pooled: sqrt of the mean squared distance over all samples.
  double hausdorff = 0.0;   ///< Largest sampled distance (an estimate from below).
  double peak = 0.0;        ///< Bounding-box diagonal of the reference.
  double psnr_db = 0.0;     ///< 20 log10(peak / rms); +infinity when rms == 0.
  std::size_t samples_a = 0, samples_b = 0;
};

/// Symmetric distance between two surfaces from area-uniform random samples,
/// exact point-to-surface distances (AABB tree). Deterministic for a given
/// seed on every platform (own uniform doubles, sequential reduction).
/// Throws std::invalid_argument when a mesh is empty, has zero area, or
/// references a missing vertex.
SurfaceDistance surface_distance(const TriangleMesh& reference, const TriangleMesh& other,
                                 const SurfaceDistanceOptions& options = {});

/// The point of a mesh nearest to a query point: its face, its barycentric
/// coordinates there (each in [0, 1], summing to 1) and its squared distance.
struct NearestPoint {
  int face = -1;
  Vec3 bary = Vec3::Zero();
  double squared_distance = 0.0;
};
/// The nearest point of `mesh` to each of `points` (AABB tree, in parallel;
/// the result depends only on the inputs). Of faces at the same distance the
/// tree's first is taken. Throws std::invalid_argument as surface_distance().
std::vector<NearestPoint> nearest_points(const TriangleMesh& mesh, const std::vector<Vec3>& points);

/// How a triangle mesh lies on a surface (the overlay of a map placed on one
/// of its two surfaces), measured with nearest points only, independently
/// of any map: each vertex's distance to the surface, each triangle's
/// orientation against the surface face nearest its centroid, and the
/// triangles' areas, signed (projected on that face's normal) and not.
/// A bijective overlay has every vertex on the surface, no flipped triangle,
/// and both area sums equal to the surface's area.
struct OverlayOnSurface {
  double largest_distance = 0;  // relative to the surface's bounding-box diagonal
  std::size_t flipped = 0;      // triangles facing against their face
  double signed_area = 0, unsigned_area = 0, surface_area = 0;
  /// Whether the three hold within `distance` (relative) and `area`
  /// (relative to the surface's area).
  bool bijective(double distance = 1e-9, double area = 1e-6) const;
};
/// Throws std::invalid_argument as nearest_points().
OverlayOnSurface overlay_on_surface(const TriangleMesh& overlay, const TriangleMesh& surface);

}  // namespace ism
