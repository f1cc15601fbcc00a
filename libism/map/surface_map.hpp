#pragma once
// The inter-surface map between a refining surface M² and a coarse domain M¹
// (paper §3 steps 3–4, §5), for the remeshing front ends where M¹ is an
// abstract domain and only M² is refined.
//
// Representation. Every vertex of M² is located in a face of M¹ (face and
// barycentric coordinates), or sits exactly on a vertex of M¹. Every
// half-edge of M² stores its walk over M¹: the face it starts in and the
// ordered M¹ edges it crosses. M² edges are straight inside each M¹ face and
// M¹ edges straight inside each M² face, so the overlay's pieces are convex
// and each M² face maps by one affine map into the unfolding of the M¹ faces
// it covers. The vertices of M¹ whose metric is a cone (angle sum ≠ 2π)
// stay on their feature vertices of M²; flat ones move freely when released.
// That keeps every M² one-ring inside a flat region, where the optimisation
// is an exact planar problem (the paper's fast path, here for every vertex).
#include "map/disc_layout.hpp"
#include "map/domain_geometry.hpp"
#include "pm/pm.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace ism {

struct DomainLocation {
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

/// Where an M² half-edge runs over M¹: the face it leaves its start vertex
/// in, then the M¹ edges (edge index in the current face) it crosses.
struct EdgeWalk {
  static constexpr int kMaxCrossings = 31;
  std::int32_t start_face = -1;
  std::uint8_t count = 0;
  std::uint64_t exits = 0;  // 2 bits per crossing
  int exit(int i) const { return int((exits >> (2 * i)) & 3u); }
  bool push(int k) {
    if (count >= kMaxCrossings) return false;
    exits |= std::uint64_t(k) << (2 * count++);
    return true;
  }
};

struct MapOptions {
  /// Release the features that sit on flat domain vertices during
  /// optimisation (the paper releases them for octahedral and toroidal maps).
  bool release_features = true;
  /// Weight of the inverse stretch (surface M² -> domain M¹) in the energy
  /// the optimiser lowers. 1 is the paper's symmetric stretch. Remeshing
  /// front ends, judged by the one-way stretch domain -> surface, lower it:
  /// the inverse term then only regularises (it keeps a region of the surface
  /// from being squeezed into a sliver of the domain, which folds the samples).
  double inverse_stretch_weight = 1.0;
  /// A cone's move to a neighbouring vertex is judged after re-optimising
  /// every vertex within this many edges (twice over); 0 judges it with only
  /// the vacated vertex re-optimised. Moves that pay only once the
  /// neighbourhood has followed the cone are found with 2 (bunny, regular
  /// octahedron: one-way efficiency 0.709 -> 0.716, gargoyle 0.668 -> 0.716).
  int cone_relaxation_rings = 2;
  /// The forward stretch of a face is weighted by the mean over its corners
  /// of curvature_density(full-resolution M², this) = 1 + w · κ / κ_rms:
  /// the map shrinks the surface's image where it bends, which samples it
  /// more densely there, where a piecewise-linear remesh errs most (higher
  /// PSNR for a little stretch). 0: the plain stretch.
  double curvature_weight = 0.0;
  /// Weight λ of an anisotropy penalty added per face to the energy:
  /// λ (A / A_M²) max(0, r − r₀)², A the face's surface area, r = Γ/γ + γ/Γ
  /// = |J|²/det J (Γ ≥ γ the singular values of the Jacobian domain -> surface)
  /// and r₀ = K + 1/K for K = anisotropy_threshold. 0 (default): none.
  double anisotropy_weight = 0.0;
  /// The ratio Γ/γ above which the penalty bites (K >= 1).
  double anisotropy_threshold = 10.0;
  /// How a vertex's move is found inside its one-ring: Newton steps on the
  /// energy's exact derivatives (newton_in_kernel), or two rounds of golden
  /// line searches along central-difference gradients (minimize_in_kernel;
  /// ~10x the ring evaluations, and it leaves squeezed maps stuck, which the
  /// repair tests need).
  enum class VertexStep { newton, line_search };
  VertexStep vertex_step = VertexStep::newton;
};

/// The anisotropy penalty's r₀ for a threshold K on Γ/γ: K + 1/K.
inline double anisotropy_onset(double threshold) {
  return threshold + 1.0 / threshold;
}
/// The same for MapOptions::anisotropy_threshold.
inline double anisotropy_onset(const MapOptions& o) {
  return anisotropy_onset(o.anisotropy_threshold);
}

/// Stretch measures of the map (DESIGN.md §2), from its pieces.
struct MapMeasures {
  double symmetric_efficiency = 0;
  double forward_efficiency = 0;   // one-way, domain M¹ -> surface M²
  double backward_efficiency = 0;  // one-way, surface M² -> domain M¹
};

/// How minimize_in_kernel searches along a line: golden sections only (24
/// steps, every search the same cost), or Brent's rule (a parabola through
/// the three best points where it falls well inside the bracket, a golden
/// section where not; stops once the bracket is below 1e-6 of the ring's
/// size: fewer evaluations where the energy is smooth, which is what an
/// expensive energy wants).
enum class LineSearch { golden, parabolic };

/// How far minimize_in_kernel searches: rounds of line searches (each along
/// a central-difference gradient and its perpendicular), and Brent's
/// stopping tolerance relative to the ring's size (LineSearch::parabolic).
struct KernelSearch {
  double tolerance = 1e-6;
  int rounds = 2;
  /// Brent's search (LineSearch::parabolic) starts from the step a
  /// quadratic model of the energy predicts (its gradient and Hessian from
  /// the central differences and one evaluation more), instead of a golden
  /// section of the whole kernel.
  bool model_seed = false;
  bool operator==(const KernelSearch&) const = default;
};

/// Minimises `energy` over p inside the kernel of the polygon `ring` (line
/// searches along the gradient and its perpendicular, `search.rounds` times; the gradient
/// by central differences of 1e-5 of the ring's size, along turned axes and
/// wider steps where those are not finite); p moves to the best point found.
/// Returns the energy there. `energy` may return HUGE_VAL (not a valid place).
/// A round whose best is not below `give_up_above` is the last (for callers
/// that keep a result only below a bound), and so is one that did not move
/// p (`energy` must be a function of p alone: the next would repeat it).
/// `energies`, when given, evaluates several points at once (out[k] the
/// energy at at[k], exactly as `energy` gives it; e.g. concurrently): the
/// central differences go through it.
double minimize_in_kernel(
    const std::vector<Vec2>& ring, Vec2& p, const std::function<double(const Vec2&)>& energy,
    LineSearch rule = LineSearch::golden, double give_up_above = HUGE_VAL, KernelSearch search = {},
    const std::function<void(std::span<const Vec2> at, std::span<double> out)>& energies = {});

/// Minimises a smooth energy over p inside the kernel of the polygon `ring`
/// by Newton steps (the Hessian shifted to be positive definite where it is
/// not), each backtracked until the energy drops enough (Armijo) and kept
/// inside 0.95 of the way to the kernel's edge; stops when a step moves p
/// less than 1e-9 of the ring's size or after `max_steps`. `energy(q,
/// gradient, hessian)` returns the energy at q (HUGE_VAL: not a valid place)
/// and, when the pointers are not null, its derivatives there. p moves to
/// the best point found; returns the energy there.
double newton_in_kernel(const std::vector<Vec2>& ring, Vec2& p,
                        const std::function<double(const Vec2&, Vec2*, Eigen::Matrix2d*)>& energy,
                        int max_steps = 20);

/// A flat-torus layout of M² over a domain that is the unit square with
/// opposite sides identified (domain::torus_3x3(): no cones, the vertex
/// positions of its mesh are its points in [0, 1)²). Vertex v lies at
/// `position[v]` (any representative modulo Z²); corner c of face t lies at
/// position[t[c]] + shift[t][c], a lift into the plane. The shifts fix the
/// homotopy class: the straight segment between two corners of a face is the
/// lift of that M² edge, so moving the positions and keeping the shifts
/// keeps the map's class.
struct FlatTorusLayout {
  std::vector<Vec2> position;                         // per vertex (inactive: unused)
  std::vector<std::array<Eigen::Vector2i, 3>> shift;  // per face
  Vec2 corner(const std::vector<Triangle>& faces, int t, int c) const {
    return position[faces[t][c]] + shift[t][c].cast<double>();
  }
};

/// The layout of each face of `domain` in the unit square (corner 0 in
/// [0, 1)², the others next to it), if the domain is a flat unit-square
/// torus: its mesh positions give that placement, congruent to the faces'
/// metric and counter-clockwise, with every vertex flat and total area 1.
std::optional<std::vector<std::array<Vec2, 3>>> unit_square_layouts(const DomainGeometry& domain);

/// The centroid of the kernel of a polygon (the points p for which every
/// triangle (p, ring[i], ring[i+1]) is counter-clockwise), if it is not empty.
std::optional<Vec2> kernel_centroid(const std::vector<Vec2>& ring);
/// The same for the points strictly left of every directed edge (a, b) of
/// `edges`, in any order (the box around their ends bounds the kernel).
std::optional<Vec2> kernel_centroid(const std::vector<std::array<Vec2, 2>>& edges);

/// SurfaceMap::split_next() found no valid position for the new vertex;
/// the map is unchanged.
class SplitBlocked : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SurfaceMap {
 public:
  /// The trivial map between the base mesh of `pm` and the domain: base
  /// vertex i sits on domain vertex i, base faces are the domain faces.
  SurfaceMap(const DomainGeometry& domain, const ProgressiveMesh& pm, MapOptions options = {});

