#pragma once
// The flat metric of a coarse domain M¹: per-face edge lengths, the planar
// layout of each face, face adjacency, and the fan of faces around each
// vertex with its total angle. A vertex whose angles sum to 2π is flat (the
// metric is Euclidean around it); any other vertex is a cone point.
#include "mesh/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <span>
#include <vector>

namespace ism {

using Vec2 = Eigen::Vector2d;

/// Edge lengths of a face: length[k] is the edge from corner k to corner k+1.
using FaceLengths = std::array<double, 3>;

/// How the faces of an abstract domain are shaped.
enum class DomainMetric {
  equilateral,      // every face equilateral with unit edges (semireg, paper's octahedron)
  right_isosceles,  // octahedron unfolded into the square; 3×3 torus grid
};

class DomainGeometry {
 public:
  /// `lengths[f][k]` is the length of edge (corner k, corner k+1) of face f.
  DomainGeometry(TriangleMesh connectivity, std::vector<FaceLengths> lengths);

  const TriangleMesh& mesh() const { return mesh_; }
  std::size_t n_faces() const { return mesh_.n_faces(); }
  std::size_t n_vertices() const { return mesh_.n_vertices(); }
  const FaceLengths& lengths(int f) const { return lengths_[f]; }
  double face_area(int f) const { return area_[f]; }
  double total_area() const { return total_area_; }

  /// Canonical layout of face f: corner 0 at the origin, corner 1 on +x.
  const std::array<Vec2, 3>& layout(int f) const { return layout_[f]; }
  /// Face across edge k of face f, and the index of that edge in it.
  int neighbour(int f, int k) const { return neighbour_[f][k]; }
  int neighbour_edge(int f, int k) const { return neighbour_edge_[f][k]; }

  /// Faces around vertex v in counter-clockwise order, with the corner of v
  /// in each and the angle there; `fan_start[i]` is the summed angle of the
  /// faces before fan[i] in that order.
  struct FanEntry {
    int face, corner;
    double angle, start;
  };
  const std::vector<FanEntry>& fan(int v) const { return fan_[v]; }
  double total_angle(int v) const { return total_angle_[v]; }
  bool is_cone(int v) const;
  /// Vertices that stay on their feature vertex of the surface whatever
  /// their angle: never released, never moved by a cone move or a split
  /// (e.g. the boundary points and loop centres of bounded_base()). `fixed`
  /// has one entry per vertex, or is empty (none fixed, the default).
  void set_fixed(std::vector<char> fixed);
  bool is_fixed(int v) const { return !fixed_.empty() && fixed_[v] != 0; }
  /// Position of fan entry `i` of v in the fan's layout: v at the origin,
  /// the face rotated to start at angle fan[i].start (plus `turns` full
  /// total angles, for charts that wrap around v).
  std::array<Vec2, 3> fan_layout(int v, int i, double extra_angle = 0.0) const;

  /// The face whose corners are `corners` in this cyclic order, and the
  /// rotation r with corners[k] == face's corner (k + r) % 3; nothing if no
  /// face has them (or only in the other orientation). Linear in the faces
  /// (domains are small).
  std::optional<std::array<int, 2>> find_face(const Triangle& corners) const;

  /// The layout of the face across edge k of a face laid out as `layout`.
  std::array<Vec2, 3> unfold(int f, const std::array<Vec2, 3>& layout, int k) const;

 private:
  TriangleMesh mesh_;
  std::vector<FaceLengths> lengths_;
  std::vector<double> area_;
  double total_area_ = 0.0;
  std::vector<std::array<Vec2, 3>> layout_;
  std::vector<std::array<int, 3>> neighbour_, neighbour_edge_;
  std::vector<std::vector<FanEntry>> fan_;
  std::vector<double> total_angle_;
  std::vector<char> fixed_;
};

/// Edge lengths for the given metric on the octahedron of domain::octahedron()
/// (right isosceles: edges at ±z are legs of length 1, equator edges √2).
std::vector<FaceLengths> octahedron_lengths(const TriangleMesh& octahedron, DomainMetric metric);
/// Right-isosceles lengths of domain::torus_3x3() (legs 1/3, diagonals √2/3).
std::vector<FaceLengths> torus_3x3_lengths(const TriangleMesh& torus);
/// Unit equilateral lengths for any domain.
std::vector<FaceLengths> equilateral_lengths(const TriangleMesh& domain);

/// The point with barycentric coordinates b in the triangle with these
/// corners (the inverse of barycentric(); b is used as given, not normalised).
inline Vec2 from_barycentric(const Eigen::Vector3d& b, const std::array<Vec2, 3>& corner) {
  return b[0] * corner[0] + b[1] * corner[1] + b[2] * corner[2];
}
/// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
/// Barycentric coordinates of p in the triangle (a, b, c).
inline Eigen::Vector3d barycentric(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const double total = orient(a, b, c);
  return Eigen::Vector3d(orient(p, b, c), orient(a, p, c), orient(a, b, p)) / total;
}
namespace detail {
/// Twice the shoelace sum of the n corners corner(0), ..., corner(n - 1).
template <class Corner>
double twice_polygon_area(std::size_t n, Corner corner) {
  double twice = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = corner(i);
    const Vec2& b = corner(i + 1 == n ? 0 : i + 1);
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return twice;
}
}  // namespace detail
/// Signed area of a polygon (shoelace): positive when counter-clockwise.
inline double polygon_area(std::span<const Vec2> polygon) {
  return 0.5 * detail::twice_polygon_area(polygon.size(),
                                          [&](std::size_t i) -> const Vec2& { return polygon[i]; });
}
/// polygon_area of the polygon position[corner[0]], position[corner[1]],
/// ... (the same number, without gathering the corners).
inline double polygon_area(std::span<const Vec2> position, std::span<const int> corner) {
  return 0.5 * detail::twice_polygon_area(corner.size(), [&](std::size_t i) -> const Vec2& {
           return position[corner[i]];
         });
}
/// Whether the boxes [lo1, hi1] and [lo2, hi2] lie apart by more than `gap`
/// along x or y.
inline bool boxes_apart(const Vec2& lo1, const Vec2& hi1, const Vec2& lo2, const Vec2& hi2,
                        double gap) {
  return lo2.x() > hi1.x() + gap || lo1.x() > hi2.x() + gap || lo2.y() > hi1.y() + gap ||
         lo1.y() > hi2.y() + gap;
}

}  // namespace ism
