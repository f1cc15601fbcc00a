// Discrete curvature: exact on spheres, scale invariant as a density, and
// higher where an ellipsoid bends most.
#include "mesh/curvature.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace ism {
namespace {

TEST(Curvature, SphereOfRadiusTwoHasCurvatureOneHalfEverywhere) {
  const TriangleMesh sphere = shapes::sphere(5000, 2.0);
  const std::vector<double> kappa = vertex_curvature(sphere);
  ASSERT_EQ(kappa.size(), sphere.n_vertices());
  for (double k : kappa) EXPECT_NEAR(k, 0.5, 0.02);
}

TEST(Curvature, DensityIsScaleInvariantAndAtLeastOne) {
  TriangleMesh blob = shapes::blob(3000, 7, 0.4);
  const std::vector<double> density = curvature_density(blob, 2.0);
  for (Vec3& p : blob.positions) p *= 10.0;
  const std::vector<double> scaled = curvature_density(blob, 2.0);
  ASSERT_EQ(density.size(), scaled.size());
  double lo = HUGE_VAL, hi = 0;
  for (std::size_t v = 0; v < density.size(); ++v) {
    EXPECT_NEAR(density[v], scaled[v], 1e-9 * density[v]);
    lo = std::min(lo, density[v]), hi = std::max(hi, density[v]);
  }
  EXPECT_GE(lo, 1.0);
  EXPECT_GT(hi, 2 * lo);  // a bumpy blob is not uniformly curved
  for (double d : curvature_density(blob, 0.0)) EXPECT_EQ(d, 1.0);
  EXPECT_THROW(curvature_density(blob, -1.0), std::invalid_argument);
}

TEST(Curvature, EllipsoidTipsBendMoreThanItsWaist) {
  // Semi-axes 3, 1, 1: principal curvatures 3 and 3 at the tips (x = ±3),
  // 1 and 1/9 at the waist (x = 0).
  const TriangleMesh e = shapes::ellipsoid(8000, Vec3(3, 1, 1));
  const std::vector<double> kappa = vertex_curvature(e);
  double tip = 0, waist = HUGE_VAL;
  for (std::size_t v = 0; v < e.n_vertices(); ++v) {
    if (std::abs(e.positions[v].x()) > 2.9) tip = std::max(tip, kappa[v]);
    if (std::abs(e.positions[v].x()) < 0.1) waist = std::min(waist, kappa[v]);
  }
  EXPECT_GT(tip, 2.0);
  EXPECT_LT(waist, 1.0);
}

}  // namespace
}  // namespace ism
