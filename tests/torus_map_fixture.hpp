#pragma once
// A map onto the flat 3×3 torus of a genus-1 surface, at its base level: the
// automatic network, its constrained progressive mesh and the trivial map.
#include "domain/domain.hpp"
#include "map/map.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"

#include <gtest/gtest.h>

namespace ism::test {

struct TorusMap {
  TriangleMesh grid = domain::torus_3x3();
  DomainGeometry geometry{grid, torus_3x3_lengths(grid)};
  PathNetwork network;
  ProgressiveMesh pm;
  SurfaceMap map;
  explicit TorusMap(const TriangleMesh& surface, MapOptions options = {})
      : network(trace_torus_network(surface)),
        pm(simplify_constrained(network, grid)),
        map(geometry, pm, options) {}
};

/// Every face of the layout counter-clockwise and the faces covering the
/// unit torus once (areas summing to 1): the layout is an embedding.
inline void expect_layout_tiles_the_torus(const std::vector<Triangle>& faces,
                                          const FlatTorusLayout& layout) {
  double area = 0;
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const double a = 0.5 * orient(layout.corner(faces, int(t), 0), layout.corner(faces, int(t), 1),
                                  layout.corner(faces, int(t), 2));
    EXPECT_GT(a, 0) << "face " << t;
    area += a;
  }
  EXPECT_NEAR(area, 1.0, 1e-9);
}

}  // namespace ism::test
