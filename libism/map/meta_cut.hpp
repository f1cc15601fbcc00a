#pragma once
// The overlay of a meta-mesh, face by face: each face of either side cut by
// the other side's edges into pieces (the cells of a planar graph in the
// face's own metric), each piece with its corners in both faces' layouts,
// triangulated the same way in both so that the map on it is piecewise
// affine, and its symmetric stretch. The global validate(), measures and
// queries and every local operation of the map core are built on these.
#include "map/meta_mesh.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace ism {

/// Views of one side of a meta-mesh derived from its faces and locations,
/// for local queries. They go stale when faces, edges or locations change;
/// whoever edits the meta-mesh keeps them current (InterSurfaceMap does).
struct MetaSideIndex {
  /// Per edge: the face in which it runs from edges[e][0] to edges[e][1]
  /// (counter-clockwise), and the other face; -1 where there is none.
  std::vector<std::array<int, 2>> edge_faces;
  /// Per vertex: its edges.
  std::vector<std::vector<int>> vertex_edges;
  /// Per vertex: its faces.
  std::vector<std::vector<int>> vertex_faces;
  /// Per face: the vertices of the other side located inside it.
  std::vector<std::vector<int>> residents;
  /// Per vertex: the vertices of the other side located on it.
  std::vector<std::vector<int>> lodgers;
  /// Whether the side has boundary edges (an open map). Only then is
  /// on_edge kept (InterSurfaceMap maps closed sides and keeps it empty).
  bool open = false;
  /// Per edge: the vertices of the other side located on it (an open map's
  /// boundary edges), by increasing parameter from the edge's first vertex.
  std::vector<std::vector<int>> on_edge;
  /// Undirected edge key (undirected_edge_key) -> edge.
  std::unordered_map<std::uint64_t, int> edge_of;

  int edge(int u, int v) const {
    auto it = edge_of.find(undirected_edge_key(u, v));
    return it == edge_of.end() ? -1 : it->second;
  }
  /// Whether edge e has one face only (a side of an open map).
  bool is_boundary(int e) const { return edge_faces[e][0] < 0 || edge_faces[e][1] < 0; }
};
using MetaIndex = std::array<MetaSideIndex, 2>;

/// The views of both sides (edges must be built, see build_edges).
MetaIndex build_index(const MetaMesh& meta);
/// Adds or removes vertex v of `side` (located in a face of the other side)
/// in that face's residents.
void add_resident(MetaIndex& index, int side, int v, int face);
void remove_resident(MetaIndex& index, int side, int v, int face);
/// The same for v located on boundary edge e of the other side (its
/// on_edge list, kept by parameter; the side of e must be open).
void add_on_edge(MetaIndex& index, const MetaMesh& meta, int side, int v, int e);
void remove_on_edge(MetaIndex& index, int side, int v, int e);
/// The same for v located on vertex x of the other side (its lodgers).
void add_lodger(MetaIndex& index, int side, int v, int x);
void remove_lodger(MetaIndex& index, int side, int v, int x);

/// Where a meta-vertex lies on one side: on a vertex, on an edge (at
/// parameter t from its first vertex) or inside a face (barycentric).
struct Place {
  enum Kind : int { vertex, edge, face } kind = vertex;
  int index = -1;
  double t = 0;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  bool operator==(const Place&) const = default;
};

/// A meta-vertex: its key and where it lies on each side.
struct MetaNode {
  NodeKey key;
  std::array<Place, 2> place;
  bool operator==(const MetaNode&) const = default;
};

/// The meta-vertex of vertex v of `side`.
MetaNode vertex_node(const MetaMesh& meta, int side, int v);
/// The meta-vertex of the i-th break point of edge e of `side`; nothing if
/// a crossing is not recorded by the other edge too.
std::optional<MetaNode> break_node(const MetaMesh& meta, int side, int e, int i);
/// The faces of `side` that a place touches (the faces around a vertex,
/// the two faces of an edge, or the face).
void place_faces(const MetaMesh& meta, const MetaIndex& index, int side, const Place& place,
                 std::vector<int>& faces);