  const DomainGeometry& domain() const { return domain_; }
  const MapOptions& options() const { return options_; }
  /// Per vertex of M² (full resolution): the curvature density that weighs
  /// the forward stretch (forward_weight); empty when curvature_weight is 0.
  const std::vector<double>& forward_density() const { return forward_density_; }
  /// Whether domain vertex x stays on its feature (DomainGeometry::is_fixed).
  bool is_fixed(int x) const { return domain_.is_fixed(x); }
  std::size_t n_vertices() const { return active_vertices_; }
  std::size_t n_faces() const { return faces_.size(); }
  std::size_t splits_applied() const { return next_split_; }
  std::size_t splits_total() const { return pm_.splits.size(); }
  const std::vector<Triangle>& faces() const { return faces_; }
  const std::vector<Vec3>& positions() const { return positions_; }
  /// Area of the surface at its current resolution.
  double surface_area() const { return surface_area_; }
  bool is_active(int v) const { return !vertex_faces_[v].empty(); }
  /// The faces around vertex v (empty when v is not active yet).
  const std::vector<int>& vertex_faces(int v) const { return vertex_faces_[v]; }
  bool is_pinned(int v) const { return pinned_[v] != 0; }

  /// Applies the next vertex split of the progressive mesh, embedding the
  /// new vertex inside the old one-ring. Returns the new vertex, or -1 when
  /// the surface is fully refined. Throws SplitBlocked, the map unchanged,
  /// when the split's one-ring leaves the new vertex no valid position (a
  /// neighbourhood squeezed flat: re-embed it, e.g. reembed_disc() around
  /// next_split_vertex(), and retry); std::runtime_error on other failures.
  int split_next();
  /// The vertex the next split splits (its vt), or -1 when fully refined.
  int next_split_vertex() const {
    return next_split_ < pm_.splits.size() ? pm_.splits[next_split_].vt : -1;
  }

