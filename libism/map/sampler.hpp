#pragma once
// Queries on a map: the surface point of a domain point and back. The
// sampler indexes every overlay piece in the frame of its M¹ face with a
// uniform grid, so a lookup costs a few point-in-triangle tests.
#include "map/surface_map.hpp"

#include <optional>

namespace ism {

struct SurfacePoint {
  int face;              // face of M²
  Eigen::Vector3d bary;  // in that face
  Vec3 position;
};

class MapSampler {
 public:
  explicit MapSampler(const SurfaceMap& map);

  /// The point of M² that the domain point (face of M¹, barycentric) maps to.
  std::optional<SurfacePoint> surface_point(int domain_face, const Eigen::Vector3d& bary) const;
  /// The point of M¹ that a point of M² (face, barycentric) maps to.
  std::optional<DomainLocation> domain_point(int surface_face, const Eigen::Vector3d& bary) const;

 private:
  struct Entry {
    int face;
    std::array<Vec2, 3> triangle;  // the M² face in the M¹ face's canonical frame
  };
  struct Grid {
    Vec2 lo, hi;
    int n = 1;
    std::vector<std::vector<int>> cells;  // indices into entries
    std::vector<Entry> entries;
  };
  const SurfaceMap& map_;
  std::vector<Grid> grids_;  // one per M¹ face
};

}  // namespace ism