/// The position of a place in the canonical layout of face f of `side`
/// (meta_face_layout); nothing if the place is not on that face.
std::optional<Vec2> place_in_face(const MetaMesh& meta, int side, int f, const Place& place);
/// The same in a layout of face f the caller already has (`layout` must be
/// meta_face_layout of its lengths): for placing many points in one face.
std::optional<Vec2> place_in_face(const MetaMesh& meta, int side, int f,
                                  const std::array<Vec2, 3>& layout, const Place& place);

/// One face cut into pieces.
struct FaceCut {
  std::optional<std::string> error;
  std::vector<MetaPiece> pieces;
};

/// Cuts face f of `side` by the other side's edges. Each piece gets its
/// face on the other side and its corners there; a piece that is not
/// positive on the other side, pieces that do not tile the face (1e-9
/// relative), or records that do not fit (an edge of the other side
/// crossing this face's edges where its own records say otherwise) give an
/// error naming the face. Of each edge of the other side entering the face
/// only the points next to the face are visited (found by the records of
/// the face's edges): the cost follows the face's content, not the length
/// of those edges' lists.
FaceCut cut_face(const MetaMesh& meta, const MetaIndex& index, int side, int f);

/// Cells of a planar graph in one list: cell i is nodes[start[i]] ..
/// nodes[start[i + 1] - 1], counter-clockwise. Kept by callers between
/// calls, so that cutting allocates nothing once it has grown.
struct PlanarCells {
  std::vector<int> nodes;
  std::vector<int> start{0};
  std::size_t size() const { return start.size() - 1; }
  std::span<const int> operator[](std::size_t i) const {
    return {nodes.data() + start[i], nodes.data() + start[i + 1]};
  }
};

/// The bounded cells of a planar straight-line graph (positions, segments
/// between them), each as its nodes counter-clockwise, with positive area,
/// into `cells` (replacing what it held); false (and `error` set) if a node
/// has fewer than two segments, two segments join the same nodes, the cells
/// do not close, or there is not exactly one unbounded cell.
bool planar_cells(const std::vector<Vec2>& position,
                  const std::vector<std::array<int, 2>>& segments, PlanarCells& cells,
                  std::string* error = nullptr);

/// A triangulation of a piece valid on both sides: triangles index
/// points[s], the piece's corners first, then points added inside it (the map
/// is affine on each triangle, so an added point is a kink of the map).
struct PieceTriangulation {
  std::vector<std::array<int, 3>> triangles;  // empty: none found
  std::array<std::vector<Vec2>, 2> points;    // corners, then added points, per side
  bool added = false;                         // points were added inside the piece
  bool cdt = false;                           // not a fan or a star (counted by the map)
};

/// A triangulation of a piece, counter-clockwise and of positive area in
/// both layouts: the fan whose worst triangle is best when one works (always
/// for a piece convex on both sides without collinear corners); else a star
/// around the centroid of each side's kernel if it works on both sides; else
/// the constrained Delaunay triangulation of one side's polygon if it is
/// valid on the other; else the triangulation on the corners whose worst
/// triangle is best; else a compatible triangulation with added points (the
/// two polygons' triangulations overlaid on a common convex drawing), which
/// exists for any two simple counter-clockwise polygons. Empty only if
/// neither of those is valid (e.g. a polygon that is not simple). Depends
/// only on the piece's corners, so it is the same from whichever side the
/// piece was cut.
PieceTriangulation triangulate_piece(const MetaPiece& piece);