  /// Moves vertex v inside the kernel of its one-ring to lower the symmetric
  /// energy (MapOptions::vertex_step); returns the energy decrease (0 when
  /// it did not move).
  double optimize_vertex(int v);
  /// Releases a cone of M¹ that sits on vertex v: moves it to the neighbour
  /// of v where, with v (and, see MapOptions::cone_relaxation_rings, its
  /// surroundings) re-optimised, the energy is lowest, if lower than now.
  /// Returns the energy decrease. The discrete counterpart, for cones, of the
  /// paper's optimisation of released features.
  double relocate_cone(int v);
  /// The faces around some vertices laid out in one chart of M¹, for the
  /// local re-embedding of a disc (paper §5.1): several vertices placed at
  /// once, which single-vertex moves cannot replace where a region is
  /// squeezed (each vertex there is confined by its squeezed neighbours).
  /// The given vertices that are free (not pinned, not on a cone) may move;
  /// every other corner of their faces is fixed. Nothing if the faces have
  /// no flat chart (they wrap around a cone) or the map is invalid there.
  std::optional<DiscLayout> disc_layout(const std::vector<int>& vertices) const;
  /// Moves the free vertices of a layout (taken from this map, unchanged
  /// since) to its positions: locates them in M¹ and re-traces their edges
  /// as straight segments of the chart. Kept only if every face of the
  /// layout stays valid and their energy drops by more than rounding
  /// (1e-12 relative); returns the decrease (0: the map is as it was).
  double set_disc_layout(const DiscLayout& layout);
  /// The one-ring of v (neighbours, counter-clockwise).
  std::vector<int> neighbours(int v) const;
  /// v and the vertices within `rings` edges of it, nearest first.
  std::vector<int> rings_around(int v, int rings) const;
  /// Energy of face t in its chart (HUGE_VAL without a valid chart).
  double face_energy(int t) const;
  /// How many optimisations had their whole one-ring inside one M¹ face.
  std::size_t single_face_rings() const { return single_face_rings_; }
  std::size_t optimizations() const { return optimizations_; }

