#pragma once
// Global re-embedding of a map onto a flat torus (a domain without cones,
// the unit square with opposite sides identified, features released).
//
// The vertex-at-a-time optimisation cannot open a strip of faces squeezed
// to nothing: every single move is blocked by the strip's neighbours (the
// mug's map at 3000 vertices: symmetric energy 11.2, and 3 more sweeps gain
// 2 %). On a flat torus the map at any level is a FlatTorusLayout: a point
// per vertex and the lattice shifts of every face's corners, which fix the
// map's homotopy class. Moving all points at once with the shifts kept is
// an unconstrained problem in R^{2n} with the symmetric energy as objective
// and a barrier at every face turning over; descend_flat_layout solves it by
// L-BFGS with the surface's Laplacian as preconditioner (mug: 11.0 -> 6.4).
//
// Also here: the linear harmonic layouts of a class (every vertex a convex
// combination of its neighbours' lifted corners). With symmetric positive
// weights such a layout embeds the torus (Gortler, Gotsman & Thurston 2006,
// discrete one-forms); with non-symmetric weights (mean-value weights,
// Floater 2003, or Yoshizawa, Belyaev & Seidel's 2004 stretch reweighting
// w_ij / σ_j) the system on a fixed lattice is only solvable with one
// vertex's equation dropped, and faces fold around it. Measured as a start
// for the descent (symmetrised mean-value weights, then reweighted by
// (σ_i + σ_j) / 2): the reweighted layouts stay 1.5–2.5 times the energy of
// the vertex-optimised map, and descending from the best of them reaches the
// same energy as descending from the map itself, at twice the cost; so the
// re-embedding starts from the map.
#include "map/inter_surface_map.hpp"
#include "map/surface_map.hpp"
#include "mesh/mean_value_weights.hpp"

#include <functional>
#include <optional>
#include <vector>

namespace ism {

/// The same weight for both directions of every M² edge (the mean of the
/// edge's four corner weights, so the edge's total is kept).
CornerWeights symmetrized(const std::vector<Triangle>& faces, const CornerWeights& weights);
/// Mean-value weights of the surface M² itself.
CornerWeights surface_mean_value_weights(const SurfaceMap& map);
/// Mean-value weights of a flat layout's triangles. Each vertex of a layout
/// with every face counter-clockwise is the mean-value combination of its
/// neighbours, so solve_flat_layout with these weights gives it back.
CornerWeights layout_mean_value_weights(const SurfaceMap& map, const FlatTorusLayout& layout);

/// The positions in which every active vertex but `fixed` is the weighted
/// average of its neighbours' lifted corners,
///   Σ_{faces t at v} Σ_m weights[t][c][m] (corner(t, c+1+m) − corner(t, c)) = 0,
/// with the shifts of `classes` (the homotopy class) kept and `fixed` left
/// at its position in `classes`. Empty if the system is singular.
std::optional<FlatTorusLayout> solve_flat_layout(const SurfaceMap& map,
                                                 const FlatTorusLayout& classes,
                                                 const CornerWeights& weights, int fixed);

/// The map's energy (SurfaceMap::energy: symmetric stretch, paper §5.2, the
/// inverse term weighted by MapOptions::inverse_stretch_weight) as a function
/// of a layout's vertex positions, with the shifts and the surface fixed,
/// and its gradient. Per face, with J the Jacobian domain -> surface, a and
/// A the face's areas in the domain and on the surface and A_M¹, A_M² the
/// totals: A c_F |J|² / 2 + a c_B |J|² / (2 det²), det = A / a,
/// c_F = A_M¹ / A_M²², c_B = A_M² / A_M¹², plus the anisotropy penalty
/// λ (A / A_M²) max(0, |J|² a / A − r₀)² (MapOptions::anisotropy_weight).
class FlatLayoutEnergy {
 public:
  explicit FlatLayoutEnergy(const SurfaceMap& map);
  /// The energy of the symmetric core's map on a flat torus
  /// (InterSurfaceMap::energy, its anisotropy penalty included) as a function of a
  /// layout of its side 1 (flat_layout(const InterSurfaceMap&, ...)).
  explicit FlatLayoutEnergy(const InterSurfaceMap& map);
  /// The terms of some faces of its side 1 only (`map_faces`), given with
  /// their corners renumbered (`faces`), side 0 flat under them.
  FlatLayoutEnergy(const InterSurfaceMap& map, const std::vector<int>& map_faces,
                   std::vector<Triangle> faces);
  /// The terms of some faces of the map only (`map_faces`), given with
  /// their corners renumbered (`faces`, indices into a layout's positions).
  FlatLayoutEnergy(const SurfaceMap& map, const std::vector<int>& map_faces,
                   std::vector<Triangle> faces);
  /// HUGE_VAL if a face is not counter-clockwise. With `gradient`, also
  /// ∂E/∂position (resized to the vertex count).
  double operator()(const FlatTorusLayout& layout, std::vector<Vec2>* gradient = nullptr) const;

