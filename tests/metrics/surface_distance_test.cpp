// Surface distance / PSNR on spheres, where the distances are known.
#include "metrics/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using ism::TriangleMesh;
using ism::Vec3;

/// Icosahedron subdivided `levels` times (20 · 4^levels faces), projected onto
/// the sphere of the given radius around the origin; outward orientation.
TriangleMesh icosphere(int levels, double radius) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.positions = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                    {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                    {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& p : mesh.positions) p.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint_of;  // shared edges get one midpoint
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoint_of.try_emplace(key, int(mesh.positions.size()));
      if (inserted) mesh.positions.push_back((mesh.positions[a] + mesh.positions[b]).normalized());
      return it->second;
    };
    std::vector<ism::Triangle> finer;
    for (const ism::Triangle& t : mesh.triangles) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    mesh.triangles = std::move(finer);
  }
  for (Vec3& p : mesh.positions) p *= radius;
  return mesh;
}

TriangleMesh transformed(TriangleMesh mesh, double scale, const Vec3& shift) {
  for (Vec3& p : mesh.positions) p = scale * p + shift;
  return mesh;
}

TEST(Icosphere, IsAClosedSphere) {
  const TriangleMesh sphere = icosphere(4, 2.0);
  EXPECT_EQ(sphere.n_faces(), 5120u);
  EXPECT_EQ(sphere.n_vertices(), 2562u);  // Euler: V = F / 2 + 2
  EXPECT_GT(ism::signed_volume(sphere), 0.0);
  EXPECT_NEAR(ism::surface_area(sphere), 4.0 * M_PI * 4.0, 0.01 * 4.0 * M_PI * 4.0);
}

TEST(SurfaceDistance, ScaledSphereMatchesAnalyticPsnr) {
  const double r = 2.0;
  const TriangleMesh reference = icosphere(5, r);
  const TriangleMesh other = transformed(reference, 1.01, Vec3::Zero());
  const ism::SurfaceDistance d = ism::surface_distance(reference, other);

  const double diagonal = ism::bounding_box_diagonal(reference);
  EXPECT_NEAR(diagonal, 2.0 * r * std::sqrt(3.0), 1e-9);  // the axis points are vertices
  const double expected_psnr = 20.0 * std::log10(diagonal / (0.01 * r));
  RecordProperty("psnr_db", std::to_string(d.psnr_db));
  RecordProperty("expected_psnr_db", std::to_string(expected_psnr));
  std::cout << "PSNR measured " << d.psnr_db << " dB, expected " << expected_psnr << " dB"
            << " (rms " << d.rms << ", a->b " << d.rms_a_to_b << ", b->a " << d.rms_b_to_a
            << ", hausdorff " << d.hausdorff << ")\n";
  EXPECT_NEAR(d.psnr_db, expected_psnr, 0.1);
  EXPECT_DOUBLE_EQ(d.peak, diagonal);
  // Both directions see the 0.01 r gap (slightly less near the facets' edges).
  EXPECT_NEAR(d.rms_a_to_b, 0.01 * r, 0.02 * 0.01 * r);
  EXPECT_NEAR(d.rms_b_to_a, 0.01 * r, 0.02 * 0.01 * r);
  EXPECT_NEAR(d.rms, std::sqrt(0.5 * (d.rms_a_to_b * d.rms_a_to_b + d.rms_b_to_a * d.rms_b_to_a)),
              1e-15);
  EXPECT_LE(d.hausdorff, 0.01 * 1.01 * r + 1e-12);
  EXPECT_GE(d.hausdorff, d.rms);
}

TEST(SurfaceDistance, MeshAgainstItselfIsExact) {
  const TriangleMesh sphere = icosphere(3, 2.0);
  const ism::SurfaceDistance d = ism::surface_distance(sphere, sphere);
  EXPECT_LT(d.rms, 1e-12);
  EXPECT_LT(d.hausdorff, 1e-12);
  EXPECT_GT(d.psnr_db, 200.0);  // +infinity when every distance is exactly 0
}