  /// The energy the optimiser lowers, summed over all faces: the paper's
  /// symmetric stretch (§5.2; efficiency 2 / energy) with the inverse term
  /// weighted by MapOptions::inverse_stretch_weight.
  double energy() const;
  /// The measures over the faces t with counted[t] set (all when empty),
  /// e.g. the input surface without the caps that closed its holes: each
  /// one-way stretch normalised by the areas of those faces and of their
  /// image in M¹.
  MapMeasures measures(const std::vector<char>& counted = {}) const;

  /// The invariants of DESIGN.md §4: positive pieces on both sides, pieces
  /// tiling every face of both meshes, walks consistent from both sides and
  /// ordered, bijection. Returns the first violation.
  std::optional<std::string> validate() const;

  /// Location in M¹ of vertex v of M².
  const DomainLocation& location(int v) const { return location_[v]; }
  /// The M¹ vertex v sits on, or -1.
  int domain_vertex_at(int v) const { return at_domain_vertex_[v]; }
  /// The M² vertex on M¹ vertex x, or -1 when x lies inside a face of M².
  int vertex_at_domain_vertex(int x) const;

  /// Face t laid out in a chart of the flat region it covers: the positions
  /// of its corners and the layout of the M¹ face its first corner starts
  /// in. Returns false if the walks around t do not close (invalid map).
  struct FaceChart {
    std::array<Vec2, 3> corner;
    int start_face;
    std::array<Vec2, 3> start_layout;
    std::array<std::array<Vec2, 3>, 3> walk_layout;  // start layout of each corner's walk
  };
  bool face_chart(int t, FaceChart& chart) const;
  /// The walk over M¹ of the half-edge from corner k to corner k+1 of face t.
  const EdgeWalk& walk(int t, int k) const { return walks_[t][k]; }
  /// Symmetric energy of one face given its domain triangle in a chart.
  double face_energy(int t, const Vec2& a, const Vec2& b, const Vec2& c) const;
  /// What face_energy needs of the surface side of face t (constant while
  /// the face, the surface's area and the options are): its area, squared
  /// edge lengths and the weights of its terms.
  struct FaceTerms {
    double area_m = 0;
    std::array<double, 3> squared{};  // |e_k|², e_k opposite corner k
    double forward = 0;               // forward_weight · area_m · A_d / A_m² / 2
    double anisotropy = 0;            // anisotropy_weight · area_m / A_m
  };
  FaceTerms face_terms(int t) const;
  /// face_energy(t, a, b, c) from face_terms(t), bit for bit.
  double face_energy(const FaceTerms& terms, const Vec2& a, const Vec2& b, const Vec2& c) const;
  /// Weight of face t's forward stretch (MapOptions::curvature_weight).
  double forward_weight(int t) const;
  /// A_m / A_d²: the backward term's normalisation, the same for every face.
  double backward_scale() const {
    return surface_area_ / (domain_.total_area() * domain_.total_area());
  }

