#include "mesh/triangle_mesh.hpp"

#include <algorithm>
#include <utility>

#include <Eigen/Geometry>

namespace ism {

Vec3 face_normal_scaled(const TriangleMesh& mesh, std::size_t f) {
  const Triangle& t = mesh.triangles[f];
  const Vec3& a = mesh.positions[t[0]];
  return (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
}

double face_area(const TriangleMesh& mesh, std::size_t f) {
  return 0.5 * face_normal_scaled(mesh, f).norm();
}

double surface_area(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) sum += face_area(mesh, f);
  return sum;
}

double bounding_box_diagonal(const TriangleMesh& mesh) {
  if (mesh.positions.empty()) return 0.0;
  Vec3 lo = mesh.positions.front(), hi = lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

double signed_volume(const TriangleMesh& mesh) {
  double six_volume = 0.0;
  for (const Triangle& t : mesh.triangles)
    six_volume += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
  return six_volume / 6.0;
}

long euler_characteristic(const TriangleMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  std::vector<int> used;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      edges.push_back(std::minmax(t[k], t[(k + 1) % 3]));
      used.push_back(t[k]);
    }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return long(used.size()) - long(edges.size()) + long(mesh.n_faces());
}

}  // namespace ism