TEST(SurfaceDistance, SampleCountsAreAtLeastTheFaceCounts) {
  const TriangleMesh fine = icosphere(4, 1.0), coarse = icosphere(2, 1.0);
  const ism::SurfaceDistance d = ism::surface_distance(coarse, fine);
  EXPECT_GE(d.samples_a, fine.n_faces());
  EXPECT_GE(d.samples_b, fine.n_faces());
  EXPECT_EQ(d.samples_a, d.samples_b);

  ism::SurfaceDistanceOptions options;
  options.min_samples = 30000;
  const ism::SurfaceDistance more = ism::surface_distance(coarse, fine, options);
  EXPECT_EQ(more.samples_a, 30000u);
  EXPECT_EQ(more.samples_b, 30000u);
}

TEST(SurfaceDistance, SameSeedIsBitIdentical) {
  const TriangleMesh a = icosphere(4, 1.0);
  const TriangleMesh b = transformed(icosphere(3, 1.0), 1.02, Vec3(0.01, -0.02, 0.03));
  ism::SurfaceDistanceOptions options;
  options.seed = 12345;
  const ism::SurfaceDistance first = ism::surface_distance(a, b, options);
  const ism::SurfaceDistance second = ism::surface_distance(a, b, options);
  EXPECT_EQ(first.rms_a_to_b, second.rms_a_to_b);
  EXPECT_EQ(first.rms_b_to_a, second.rms_b_to_a);
  EXPECT_EQ(first.rms, second.rms);
  EXPECT_EQ(first.hausdorff, second.hausdorff);
  EXPECT_EQ(first.psnr_db, second.psnr_db);

  options.seed = 54321;
  const ism::SurfaceDistance other_seed = ism::surface_distance(a, b, options);
  EXPECT_NE(other_seed.rms_a_to_b, first.rms_a_to_b);
  EXPECT_NEAR(other_seed.rms, first.rms, 0.05 * first.rms);  // same quantity, new samples
}

TEST(SurfaceDistance, TranslatedSphere) {
  // Each point p + t of the moved sphere is within t of p, so every distance is
  // <= t; to first order in t the gap is t |cos θ|, whose RMS is t / sqrt(3),
  // and it reaches ~t at the two ends of the x axis.
  const double t = 0.02;
  const TriangleMesh reference = icosphere(5, 1.0);
  const TriangleMesh moved = transformed(reference, 1.0, Vec3(t, 0.0, 0.0));
  const ism::SurfaceDistance d = ism::surface_distance(reference, moved);
  EXPECT_LE(d.rms, t);
  EXPECT_LE(d.hausdorff, t + 1e-12);
  EXPECT_GE(d.hausdorff, 0.95 * t);
  EXPECT_NEAR(d.rms_a_to_b, t / std::sqrt(3.0), 0.03 * t);
  EXPECT_NEAR(d.rms_b_to_a, t / std::sqrt(3.0), 0.03 * t);
}

TEST(SurfaceDistance, DirectionsAreReportedSeparately) {
  // The other mesh is the sphere plus a far triangle: every reference sample
  // lies on the other mesh, but samples on the far triangle are >= 4 away.
  const TriangleMesh reference = icosphere(3, 1.0);
  TriangleMesh other = reference;
  const int base = int(other.positions.size());
  other.positions.insert(other.positions.end(), {Vec3(5, 0, 0), Vec3(5, 2, 0), Vec3(5, 0, 2)});
  other.triangles.push_back({base, base + 1, base + 2});

  const ism::SurfaceDistance d = ism::surface_distance(reference, other);
  EXPECT_LT(d.rms_a_to_b, 1e-12);
  EXPECT_GT(d.rms_b_to_a, 1.0);
  EXPECT_GE(d.hausdorff, 4.0);
  EXPECT_DOUBLE_EQ(d.peak,
                   ism::bounding_box_diagonal(reference));  // the reference's, not the union's
  EXPECT_NEAR(d.psnr_db, 20.0 * std::log10(d.peak / d.rms), 1e-9);
}