  // Flat-torus layouts (flat_torus_embedding.cpp), for a unit-square torus
  // domain with no pinned vertex.
  /// True if the domain is a flat unit-square torus (unit_square_layouts)
  /// and no vertex of M² is pinned, so every vertex may go anywhere.
  bool is_free_flat_torus() const;
  /// The current map as a flat-torus layout: every active vertex at its
  /// point of the unit square, the shifts from the faces' charts. Empty if
  /// not is_free_flat_torus() or the map is invalid.
  std::optional<FlatTorusLayout> flat_layout() const;
  /// Symmetric energy of the map a layout describes (as energy()), without
  /// installing it; HUGE_VAL if a face is not counter-clockwise.
  double layout_energy(const FlatTorusLayout& layout) const;
  /// Installs a layout: every active vertex moves to its position, every
  /// walk is re-traced as the straight segment between its face's corners.
  /// The new map is kept only if it validates and its energy() is below
  /// `max_energy`; otherwise the map is left as it was and false returned.
  bool set_flat_layout(const FlatTorusLayout& layout, double max_energy = HUGE_VAL);

 private:
  struct WalkEnd {
    int face;
    std::array<Vec2, 3> layout;
  };
  struct Ring {
    std::vector<int> faces;       // ccw around the centre
    std::vector<int> corner;      // corner of the centre in each face
    std::vector<int> vertices;    // vertices[i] = the corner after the centre in faces[i]
    std::vector<Vec2> positions;  // chart positions of vertices
    std::vector<int> end_face;    // M¹ face each walk centre -> vertices[i] ends in
    std::vector<std::array<Vec2, 3>> end_layout;
    std::vector<FaceTerms> terms;  // face_terms of faces[i]
    Vec2 centre = Vec2::Zero();
    int centre_face = -1;  // face of the centre's start layout
    std::array<Vec2, 3> centre_layout{};
    bool single_face = true;
    /// Empties the ring, keeping its lists' storage (build_ring refills it).
    void clear();
  };
  /// Lays out v's ring into `ring` (its lists' storage reused: callers that
  /// build many rings pass the same one). False where the ring is not a
  /// closed fan or a walk does not end where its vertex lies.
  bool build_ring(int v, Ring& ring, int start_vertex = -1) const;
  /// Moves the cone on v to neighbour `to` (any gain), or to the neighbour
  /// with the best positive gain when `to` < 0. The gain, or nothing when no
  /// move was made. With `estimates`, moves nothing and lists the gain of
  /// every possible move instead.
  std::optional<double> move_cone(int v, int to,
                                  std::vector<std::pair<double, int>>* estimates = nullptr);
  /// relocate_cone() with each candidate move followed by `passes`
  /// optimisations of every vertex within `rings` of v.
  double relocate_cone_relaxed(int v, int rings, int passes);
  /// What optimisation and cone moves can change around a set of vertices.
  struct RegionState {
    std::vector<int> vertices, faces;  // faces: those around the vertices
    std::vector<DomainLocation> locations;
    std::vector<int> at_domain_vertex;
    std::vector<char> pinned;
    std::vector<std::array<EdgeWalk, 3>> walks;
    std::size_t optimizations = 0, single_face_rings = 0;
  };
  RegionState save_region(const std::vector<int>& vertices) const;
  void restore_region(const RegionState& state);
  /// face_energy(t) summed over a list of faces.
  double faces_energy(const std::vector<int>& faces) const;
  /// The split of a vertex on a cone whose new vertex takes at least half
  /// of the cone's angle: the new vertex takes the cone, the old one moves.
  int split_onto_cone(const Ring& fan, std::size_t last, const std::string& where);
  /// Turns counter-clockwise around M¹ vertex x (at corner of `face` in
  /// `layout`) until the face's wedge at x holds the direction to p.
  bool wedge_containing(int x, int& face, std::array<Vec2, 3>& layout, const Vec2& p) const;
  /// The walk of the segment from vertex u (laid out by the end of a walk in
  /// `face`/`layout`) to the chart point p.
  bool trace_from(int u, int face, std::array<Vec2, 3> layout, const Vec2& p, EdgeWalk& walk,
                  WalkEnd& end) const;
  double ring_energy(const Ring& ring, int v, const Vec2& p) const;
  /// Moves v to chart point p and re-traces its edges; false (and nothing
  /// changed) if that cannot be done consistently.
  bool move_vertex(int v, const Ring& ring, const Vec2& target);
  /// Every face in the list has a closing chart with positive area.
  bool faces_are_valid(const std::vector<int>& faces) const;