 private:
  // What the terms depend on: the surface's positions and faces (those
  // numbered `map_faces`), both totals, the energy settings, and the forward
  // weight of each face (by its number in `surface_faces`).
  struct Setting {
    const std::vector<Vec3>& positions;
    const std::vector<Triangle>& surface_faces;
    double total_surface, total_domain, inverse_weight, anisotropy_weight, onset;
    std::function<double(int)> forward_weight;
  };
  FlatLayoutEnergy(const Setting& setting, const std::vector<int>& map_faces,
                   std::vector<Triangle> faces);
  FlatLayoutEnergy(const InterSurfaceMap& map, const EnergyTerms& terms,
                   const std::vector<int>& map_faces, std::vector<Triangle> faces);

  std::vector<Triangle> faces_;
  std::vector<Eigen::Matrix2d> gram_;       // Q^T Q, Q the surface edges from corner 0
  std::vector<double> forward_, backward_;  // A c_F / 2 and c_B / (2 A²)
  std::vector<double> anisotropy_;          // λ A / A_M², 0 without the penalty
  std::vector<double> surface_area_;        // A
  double onset_ = 0;                        // r₀
};

/// Lowers the symmetric energy of a layout by moving all vertices at once:
/// L-BFGS whose initial Hessian is the surface's cotangent Laplacian (the
/// Sobolev metric that the vertex-at-a-time optimisation lacks), each step
/// limited so that no face turns over (the largest step keeping every
/// face's signed area positive) and accepted only if the energy decreases
/// enough (Armijo). The shifts are kept, so the result is a layout in the
/// same class with every face counter-clockwise: a bijection of the torus.
struct FlatDescentOptions {
  int max_iterations = 3000;
  /// Stop when the last `window` iterations together gained less than
  /// window · relative_gain · energy.
  double relative_gain = 1e-6;
  int window = 20;
  int memory = 8;  // L-BFGS pairs
};
struct FlatDescentStats {
  int iterations = 0;
  double energy_before = 0, energy_after = 0;
};
FlatDescentStats descend_flat_layout(const SurfaceMap& map, FlatTorusLayout& layout,
                                     const FlatDescentOptions& options = {});
/// The same descent on part of a layout: the faces of `energy` (given as
/// `faces`, local indices) with `surface` the 3D position of each local
/// vertex; only the vertices with `movable` set move (the others fix the
/// boundary of the part).
FlatDescentStats descend_layout(const FlatLayoutEnergy& energy, const std::vector<Triangle>& faces,
                                const std::vector<Vec3>& surface, const std::vector<char>& movable,
                                FlatTorusLayout& layout, const FlatDescentOptions& options = {});

/// Moves each vertex of a turned-over face (not counter-clockwise) of the
/// layout to the centroid of its one-ring's kernel (where every face around
/// it is counter-clockwise), `passes` times at most. True if every face is
/// then counter-clockwise; the layout's shifts are kept.
bool untangle_layout(const std::vector<Triangle>& faces, FlatTorusLayout& layout, int passes = 10);

struct FlatReembeddingOptions {
  FlatDescentOptions descent;
};

struct FlatReembeddingStats {
  bool applied = false;
  double energy_before = 0, energy_after = 0;  // symmetric energy of the map
  int iterations = 0;                          // descent iterations
};

/// The global re-embedding: the map read as a flat layout, descended, and
/// installed (SurfaceMap::set_flat_layout) if that validates with a lower
/// symmetric energy. Nothing happens (applied = false) unless the map is a
/// free flat torus (SurfaceMap::is_free_flat_torus).
FlatReembeddingStats global_flat_reembedding(SurfaceMap& map,
                                             const FlatReembeddingOptions& options = {});
/// The same on the symmetric core, `domain` being side 0 (a flat
/// unit-square torus): the map read as a layout (flat_layout; faces its
/// straightening turned over are untangled first), descended,
/// its overlay rebuilt (flat_torus_overlay) and installed if that validates
/// with a lower energy (InterSurfaceMap::replace_overlay). Nothing happens
/// if the domain is not a flat torus, a vertex is pinned, or the layout
/// cannot be untangled.
FlatReembeddingStats global_flat_reembedding(InterSurfaceMap& map, const DomainGeometry& domain,
                                             const FlatReembeddingOptions& options = {});

}  // namespace ism