/// The weights of the energy the map core lowers: symmetric stretch (paper
/// §5.2), side 0 read as the domain, with the inverse term (side 1 -> side
/// 0) weighted by `inverse_weight` and the forward term of a piece by
/// `forward_weight` (e.g. a curvature density of side 1's face; 1 if empty).
struct EnergyTerms {
  double area0 = 1, area1 = 1;  // total areas of the sides
  double inverse_weight = 1;
  /// Per vertex of side 1 (empty: all 1): the forward term of a piece is
  /// weighted by the mean of this over the corners of its face of side 1
  /// (a curvature density, MapOptions::curvature_weight).
  std::span<const double> density1 = {};
  /// That weight for face f of side 1.
  double forward_weight(const MetaSide& side1, int f) const {
    if (density1.empty()) return 1.0;
    const Triangle& t = side1.faces[f];
    return (density1[t[0]] + density1[t[1]] + density1[t[2]]) / 3;
  }
  /// Weight λ of an anisotropy penalty (0: none) and its onset r₀: an
  /// affine triangle of area a₁ on side 1 whose map has singular values
  /// Γ ≥ γ adds λ (a₁ / area1) max(0, Γ/γ + γ/Γ − r₀)² (SurfaceMap's
  /// penalty, MapOptions::anisotropy_weight, per piece).
  double anisotropy_weight = 0, anisotropy_onset = 0;
  /// That penalty for Γ/γ + γ/Γ = `ratio` (|J|²_F / det J of the map either
  /// way) over an area a1 of side 1.
  double anisotropy(double ratio, double a1) const {
    const double excess = std::max(0.0, ratio - anisotropy_onset);
    return anisotropy_weight * (a1 / area1) * excess * excess;
  }
};

/// The stretch of one affine triangle, corners p on side 0 and q on side 1
/// (both counter-clockwise), from the corners themselves (no edge lengths:
/// slivers keep their digits): forward = area on side 1 · σ²(side 0 -> 1),
/// backward = area on side 0 · σ²(side 1 -> 0), σ² = |J|²_F / 2; both
/// HUGE_VAL (areas 0) if either layout is not positive. The one definition
/// behind triangle_energy and the measures of a meta-mesh.
struct StretchTerms {
  double forward, backward;
  double area0, area1;
};
StretchTerms triangle_stretch_terms(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q);

/// The linear part of the affine map taking triangle `from` to triangle `to`
/// (corner k to corner k); `from` must not be degenerate.
Eigen::Matrix2d affine_linear_part(const std::array<Vec2, 3>& from, const std::array<Vec2, 3>& to);

/// The stretch terms of many triangles that one common affine map A takes
/// from a plane (a chart) to one side, each with its own affine map B from
/// the chart to the other side (`add`: its corners c in the chart and B·c
/// on the other side, both counter-clockwise); `evaluate` gives, for any A
/// of positive determinant, the sums {X, Y} of X = area_B·σ²(A-side ->
/// B-side) and Y = area_A·σ²(B-side -> A-side) over them: the terms of
/// triangle_stretch_terms of the triangles (A·c, B·c), summed, up to
/// rounding. With the A-side as side 0, forward = X, backward = Y.
struct StretchMoments {
  double area = 0;   // in the chart
  double m[3] = {};  // Σ area_c·det B·BᵀB (symmetric: xx, xy, yy)
  double n[3] = {};  // Σ area_c·B⁻¹B⁻ᵀ
  /// False (nothing added) if either triangle is not positive.
  bool add(const std::array<Vec2, 3>& c, const std::array<Vec2, 3>& b);
  /// Adds another's sums, scaled by `share` (a part of its triangles), its
  /// m sums also by `m_weight`.
  void add(const StretchMoments& other, double share = 1, double m_weight = 1);
  std::array<double, 2> evaluate(const Eigen::Matrix2d& A) const;
  bool operator==(const StretchMoments&) const = default;
};

/// The energy of stretch terms (of one triangle, or summed over many):
/// forward_weight·A₀/A₁²·forward + inverse_weight·A₁/A₀²·backward, each
/// one-way term normalised by both sides' total areas (paper §5.2). No
/// anisotropy penalty (it does not sum over triangles): triangle_energy and
/// piece_energy add it.
double stretch_energy(double forward, double backward, const EnergyTerms& terms,
                      double forward_weight = 1);
/// Energy of one affine triangle: corners p on side 0, q on side 1 (both
/// counter-clockwise), its anisotropy penalty included; HUGE_VAL if either
/// is not positive.
double triangle_energy(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q,
                       const EnergyTerms& terms, double forward_weight = 1);
