#include "metrics/metrics.hpp"

#include <cmath>

namespace ism {

bool OverlayOnSurface::bijective(double distance, double area) const {
  return largest_distance < distance && flipped == 0 &&
         std::abs(signed_area - surface_area) < area * surface_area &&
         std::abs(unsigned_area - surface_area) < area * surface_area;
}

OverlayOnSurface overlay_on_surface(const TriangleMesh& overlay, const TriangleMesh& surface) {
  OverlayOnSurface out;
  const double diagonal = bounding_box_diagonal(surface);
  for (const NearestPoint& p : nearest_points(surface, overlay.positions))
    out.largest_distance = std::max(out.largest_distance, std::sqrt(p.squared_distance) / diagonal);
  std::vector<Vec3> centroids;
  centroids.reserve(overlay.n_faces());
  for (const Triangle& t : overlay.triangles)
    centroids.push_back(
        (overlay.positions[t[0]] + overlay.positions[t[1]] + overlay.positions[t[2]]) / 3);
  const std::vector<NearestPoint> holder = nearest_points(surface, centroids);
  for (std::size_t i = 0; i < overlay.n_faces(); ++i) {
    const Vec3 n = face_normal_scaled(overlay, i);
    const Vec3 face_n = face_normal_scaled(surface, std::size_t(holder[i].face)).normalized();
    const double s = 0.5 * n.dot(face_n);
    out.signed_area += s;
    out.unsigned_area += 0.5 * n.norm();
    if (s < -1e-14 * diagonal * diagonal) ++out.flipped;
  }
  out.surface_area = surface_area(surface);
  return out;
}

}  // namespace ism