  // Walks over M¹.
  WalkEnd follow(const EdgeWalk& walk, const std::array<Vec2, 3>& start_layout) const;
  bool trace(int face, std::array<Vec2, 3> layout, const Vec2& from, const Vec2& to, EdgeWalk& walk,
             WalkEnd& end) const;
  EdgeWalk reversed(const EdgeWalk& walk) const;
  std::array<Vec2, 3> start_layout_of(int v, int face) const;
  Vec2 position_in(int v, int face, const std::array<Vec2, 3>& layout) const;
  /// Rotates a layout of a face around domain vertex x, clockwise, until it
  /// reaches `target` face.
  bool rotate_to(int x, int& face, std::array<Vec2, 3>& layout, int target, bool clockwise) const;
  int fan_index(int x, int face) const;
  void set_location(int v, int face, const std::array<Vec2, 3>& layout, const Vec2& p);
  /// p moved strictly inside the face laid out as `layout` (see set_location).
  static Vec2 interior_point(const std::array<Vec2, 3>& layout, const Vec2& p);

  /// Appends a face (and its area to the surface's total).
  void add_face(const Triangle& t);
  /// 3D area of face f of M².
  double surface_face_area(int f) const;
  /// Replaces the vertex at `corner` of face f by `to`, keeping the vertex
  /// fans and the total area up to date.
  void move_corner(int f, int corner, int to);
  int corner_of(int f, int v) const;
  int face_after(int v, int x) const;
  EdgeWalk& walk(int f, int corner) { return walks_[f][corner]; }

  const DomainGeometry& domain_;
  const ProgressiveMesh& pm_;
  MapOptions options_;
  std::vector<Vec3> positions_;
  std::vector<Triangle> faces_;
  std::vector<std::array<EdgeWalk, 3>> walks_;  // walks_[f][k]: half-edge corner k -> k+1
  std::vector<std::vector<int>> vertex_faces_;
  std::vector<DomainLocation> location_;
  std::vector<int> at_domain_vertex_;
  std::vector<char> pinned_;
  std::size_t next_split_ = 0, active_vertices_ = 0;
  double surface_area_ = 0;
  std::vector<double> forward_density_;  // per M² vertex; empty: 1 (curvature_weight 0)
  std::size_t single_face_rings_ = 0, optimizations_ = 0;
};

}  // namespace ism
