#pragma once
// The map core in symmetric form (paper §3, §5; DESIGN.md §4): one MetaMesh
// that both sides refine and optimise the same way. Either side may be an
// embedded surface (metric from its 3D positions) or an abstract domain
// (metric given per face), refined by the vertex splits of its progressive
// mesh or never. Every operation edits the meta-mesh through one
// transaction: stage the changed locations and edge records, check the
// changed faces (cut_face: every record they use kept by both edges, pieces
// tiling the faces, each positive on both sides; with the region's boundary
// unchanged that makes the edit a bijection onto the same region of the
// other side), then commit or roll back; the energy of the changed pieces
// before and after gives the exact gain. validate() checks the whole map
// from both sides independently.
//
// Local operations (paper §5.1) work in a chart of a one-ring of one side:
// each edge from the centre is developed over the other side's faces
// (radii and angles of its image, the angles scaled to 2π when the image
// wraps a vertex of the other side), the other side's content inside is
// laid out in it and its edges redrawn straight, the centre (or, for a
// split, the two new vertices) placed, the new edges drawn straight, and
// their crossings mapped back by the split ratios on both edges. When the
// chart is an isometric development of the other side (no vertex of the
// other side inside, nothing bent) the energy is that of the one-ring's
// triangles in the chart (the fast path); otherwise that of every piece.
#include "map/chart_cell.hpp"
#include "map/disc_layout.hpp"
#include "map/meta_cut.hpp"
#include "pm/pm.hpp"

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ism {

/// One side of an InterSurfaceMap at the start: its base mesh, and what
/// refines it.
struct MapSideInput {
  /// Faces of the base mesh over the side's full vertex numbering; base
  /// vertex i is vertex base_vertices[i]. Base face f of side 0 and base
  /// face f of side 1 must be the same face of base vertices.
  std::vector<Triangle> base_faces;
  std::vector<int> base_vertices;
  std::size_t n_vertices = 0;
  /// An embedded surface: every vertex's position (the metric follows).
  std::vector<Vec3> positions;
  /// An abstract domain (no positions): the metric of each base face.
  std::vector<FaceLengths> base_lengths;
  /// Vertex splits to replay, in order (empty: the side never refines).
  std::vector<VertexSplit> splits;
};

/// A side from a progressive mesh (embedded surface, refined by its splits).
MapSideInput side_from_pm(const ProgressiveMesh& pm);
/// A side from an abstract domain that never refines (vertices 0..n-1).
MapSideInput side_from_domain(const TriangleMesh& domain, std::vector<FaceLengths> lengths);
/// The abstract domain of a remesher (never refines) facing the surface side
/// side_from_pm(pm): domain vertex i is the PM's base vertex i, and the faces
/// are the PM's base faces in their order and rotation, each with its domain
/// face's lengths. Throws std::invalid_argument if the vertex counts differ
/// or a base face is not a face of the domain (same orientation).
MapSideInput side_from_domain(const DomainGeometry& domain, const ProgressiveMesh& pm);

struct InterSurfaceOptions {
  /// Base vertices (the features) stay on each other; otherwise they are
  /// released and move like any vertex (continuously: a vertex of one side
  /// may leave the vertex of the other it sat on).
  bool hold_features = false;
  /// Weight of the inverse term (side 1 -> side 0) of the symmetric energy.
  double inverse_weight = 1.0;
  /// Where a moved vertex's edges bend inside a face of the other side
  /// (chart_cell.hpp). Which rule maps better depends on the pair; measured
  /// in docs/results-two-surfaces.md.
  KinkRule kinks = KinkRule::where_needed;
  /// Per vertex of side 1 (empty: none): the forward term of the energy on
  /// a face of side 1 is weighted by the mean of this over its corners
  /// (EnergyTerms::density1; the remeshers' curvature density). The
  /// measures are not weighted. Its size must be side 1's n_vertices.
  std::vector<double> forward_density;
  /// Weight λ of an anisotropy penalty on every piece (EnergyTerms; 0:
  /// none), as SurfaceMap's MapOptions::anisotropy_weight; the measures are
  /// not penalised.
  double anisotropy_weight = 0.0;
  /// The ratio of singular values K ≥ 1 past which it bites (r₀ = K + 1/K).
  double anisotropy_threshold = 10.0;
};

/// The chart the last vertex optimisation laid its one-ring out in
/// (InterSurfaceMap::last_chart): none (the ring could not be charted, or
/// the vertex is pinned), inside one face of the other side, an isometric
/// development over several, a general chart, or a large one (any kind
/// whose ring holds much of the other side, as a cone of a coarse domain's
/// does: its evaluations cost thousands of pieces each).
enum class ChartKind { none, fast, developed, general, large };
inline constexpr std::size_t kChartKinds = 5;
/// "unchartable", "fast", "developed", "general", "large".
inline const char* chart_kind_name(ChartKind kind) {
  static const char* names[kChartKinds] = {"unchartable", "fast", "developed", "general", "large"};
  return names[std::size_t(kind)];
}

/// What the local operations did (for reports and tests).
struct MapOperationStats {
  std::size_t optimizations = 0;  // optimize_vertex calls that ran
  std::size_t moves = 0;          // kept
  std::size_t fast_path = 0;      // charts inside one face of the other side
  std::size_t developed = 0;      // charts isometric over several faces
  std::size_t general = 0;        // charts with the other side's vertices or bends inside
  std::size_t rejected = 0;       // moves refused by the transaction's check
  std::size_t splits = 0;
  std::size_t splits_in_place = 0;     // splits that needed the in-place fallback
  std::size_t split_retries = 0;       // splits undone, their neighbourhood moved, tried again
  std::size_t splits_later_round = 0;  // placed after the first round of retries
  std::size_t splits_old_moved = 0;    // placed once the old vertex moved (a last attempt)
  /// Kept moves whose chart energy at the chosen place differs from the
  /// ring's energy after the move by more than 1 %, and the largest
  /// relative difference (a general chart's non-affine pieces are fanned
  /// from their corners, which the move itself changes).
  std::size_t mispredicted = 0;
  double worst_prediction = 0;
  /// Optimisations committed from a plan (InterSurfaceMap::VertexPlan):
  /// the plan held, or the vertex was optimised anew.
  std::size_t plans_held = 0, plans_stale = 0;
  std::size_t plans_untouched = 0;  // held plans known unchanged by the edit stamps (not rebuilt)
  /// Evaluations of a chart's energy by the line searches of the
  /// optimisations committed (a plan's counted where it held).
  std::size_t evaluations = 0;
  /// Evaluations of a chart's energy by the splits' placements (candidates
  /// and line searches, undone attempts too).
  std::size_t split_evaluations = 0;
};

/// How split_next places a split's new vertex. Candidates: the middle of the
/// kernel of its new ring and the middles of the faces it takes over, each
/// also drawn towards the old vertex by halving (1/2, 1/4, ..., 1/256); the
/// first `first_halvings` of those halvings are evaluated with them, the
/// rest only when none of these is valid below the energy cap. Line
/// searches (`search`) then start from the best.
struct SplitPlacement {
  int first_halvings = 8;  // 0..8
  KernelSearch search;
  bool operator==(const SplitPlacement&) const = default;
};

class InterSurfaceMap {
  friend struct InterSurfaceMapTestAccess;  // tests: the split's undo, the index

 public:
  /// The trivial map between the two base meshes (same connectivity, base
  /// vertex i of one on base vertex i of the other, no crossing). The bases
  /// may have boundaries (an open map, meta_mesh.hpp): their boundary edges
  /// then coincide. Throws
  /// std::invalid_argument if the base meshes differ, a metric is missing or
  /// the forward density has the wrong size.
  InterSurfaceMap(MapSideInput side0, MapSideInput side1, InterSurfaceOptions options = {});

  /// A map resumed at an intermediate resolution: `meta` is a valid map
  /// between the two sides' meshes after `applied[s]` of their splits, in
  /// the inputs' vertex numbering (e.g. meta_mesh() of a SurfaceMap refined
  /// part of the way); the inputs' base vertices are the features. Throws
  /// std::invalid_argument if it does not validate or does not fit.
  InterSurfaceMap(MetaMesh meta, MapSideInput side0, MapSideInput side1,
                  std::array<std::size_t, 2> applied, InterSurfaceOptions options = {});

  const MetaMesh& meta() const { return meta_; }
  const InterSurfaceOptions& options() const { return options_; }
  /// Active vertices and faces of a side at its current resolution.
  std::size_t n_vertices(int side) const { return active_[side]; }
  std::size_t n_faces(int side) const { return meta_.side[side].faces.size(); }
  bool is_active(int side, int v) const { return !index_[side].vertex_faces[v].empty(); }
  bool is_pinned(int side, int v) const { return pinned_[side][v] != 0; }
  /// Releases the features (InterSurfaceOptions::hold_features): from now on
  /// the base vertices of both sides move like any vertex. The map is not
  /// changed.
  void release_features();
  std::size_t splits_applied(int side) const { return next_split_[side]; }
  std::size_t splits_total(int side) const { return input_[side].splits.size(); }
  /// Total area of a side's faces (its metric).
  double area(int side) const { return area_[side]; }

  /// Applies the next vertex split of a side: the new vertex and the split
  /// vertex are placed inside the old one-ring. Returns the new vertex, or
  /// -1 when the side is fully refined. A split whose new vertex finds no
  /// valid place, or only places that raise the energy of the ring more
  /// than kSplitEnergyCap-fold or come nearer to the other side's vertices
  /// and edges than moves may (a nearly degenerate piece), is undone (the
  /// map exactly as before), the other side's vertices in and on the ring,
  /// the split vertex and its neighbours are optimised (retry r: its rings
  /// out to r + 1 edges away), and the split tried again, the last time
  /// accepting any valid place; that is a round of kSplitRetries retries,
  /// and the rings keep widening through kSplitRounds of them (a split the
  /// first round places is placed as with one round). After the last it
  /// throws std::runtime_error, the map still valid at the split before.
  /// A held feature (a pinned vertex) is never moved by a split. On an open
  /// map (sides with boundaries) an interior vertex whose ring reaches the
  /// boundary splits like any other; a boundary split (one wing -1) puts
  /// the new vertex in place on the other side's boundary next to vt
  /// (try_boundary_split), for the slides to place; a boundary vertex's
  /// split with both wings whose fan from vl to vr lies inside is split in
  /// place (vs an inner vertex); one whose fan runs across the boundary, a
  /// boundary split adding a face outside the boundary, and splits of a
  /// boundary vertex on a vertex of the other side throw std::runtime_error
  /// before anything changes. The
  /// candidate places are evaluated in parallel (TBB, in the calling
  /// thread's arena); the result does not depend on the number of threads.
  int split_next(int side);
  /// The energy of the faces the last split_next changed (the split
  /// vertex's old ring and the two new faces) over that of the old ring
  /// before it; 0 before any split.
  double last_split_growth() const { return last_split_growth_; }
  static constexpr int kSplitRetries = 6;
  static constexpr int kSplitRounds = 2;
  static constexpr double kSplitEnergyCap = 100;

  /// Moves vertex v of `side` over the other side to lower the energy
  /// inside the kernel of its one-ring in a chart (newton_in_kernel in a
  /// fast chart, smooth_ring; LineSearch::parabolic line searches in the
  /// others); kept only if the map stays valid and the energy drops.
  /// Returns the gain. On an open map, a ring edge on the boundary bounds
  /// the chart like any other, the other side's vertices on it fixed in
  /// it; a boundary vertex on a boundary edge of the other side slides
  /// along that edge (slide_vertex), and one on a vertex of the other side
  /// stays (gain 0).
  double optimize_vertex(int side, int v);

  /// An optimisation of one vertex worked out ahead (plan_vertex) and
  /// applied later (commit_plan). Planning only reads the map: plans of
  /// many vertices may be made concurrently, one per thread at a time,
  /// while nothing edits the map. commit_plan uses the planned place only
  /// if the vertex's chart on the map as it is then is exactly the planned
  /// one (and, for a large chart, whose search depends on it, the ring's
  /// energy too); otherwise it optimises the vertex anew. Where no edit
  /// has touched the faces of the vertex's ring since the plan was made
  /// (the map's per-face edit stamps), the planned chart is known to be
  /// that chart and is not built again, and the ring's energy and the
  /// move's proposal made in planning are used as they are (the serial
  /// commit then only applies and checks it); else the chart is built and
  /// compared.
  /// Plans committed in some order therefore give exactly what
  /// optimize_vertex in that order gives, whatever the number of threads
  /// that made them. A plan is owned by its caller and reusable (its
  /// storage kept).
  struct VertexPlan {
    struct State;
    VertexPlan();
    ~VertexPlan();
    VertexPlan(VertexPlan&&) noexcept;
    VertexPlan& operator=(VertexPlan&&) noexcept;
    int side = -1, vertex = -1;
    std::unique_ptr<State> state;
  };
  /// Plans the optimisation of v of `side` (const; see VertexPlan).
  void plan_vertex(int side, int v, VertexPlan& plan) const;
  /// Commits a plan: optimize_vertex(plan.side, plan.vertex), its search
  /// skipped where the plan still holds. Returns the gain; last_chart() and
  /// stats() as optimize_vertex leaves them (stats() also counts the plans
  /// that held).
  double commit_plan(VertexPlan& plan);
  /// The faces of side 1 around some of its vertices laid out in the chart
  /// of one face of side 0, or of two across the edge they share (the
  /// second unfolded), for the local re-embedding of a disc (paper §5.1;
  /// refine/disc_relaxation.hpp): the given vertices that are not pinned
  /// may move, every other corner of their faces is fixed. Only where every
  /// corner lies in those faces, every edge crosses at most the shared edge
  /// once (no kink), no vertex of side 0 lies inside, and each edge between
  /// fixed corners crosses where the chart's straight segment does (as at
  /// fine levels over a coarse domain, away from its vertices); nothing
  /// otherwise. As SurfaceMap::disc_layout, with walk_face and walk_layout
  /// empty.
  std::optional<DiscLayout> disc_layout(const std::vector<int>& vertices) const;
  /// Moves the free vertices of a layout from disc_layout (the map
  /// unchanged since) to its positions, one transaction: each located in
  /// the face holding it, clear of that face's edges (as a vertex move
  /// must), the edges with a free end redrawn straight in the chart (their
  /// crossings with the shared edge replaced); kept if the faces stay valid
  /// and their energy drops. Returns the decrease (0: the map unchanged).
  double set_disc_layout(const DiscLayout& disc);
  /// v and the vertices within `rings` edges of it on `side`, nearest first.
  std::vector<int> rings_around(int side, int v, int rings) const;
  /// rings_around(1, v, rings), or none as soon as those vertices lie over
  /// more than two faces of side 0 or one lies on a vertex of side 0 (they
  /// are corners of the disc: disc_layout would have no layout).
  std::vector<int> disc_around(int v, int rings) const;
  /// The chart the last optimize_vertex laid its vertex out in.
  ChartKind last_chart() const { return last_chart_; }
  /// How far optimize_vertex searches in a general chart
  /// (minimize_in_kernel's rounds and tolerance; KernelSearch{} unless set).
  void set_search(KernelSearch search) { search_ = search; }
  KernelSearch search() const { return search_; }
  /// How split_next places a new vertex (SplitPlacement{} unless set).
  void set_split_placement(SplitPlacement placement) { split_placement_ = placement; }
  SplitPlacement split_placement() const { return split_placement_; }

  /// The one-ring of v, counter-clockwise.
  std::vector<int> neighbours(int side, int v) const;
  /// The other side's vertices located inside a face of v's one-ring or
  /// on v or one of its neighbours (those on vertices in increasing order).
  std::vector<int> others_in_ring(int side, int v) const;

  /// The energy over every piece (symmetric stretch, paper §5.2, with the
  /// inverse term weighted by options().inverse_weight); efficiency 2 /
  /// energy when that weight is 1. Every face is cut afresh.
  double energy() const;
  /// The same number as energy(), from the per-face sums of the map as
  /// committed: only the faces an edit has touched since they were last
  /// summed are cut (on the caller's arena's threads).
  double cached_energy() const;
  /// Energy of the pieces of some faces of one side (each face's stretch
  /// sums cached until an edit may change them; the faces without them cut
  /// on the caller's arena's threads, the sum in the faces' order).
  double faces_energy(int side, const std::vector<int>& faces) const;
  /// What energy() sums (the sides' areas and the options' weights).
  EnergyTerms energy_terms() const;
  /// Replaces the whole overlay by `candidate`, another map between the two
  /// sides as they are now (the same faces, metrics and edges on both; e.g.
  /// a global re-embedding, map/flat_torus_overlay.hpp), if it validates,
  /// keeps every pinned vertex where it is and has a lower energy. Returns
  /// the gain (0: the map unchanged).
  double replace_overlay(MetaMesh candidate);
  /// Checks the whole map from both sides (validate(const MetaMesh&)).
  std::optional<std::string> validate() const;
  MapMeasures measures() const;
  const MapOperationStats& stats() const { return stats_; }

 private:
  struct Chart;
  struct Layout;
  struct Edit;
  struct Proposal;
  struct Move;
  /// What a split's connectivity change overwrites (to undo it).
  struct SplitUndo {
    struct VertexLists {
      int vertex;
      std::vector<int> edges, faces;
    };
    struct FaceRecord {
      int face;
      Triangle corners;
      FaceLengths lengths;
      std::array<int, 3> edges;
    };
    struct EdgeRecord {  // a spoke of the split vertex
      int edge;
      std::array<int, 2> ends, faces;
      std::vector<MetaCrossing> crossings;  // only where the split reverses them
    };
    std::size_t n_edges = 0, n_faces = 0;
    double area = 0;
    std::vector<VertexLists> vertices;
    std::vector<FaceRecord> faces;
    std::vector<EdgeRecord> edges;
    std::vector<std::pair<int, std::vector<MetaCrossing>>> other_lists;
  };

  /// The chart of v's one-ring (false if the map there cannot be
  /// developed, which leaves v where it is).
  bool build_chart(int s, int v, Chart& chart) const;
  /// The same with the ring starting at the face (v, start, *).
  /// (With `ring_only`, only the ring's faces, vertices and edges.)
  /// (With `half_disc`, build_half_disc's chart.)
  bool build_chart_from(int s, int v, int start, Chart& chart, bool ring_only = false,
                        bool half_disc = false, const Place* slide = nullptr) const;
  /// The chart of a boundary vertex v of an open map: its fan laid out as a
  /// half-disc (its two boundary edges on one line), the other side's
  /// vertices on those edges anchors on that line and v itself an anchor
  /// between them (chart.slider), at its place or, with `slide`, at that
  /// place on the other side's boundary edge that v lies on (between the
  /// slider's neighbours on the line). False if v's fan has fewer than two
  /// faces, v lies on a vertex of the other side, or the content cannot be
  /// laid out.
  bool build_half_disc(int s, int v, Chart& chart, const Place* slide = nullptr) const;
  /// optimize_vertex of a boundary vertex of an open map: v slides along
  /// the other side's boundary edge it lies on, between the other side's
  /// vertices next to it on the boundary (a golden-section search of the
  /// ring's energy), committed through apply() if it gains.
  double slide_vertex(int s, int v);
  /// optimize_vertex's search in a chart built on the map as it is (line
  /// searches given up after a round that ends above `give_up_above`).
  /// Reads only the chart and what moves do not change (connectivity,
  /// metrics, areas).
  Move search_move(const Chart& chart, Layout& layout, double give_up_above) const;
  /// The proposal of the move of the chart's vertex to p (evaluate at p
  /// with the layout's other inner vertices as they are): its predicted
  /// energy of the ring.
  double propose_move(const Chart& chart, Layout& layout, const Vec2& p, Proposal& proposal) const;
  /// optimize_vertex's end: a proposal (propose_move, `predicted` its
  /// energy) from the ring's energy `before` committed if it gains.
  double finish_move(int s, const std::vector<int>& faces, double before, const Proposal& proposal,
                     double predicted, bool smooth);
  /// faces_energy without storing what it cuts (safe beside other readers);
  /// with `sums`, each face's sums in the order of `faces` (for
  /// keep_sums). HUGE_VAL where a face cannot be cut.
  double faces_energy_read(int s, const std::vector<int>& faces,
                           std::vector<StretchSums>* sums = nullptr) const;
  /// Stores sums of these faces of side s (faces_energy_read's) as cut on
  /// the map at edit clock `clock`: they count for the faces no edit has
  /// touched since, and stay stale for the others.
  void keep_sums(int s, const std::vector<int>& faces, const std::vector<StretchSums>& sums,
                 std::uint64_t clock) const;
  /// The exact development of v's ring (v inside a face of the other side,
  /// none of its vertices inside the ring's faces): chart.w from unfolding
  /// each spoke's image, chart.boundary_breaks from unfolding the ring's
  /// edges, chart.straight_boundary; false (the chart untouched) if it cannot
  /// be made or is not star-shaped around chart.centre.
  bool developed_ring(int s, int v, Chart& chart) const;
  /// The ring's boundary in a chart from ring[first] to ring[last] (last ==
  /// the ring's size: the whole loop), with the break points of its edges
  /// where they are not on the chords between the ring's vertices.
  static std::vector<Vec2> boundary_polygon(const Chart& chart, std::size_t first,
                                            std::size_t last);
  /// The fallback of a split (after its connectivity change): vs placed a
  /// fraction eps along one of vt's old edges it took over, its new edges
  /// to vl and vr copies of vt's shifted by eps; false if that cannot be
  /// set up.
  bool split_in_place(const Chart& chart, std::size_t last, int vs, int e_vl, int e_vr, double eps,
                      Proposal& out) const;
  /// split_in_place's copy of vt's edge `old_edge` as vs's new edge
  /// `new_edge`: its records shifted by eps to the left of vt -> its other
  /// end (side 1) or to the right (-1) across the edges of t it crosses;
  /// their new records go to `other` (started from their lists). False if
  /// a shifted point leaves its face.
  bool shifted_copy(int s, int vt, int vs, int old_edge, int new_edge, double side, double eps,
                    std::map<int, std::vector<MetaCrossing>>& other,
                    std::vector<MetaCrossing>& copy) const;
  /// try_split of a boundary split (one wing -1): vs and vt both on the
  /// boundary, one new face; vs placed in place on the other side's
  /// boundary between vt and the next boundary vertex of either side.
  int try_boundary_split(int side, bool place, double cap);
  /// Each edge of vertex x of a side -> its direction around x, a full turn
  /// scaled to 2π.
  std::map<int, double> vertex_edge_angles(int side, int x) const;
  /// Writes to `layout` the chart's one-ring with its centre vertex alone
  /// inside, at the chart's centre (its lists' storage reused).
  void ring_layout(const Chart& chart, Layout& layout) const;
  /// Whether every triangle of the chart's ring is one affine map with one
  /// forward weight (evaluate then sums them without cutting): a fast chart,
  /// or a developed one unless side 0 moves under a density on side 1
  /// (whose weight varies over the faces of side 1 a triangle covers).
  bool affine_ring(const Chart& chart) const;
  /// In a chart with an affine ring, with the one inner vertex off the
  /// anchors: each triangle's
  /// energy, penalty included, as a function of that vertex (CornerStretch),
  /// in `corners`; false otherwise.
  bool smooth_ring(const Chart& chart, const Layout& layout,
                   std::vector<CornerStretch>& corners) const;
  /// The energy of the ring's faces with the inner vertices placed as in
  /// `layout` (HUGE_VAL if not valid); with `out`, what to write. Where
  /// affine_ring holds, the energy is the ring triangles' sum and the
  /// pieces are not cut here: apply()'s check is what finds an invalid
  /// proposal there.
  double evaluate(const Chart& chart, const Layout& layout, Proposal* out) const;
  /// evaluate() with `layout`'s inner vertex 0 at each point of `at`, into
  /// `out` (the same size): in parallel in the caller's arena, `grain`
  /// points per task, each task on its own copy of `layout`. The values do
  /// not depend on the number of threads.
  void evaluate_each(const Chart& chart, const Layout& layout, std::span<const Vec2> at,
                     std::span<double> out, std::size_t grain) const;
  /// Checks the changed faces of side s after an edit (see the file
  /// comment); their energy when asked. The faces are cut on the caller's
  /// arena's threads; the first problem in the faces' order is returned.
  std::optional<std::string> check_faces(int s, const std::vector<int>& faces,
                                         std::vector<StretchSums>* sums) const;
  /// The energy of stretch sums (one per face), summed in order.
  double sums_energy(const std::vector<StretchSums>& sums) const;
  /// Stages a proposal on faces of side s, checks them (check_faces) and keeps it if
  /// valid and, when `need_gain`, lower than `energy_before`; the gain, or
  /// nothing (and the map unchanged).
  std::optional<double> apply(int s, const std::vector<int>& faces, const Proposal& proposal,
                              double energy_before, bool need_gain);

  void set_location(int side, int v, const MetaLocation& loc, Edit* edit);
  void set_breaks(int side, int e, std::vector<MetaCrossing> list, Edit* edit);
  void rollback(Edit& edit);
  /// One attempt at the next split of side s: the new vertex, or -1 with
  /// the split undone. With `place` false the connectivity change is
  /// undone at once (for tests of the undo).
  /// (`cap`: placements whose ring energy exceeds cap times the ring's
  /// before the split, or that come nearer than moves may to the other
  /// side's vertices and edges, are refused; HUGE_VAL accepts any valid
  /// one.)
  int try_split(int side, bool place = true, double cap = HUGE_VAL);
  SplitUndo split_undo(int side, const Chart& chart, const VertexSplit& split) const;
  void restore(int side, const SplitUndo& undo);
  FaceLengths face_lengths(int side, const Triangle& t) const;
  /// The end of both constructors: the forward density checked against side
  /// 1 (std::invalid_argument), the index built, active vertices counted and
  /// areas summed.
  void index_and_measure();
  double face_area(int side, int f) const;
  std::vector<int> ring_faces(int side, int v) const;
  /// The same into `out` (its storage reused).
  void ring_faces(int side, int v, std::vector<int>& out) const;
  /// A boundary vertex's faces counter-clockwise from the one whose edge
  /// (v, next) is on the boundary (empty if v is not on exactly one
  /// boundary stretch).
  void fan_faces(int side, int v, std::vector<int>& out) const;
  int add_edge(int side, int u, int v);
  /// The chart of a disc of side 1 (disc_layout): one face of side 0, or
  /// two across the edge they share, the second unfolded; that edge from
  /// its first vertex to its second in the chart.
  struct DiscChart {
    std::array<int, 2> face{-1, -1};
    std::array<std::array<Vec2, 3>, 2> layout;
    int edge = -1;
    Vec2 edge_from = Vec2::Zero(), edge_to = Vec2::Zero();
    /// Where p -> q crosses the shared edge (parameter along it), if it
    /// does, clear of both segments' ends by `clearance`.
    std::optional<double> cross(const Vec2& p, const Vec2& q, double clearance) const;
  };
  /// The chart of these faces of side 1, if they lie over one face of
  /// side 0 (no edge crossing) or over two across one edge (their edges
  /// crossing only it, once at most), no vertex of side 0 inside.
  std::optional<DiscChart> disc_chart(const std::vector<int>& faces) const;

  MetaMesh meta_;
  MetaIndex index_;
  std::array<MapSideInput, 2> input_;
  InterSurfaceOptions options_;
  std::array<std::vector<char>, 2> pinned_;
  std::array<std::size_t, 2> next_split_{0, 0}, active_{0, 0};
  std::array<double, 2> area_{0, 0};
  mutable MapOperationStats stats_;
  KernelSearch search_;
  SplitPlacement split_placement_;
  /// The stretch sums of faces as the map was last committed, each with
  /// the edit clock when it was cut: valid while no edit has touched its
  /// face since (face_edit_) and no operation invalidated its whole side
  /// since (sums_all_). apply() stores the faces it changed; a split's
  /// connectivity change reaches only the faces of its side its apply()
  /// stores, or is undone, and the other side's faces under its ring
  /// (which take the new metric), which it touches (touch_under);
  /// replace_overlay invalidates both sides. With the environment
  /// variable ISM_CHECK_ENERGY_CACHE=1 at construction, every cached face
  /// is cut again when used and std::logic_error thrown if it differs
  /// (tests/map and tests/refine set it).
  struct CachedSums {
    std::uint64_t stamp = 0;
    StretchSums sums;
  };
  mutable std::array<std::vector<CachedSums>, 2> sums_cache_;
  /// When each face's content last changed, on a clock that every edit
  /// advances: a face of a side is touched when its edges' break lists,
  /// the other side's vertices inside it or on its corners, or its corners'
  /// locations change, and when an edit of the other side changes a break
  /// list or a location that lies in it (set_location, set_breaks: old and
  /// new places both). Operations that change connectivity or many faces
  /// (a split with its undoing, replace_overlay) touch every face
  /// (`edit_all_`). A chart of v of a side reads only the faces of v's
  /// ring and what lies in them, so a plan whose ring faces were not
  /// touched since it was made still holds (commit_plan). With
  /// ISM_CHECK_PLANS=1 at construction, commit_plan also builds every
  /// chart it takes as unchanged and throws std::logic_error if it differs
  /// (tests/refine set it).
  std::array<std::vector<std::uint64_t>, 2> face_edit_;
  std::uint64_t edit_clock_ = 1, edit_all_ = 1;
  bool check_plans_ = false;
  void touch_face(int side, int f);
  void touch_vertex(int side, int v);                      // the faces around v
  void touch_location(int side, const MetaLocation& loc);  // on the other side
  void touch_edge(int side, int e);                        // the faces beside e
  /// The other side's faces where the records of a break list of `side`
  /// lie (a crossed edge's faces, a kink's face).
  void touch_crossings(int side, const std::vector<MetaCrossing>& list);
  /// Touches the faces of the other side that overlap these faces of
  /// `side` (those holding their corners or the other side's vertices on
  /// or inside them, and those their edges cross or bend in): the faces
  /// whose pieces a change of these faces' connectivity or metric reaches.
  void touch_under(int side, const std::vector<int>& faces);
  /// Touches every face of both sides; the cached energies of the sides
  /// listed go stale too.
  void touch_all(std::initializer_list<int> stale_sums);
  /// Whether no face of `faces` of `side` changed after clock value `since`.
  bool untouched_since(int side, const std::vector<int>& faces, std::uint64_t since) const;
  std::array<std::uint64_t, 2> sums_all_{1, 1};
  bool sums_valid(int side, int f, const CachedSums& entry) const;
  bool check_cache_ = false;
  std::string last_refusal_;  // why the transaction last refused an edit (diagnostics)
  double last_split_growth_ = 0;
  ChartKind last_chart_ = ChartKind::none;
  /// Tests only (InterSurfaceMapTestAccess): split_next's next this many
  /// attempts find no place without trying, so the retries and the later
  /// rounds run on maps whose splits would all be placed at once.
  int refused_split_attempts_ = 0;
};

}  // namespace ism
