// Automatic features for the 3×3 torus domain: a valid network of 18 discs
// on every genus-1 surface we have, features on a 3×3 lattice of angles on
// an analytic torus, and a clear refusal of other surfaces.
#include "partition/torus_features.hpp"

#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <tuple>

namespace ism {
namespace {

TriangleMesh read_shared(const std::string& file) {
  return prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file)).mesh;
}

void expect_torus_network(const TriangleMesh& surface) {
  const PathNetwork net = trace_torus_network(surface);
  EXPECT_EQ(validate_network(net, domain::torus_3x3()), std::nullopt);
  EXPECT_EQ(net.paths.size(), 27u);
  EXPECT_EQ(std::set<int>(net.face_patch.begin(), net.face_patch.end()).size(), 18u);
  EXPECT_EQ(std::set<int>(net.features.begin(), net.features.end()).size(), 9u);
}

TEST(TorusFeatures, GeneratedToriGiveEighteenDiscs) {
  expect_torus_network(shapes::torus(4000, 2.0, 1.0));
  expect_torus_network(shapes::torus(8000, 3.0, 0.5));
}

TEST(TorusFeatures, EveryClosedGenusOneSharedModel) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const char* file :
       {"torus.obj", "teapot.obj", "rocker_arm.obj", "mug.obj", "cup.obj", "bob.obj", "knot.obj"}) {
    SCOPED_TRACE(file);
    expect_torus_network(read_shared(file));
  }
}

// Angles in degrees: u around the z axis, v around the tube of major radius R.
std::array<double, 2> torus_angles(const Vec3& p, double R) {
  const double u = std::atan2(p.y(), p.x());
  const double v = std::atan2(p.z(), std::hypot(p.x(), p.y()) - R);
  return {u * 180 / std::numbers::pi, v * 180 / std::numbers::pi};
}

// a - b within 25° of `difference`, modulo 360°.
bool near_angle(double a, double b, double difference) {
  return std::abs(std::remainder(a - b - difference, 360.0)) <= 25.0;
}

// Each row at one value of angle `row_angle` and each column at one value of
// the other, consecutive rows and columns 120° apart.
bool on_angle_lattice(const std::vector<std::array<double, 2>>& angles, int row_angle) {
  const int col_angle = 1 - row_angle;
  auto at = [&](int row, int col, int which) { return angles[3 * row + col][which]; };
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      if (!near_angle(at(row, col, row_angle), at(row, 0, row_angle), 0) ||
          !near_angle(at(row, col, col_angle), at(0, col, col_angle), 0))
        return false;
  for (int k = 1; k < 3; ++k) {
    const double rows = at(k, 0, row_angle) - at(k - 1, 0, row_angle);
    const double cols = at(0, k, col_angle) - at(0, k - 1, col_angle);
    if (!near_angle(rows, 0, 120) && !near_angle(rows, 0, -120)) return false;
    if (!near_angle(cols, 0, 120) && !near_angle(cols, 0, -120)) return false;
  }
  return true;
}

TEST(TorusFeatures, AnalyticTorusFeaturesLieOnAnAngleLattice) {
  for (auto [faces, R, r] : {std::tuple{4000, 2.0, 1.0}, {8000, 3.0, 0.5}, {3000, 1.0, 0.4}}) {
    SCOPED_TRACE(R);
    const TriangleMesh surface = shapes::torus(faces, R, r);
    for (const auto& features :
         {choose_torus_features(surface), trace_torus_network(surface).features}) {
      ASSERT_EQ(features.size(), 9u);
      EXPECT_EQ(std::set<int>(features.begin(), features.end()).size(), 9u);
      std::vector<std::array<double, 2>> angles;
      for (int f : features) angles.push_back(torus_angles(surface.positions[f], R));
      EXPECT_TRUE(on_angle_lattice(angles, 0) || on_angle_lattice(angles, 1));
    }
  }
}

TEST(TorusFeatures, ChosenFeaturesTraceDirectly) {
  const TriangleMesh surface = shapes::torus(4000, 2.0, 1.0);
  const std::vector<int> features = choose_torus_features(surface);
  const PathNetwork net = trace_path_network(surface, domain::torus_3x3(), features);
  EXPECT_EQ(validate_network(net, domain::torus_3x3()), std::nullopt);
  EXPECT_EQ(net.features, features);
}

TEST(TorusFeatures, UnusedVerticesAreNeverFeatures) {
  TriangleMesh surface = shapes::torus(2000, 2.0, 1.0);
  surface.positions.insert(surface.positions.begin(), Vec3(2, 0, 0));  // on the surface
  for (Triangle& t : surface.triangles)
    for (int& v : t) ++v;
  const std::vector<int> features = choose_torus_features(surface);
  EXPECT_EQ(std::set<int>(features.begin(), features.end()).size(), 9u);
  for (int f : features) EXPECT_NE(f, 0);
}

TEST(TorusFeatures, ProgressIsMonotoneAndEnds) {
  std::vector<double> seen;
  PartitionOptions options;
  options.progress = [&](double p) { seen.push_back(p); };
  trace_torus_network(shapes::torus(2000, 2.0, 1.0), options);
  ASSERT_FALSE(seen.empty());
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
}

std::string error_of(const TriangleMesh& surface) {
  try {
    choose_torus_features(surface);
  } catch (const PartitionError& e) {
    return e.what();
  }
  return "";
}

TEST(TorusFeatures, OtherGeneraAndOpenSurfacesAreRefused) {
  EXPECT_NE(error_of(shapes::sphere(500)).find("genus 0"), std::string::npos);
  EXPECT_NE(error_of(shapes::double_torus(500)).find("genus 2"), std::string::npos);
  EXPECT_THROW(trace_torus_network(shapes::sphere(500)), PartitionError);
  TriangleMesh open = shapes::torus(1000);
  open.triangles.pop_back();
  EXPECT_NE(error_of(open).find("boundary"), std::string::npos);
  EXPECT_NE(error_of(TriangleMesh{}).find("no triangles"), std::string::npos);
  TriangleMesh two = shapes::torus(1000);
  const int n = int(two.n_vertices());
  const TriangleMesh other = shapes::torus(1000);
  for (const Vec3& p : other.positions) two.positions.push_back(p + Vec3(10, 0, 0));
  for (const Triangle& t : other.triangles) two.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  EXPECT_NE(error_of(two).find("components"), std::string::npos);
}

}  // namespace
}  // namespace ism
