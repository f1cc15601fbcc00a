#pragma once
// Queries on a meta-mesh, the same both ways: the point of one mesh for a
// point of the other, through the affine map of the piece that holds it.
// Every map's queries, whichever core made it (and a map read back from a
// meta-mesh file).
#include "map/domain_geometry.hpp"
#include "map/meta_mesh.hpp"

#include <optional>

namespace ism {

/// A point of an embedded surface: its face, barycentric coordinates there
/// and its position.
struct SurfacePoint {
  int face;
  Eigen::Vector3d bary;
  Vec3 position;
};

/// A point of one side of a meta-mesh: a face and barycentric coordinates
/// with respect to its corners.
struct MetaPoint {
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

class MetaMeshSampler {
 public:
  /// Indexes the pieces of every face of both sides. Throws
  /// std::invalid_argument if the meta-mesh does not validate.
  explicit MetaMeshSampler(const MetaMesh& meta);
  /// The same from the meta-mesh's pieces already cut (meta_pieces of a
  /// valid meta-mesh; not checked again).
  MetaMeshSampler(const MetaMesh& meta, std::vector<MetaPiece> pieces);

  /// The point of side 1 - m that the point (face, bary) of side m maps to.
  /// Nothing for a face that does not exist or a point outside its face
  /// (beyond rounding).
  std::optional<MetaPoint> map_point(int m, int face, const Eigen::Vector3d& bary) const;

 private:
  // The pieces of one face in a uniform grid over its layout, as
  // compressed rows: the pieces of cell c are items[start[c] .. start[c+1]).
  struct Grid {
    Vec2 lo = Vec2::Zero();
    double cell = 1;
    int n = 1;
    std::vector<int> start, items;
  };
  // Each piece i: its faces on both sides; its triangulation
  // (triangulate_piece) as points point_[m][first_point_[i] ..
  // first_point_[i+1]) in side m's layout and triangles
  // triangle_[first_triangle_[i] .. first_triangle_[i+1]) of those points.
  std::vector<std::array<int, 2>> face_;
  std::vector<int> first_point_, first_triangle_;
  std::array<std::vector<Vec2>, 2> point_;
  std::vector<std::array<int, 3>> triangle_;
  std::array<std::vector<std::array<Vec2, 3>>, 2> layout_;
  std::array<std::vector<Grid>, 2> grid_;
  void index(const MetaMesh& meta, const std::vector<MetaPiece>& pieces);
};

/// A remesher's domain points on the surface, through a meta-mesh whose side
/// 0 is that domain (its faces are the domain's, in any order and rotation:
/// meta_mesh(SurfaceMap), InterSurfaceMap's side_from_domain) and side 1 the
/// embedded surface (positions given), whichever core made it. Throws
/// std::invalid_argument if the meta-mesh does not validate, side 1 has no
/// positions, or a face of side 0 is not a face of `domain`. Keeps no
/// reference to either.
class DomainSurfaceSampler {
 public:
  DomainSurfaceSampler(const MetaMesh& meta, const DomainGeometry& domain);
  /// The same from the meta-mesh's pieces already cut (meta_pieces of a
  /// valid meta-mesh; not checked again).
  DomainSurfaceSampler(const MetaMesh& meta, std::vector<MetaPiece> pieces,
                       const DomainGeometry& domain);
  /// The surface point of (face, bary) of the domain, face and barycentric
  /// coordinates in the domain's own corner order; nothing for a face out
  /// of range or a point outside it (beyond rounding).
  std::optional<SurfacePoint> surface_point(int face, const Eigen::Vector3d& bary) const;

 private:
  MetaMeshSampler sampler_;
  std::vector<std::array<int, 2>> side_face_;  // domain face -> side-0 face, rotation
  std::vector<Triangle> faces_;                // side 1
  std::vector<Vec3> positions_;
};

}  // namespace ism