/// Squared distance from p to triangle abc by brute force: the interior's
/// projection when it falls inside, else the nearest point of the three edges.
double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 q = p - n * (n.dot(p - a) / n.squaredNorm());
  const bool inside = n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
                      n.dot((a - c).cross(q - c)) >= 0;
  if (inside) return (p - q).squaredNorm();
  auto to_segment = [&](const Vec3& s, const Vec3& e) {
    const double t = std::clamp((p - s).dot(e - s) / (e - s).squaredNorm(), 0.0, 1.0);
    return (p - (s + t * (e - s))).squaredNorm();
  };
  return std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
}

// The queries run in spatial order, each from the previous answer: the
// answers must still be the exact nearest points, for points near the
// surface, far from it, repeated, and in no particular order.
TEST(NearestPoints, MatchBruteForceWhateverTheOrderOfTheQueries) {
  const TriangleMesh sphere = transformed(icosphere(2, 1.0), 1.0, Vec3(0.2, -0.1, 0.3));
  std::vector<Vec3> points;
  std::uint64_t state = 12345;
  auto next = [&] {  // a small LCG: reproducible everywhere
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) * 0x1.0p-53;
  };
  for (int i = 0; i < 3000; ++i) {
    const Vec3 d = Vec3(next() - 0.5, next() - 0.5, next() - 0.5).normalized();
    const double r = i % 3 == 0 ? 0.999 + 0.002 * next() : i % 3 == 1 ? 3.0 * next() : 40.0;
    points.push_back(Vec3(0.2, -0.1, 0.3) + r * d);
    if (i % 100 == 0) points.push_back(points.back());  // the same point twice
  }
  const std::vector<ism::NearestPoint> near = ism::nearest_points(sphere, points);
  ASSERT_EQ(near.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = HUGE_VAL;
    for (const ism::Triangle& t : sphere.triangles)
      best = std::min(best,
                      squared_distance_to_triangle(points[i], sphere.positions[t[0]],
                                                   sphere.positions[t[1]], sphere.positions[t[2]]));
    ASSERT_NEAR(near[i].squared_distance, best, 1e-12 * (1 + best)) << "point " << i;
    const ism::Triangle& t = sphere.triangles[std::size_t(near[i].face)];
    const Vec3 q = near[i].bary[0] * sphere.positions[t[0]] +
                   near[i].bary[1] * sphere.positions[t[1]] +
                   near[i].bary[2] * sphere.positions[t[2]];
    ASSERT_NEAR((q - points[i]).squaredNorm(), best, 1e-9 * (1 + best)) << "point " << i;
  }
  // The same queries in reverse give the same distances.
  std::vector<Vec3> reversed(points.rbegin(), points.rend());
  const std::vector<ism::NearestPoint> back = ism::nearest_points(sphere, reversed);
  for (std::size_t i = 0; i < points.size(); ++i)
    ASSERT_EQ(back[points.size() - 1 - i].squared_distance, near[i].squared_distance);
}

TEST(SurfaceDistance, RejectsEmptyOrFlatMeshes) {
  const TriangleMesh sphere = icosphere(1, 1.0);
  EXPECT_THROW(ism::surface_distance(TriangleMesh{}, sphere), std::invalid_argument);
  EXPECT_THROW(ism::surface_distance(sphere, TriangleMesh{}), std::invalid_argument);

  TriangleMesh point;  // faces with zero total area
  point.positions = {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)};
  point.triangles = {{0, 1, 2}};
  EXPECT_THROW(ism::surface_distance(point, sphere), std::invalid_argument);

  TriangleMesh broken = sphere;
  broken.triangles.push_back({0, 1, int(broken.positions.size())});
  EXPECT_THROW(ism::surface_distance(sphere, broken), std::invalid_argument);
}

}  // namespace
