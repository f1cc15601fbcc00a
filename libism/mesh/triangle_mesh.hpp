#pragma once
// The plain indexed triangle mesh that stages exchange: positions and
// counter-clockwise (outward) triangles. No topology is cached here; stages
// that need adjacency build it themselves.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <vector>

namespace ism {

using Vec3 = Eigen::Vector3d;
using Triangle = std::array<int, 3>;

struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;

  std::size_t n_vertices() const { return positions.size(); }
  std::size_t n_faces() const { return triangles.size(); }
};

/// Area of triangle f.
double face_area(const TriangleMesh& mesh, std::size_t f);
/// Unnormalised normal (twice the area, outward for counter-clockwise order).
Vec3 face_normal_scaled(const TriangleMesh& mesh, std::size_t f);
/// Sum of the face areas.
double surface_area(const TriangleMesh& mesh);
/// Length of the diagonal of the axis-aligned bounding box of the vertices.
double bounding_box_diagonal(const TriangleMesh& mesh);
/// V − E + F over the vertices that faces use (2 − 2g for a closed,
/// connected, orientable surface of genus g).
long euler_characteristic(const TriangleMesh& mesh);

/// Signed enclosed volume (positive for a closed, outward-oriented mesh).
double signed_volume(const TriangleMesh& mesh);

}  // namespace ism