/// triangle_energy as a function of one corner x of one side's triangle,
/// the rest fixed (a vertex moved in a chart whose triangles on the other
/// side are fixed): with N the cotangent sum (4 a₀² |J|²_F, symmetric in the
/// two triangles), a the moving triangle's area and B the fixed one's, the
/// stretch is N/8 · (α/a² + β·a), α and β from B and the terms; the
/// anisotropy penalty, with r = N / (4 B a) (= Γ/γ + γ/Γ), is
/// (κ₀ + κ₁·a) · max(0, r − r₀)² (its area factor is B's or a's, by which
/// side is side 1). `value` gives the sum (HUGE_VAL where the moving
/// triangle is not positive), `derivatives` its gradient and Hessian in x
/// too (the penalty is C¹: its Hessian jumps where r crosses r₀). Built by
/// corner_stretch.
struct CornerStretch {
  Vec2 a, b;          // the moving triangle's other corners, counter-clockwise after x
  double l0, l1, l2;  // the fixed triangle's squared edge lengths opposite x, a, b
  double alpha, beta;
  double fixed_area = 0;          // B (needed only with a penalty)
  double kappa0 = 0, kappa1 = 0;  // the penalty's weights (both 0: none)
  double onset = 0;               // r₀
  double value(const Vec2& x) const;
  double derivatives(const Vec2& x, Vec2& gradient, Eigen::Matrix2d& hessian) const;

 private:
  /// N from the moving triangle's edges opposite x, a, b.
  double cotangent_sum(const Vec2& e0, const Vec2& e1, const Vec2& e2) const;
  /// r = N / (4 B a) from N and 1 / a (value and derivatives: the same digits).
  double ratio(double n, double inverse_area) const {
    return 1 / (4 * fixed_area) * n * inverse_area;
  }
};
/// The sum of the energies of triangles sharing their moving corner x;
/// with `gradient` and `hessian` (both or neither), their derivatives too.
double corners_energy(const std::vector<CornerStretch>& corners, const Vec2& x,
                      Vec2* gradient = nullptr, Eigen::Matrix2d* hessian = nullptr);
/// The CornerStretch of corner k of triangle p (side 0) if `moving` is 0, of
/// triangle q (side 1) if it is 1, both counter-clockwise; nullopt if the
/// fixed triangle is not positive.
std::optional<CornerStretch> corner_stretch(const std::array<Vec2, 3>& p,
                                            const std::array<Vec2, 3>& q, int moving, int k,
                                            const EnergyTerms& terms, double forward_weight = 1);
/// Energy of a piece through triangulate_piece (HUGE_VAL if none).
double piece_energy(const MetaPiece& piece, const EnergyTerms& terms, double forward_weight = 1);
/// What the energy of many triangles sums apart from the sides' total
/// areas (which change with every split), so that a sum kept for a face
/// stays valid while other faces change: the map core caches one per face.
struct StretchSums {
  double forward = 0;   // Σ forward_weight·forward (triangle_stretch_terms)
  double backward = 0;  // Σ backward
  double anisotropy = 0;  // Σ a₁·max(0, ratio − r₀)² (EnergyTerms::anisotropy without λ / A₁)
  /// Adds triangle (p on side 0, q on side 1); if either is not positive
  /// the sums become HUGE_VAL (and stay so).
  void add_triangle(const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q,
                    const EnergyTerms& terms, double forward_weight = 1);
  /// Adds a piece's triangles (triangulate_piece's); HUGE_VAL if it has none.
  void add_piece(const MetaPiece& piece, const EnergyTerms& terms, double forward_weight = 1);
  /// The energy of the summed triangles: stretch_energy of the one-way sums
  /// plus λ / A₁ times the anisotropy sum (equal to the sum of their
  /// triangle_energy up to rounding).
  double energy(const EnergyTerms& terms) const;
  /// Marks the sums as those of an invalid (non-positive) triangle.
  void set_invalid() { forward = backward = HUGE_VAL; }
  bool operator==(const StretchSums&) const = default;
};

/// Adds the stretch sums of every piece of face f of `side` (cut_face's
/// pieces, without keeping them); cut_face's error if it has one (`sums`
/// are then void).
std::optional<std::string> add_face_sums(const MetaMesh& meta, const MetaIndex& index, int side,
                                         int f, const EnergyTerms& terms, StretchSums& sums);

}  // namespace ism
