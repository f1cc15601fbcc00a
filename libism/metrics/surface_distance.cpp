// The only translation unit that includes CGAL (built as its own object
// library, see CMakeLists.txt), so CGAL's flags and headers stay out of the
// rest of the library.
#include "metrics/metrics.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ism {

namespace {

// Inexact constructions are fine here: we only need distances to double precision.
using Kernel = CGAL::Simple_cartesian<double>;
using CgalPoint = Kernel::Point_3;
using CgalTriangle = Kernel::Triangle_3;
using CgalTriangles = std::vector<CgalTriangle>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, CgalTriangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

CgalPoint to_cgal(const Vec3& p) {
  return {p.x(), p.y(), p.z()};
}

void check_mesh(const TriangleMesh& mesh, const char* role) {
  const std::string where = std::string("surface_distance: ") + role + " mesh ";
  if (mesh.triangles.empty()) throw std::invalid_argument(where + "has no triangles");
  for (const Triangle& t : mesh.triangles)
    for (int v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.n_vertices())
        throw std::invalid_argument(where + "has a triangle referencing missing vertex " +
                                    std::to_string(v));
}

/// Uniform double in [0, 1) from the top 53 bits: std::uniform_real_distribution
/// is implementation-defined, this is the same on every standard library.
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Draws area-uniform random points on a mesh.
class SurfaceSampler {
 public:
  SurfaceSampler(const TriangleMesh& mesh, const char* role) : mesh_(mesh) {
    cumulative_area_.reserve(mesh.n_faces());
    double total = 0.0;
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
      total += face_area(mesh, f);
      cumulative_area_.push_back(total);
    }
    if (!(total > 0.0) || !std::isfinite(total))
      throw std::invalid_argument(std::string("surface_distance: ") + role +
                                  " mesh has zero (or non-finite) total area");
  }

  std::vector<Vec3> sample(std::size_t count, std::mt19937_64& rng) const {
    std::vector<Vec3> points;
    points.reserve(count);
    for (std::size_t i = 0; i < count; ++i) points.push_back(sample_one(rng));
    return points;
  }

 private:
  Vec3 sample_one(std::mt19937_64& rng) const {
    // Triangle with probability proportional to its area; upper_bound never
    // lands on a zero-area triangle.
    const double target = uniform01(rng) * cumulative_area_.back();
    const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), target);
    const std::size_t f =
        std::min<std::size_t>(it - cumulative_area_.begin(), cumulative_area_.size() - 1);
    const Triangle& t = mesh_.triangles[f];
    // Uniform point in the triangle: the sqrt undoes the density growth towards the base.
    const double s = std::sqrt(uniform01(rng));
    const double r = uniform01(rng);
    return (1.0 - s) * mesh_.positions[t[0]] + (s * (1.0 - r)) * mesh_.positions[t[1]] +
           (s * r) * mesh_.positions[t[2]];
  }

  const TriangleMesh& mesh_;
  std::vector<double> cumulative_area_;
};

/// Spreads the low 21 bits of x so that two zero bits follow each.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// The points' indices along a Morton (Z-order) curve of their bounding box:
/// consecutive points of the order are near each other, so the answer to one
/// closest-point query is a good hint for the next.
std::vector<std::size_t> spatial_order(const std::vector<Vec3>& points) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).maxCoeff();
  const double scale = extent > 0 && std::isfinite(extent) ? double(0x1fffff) / extent : 0.0;
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double t = std::clamp((points[i][a] - lo[a]) * scale, 0.0, double(0x1fffff));
      key |= spread_bits(std::uint64_t(std::isfinite(t) ? t : 0.0)) << a;
    }
    keyed[i] = {key, i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) order[i] = keyed[i].second;
  return order;
}

/// Closest-point queries against one mesh.
class DistanceOracle {
 public:
  explicit DistanceOracle(const TriangleMesh& mesh) : mesh_(mesh) {
    triangles_.reserve(mesh.n_faces());
    for (const Triangle& t : mesh.triangles)
      triangles_.emplace_back(to_cgal(mesh.positions[t[0]]), to_cgal(mesh.positions[t[1]]),
                              to_cgal(mesh.positions[t[2]]));
    tree_.insert(triangles_.cbegin(), triangles_.cend());
    // Built now: later const queries would otherwise build it lazily, behind
    // a lock, from the worker threads. No k-d tree of hints: the queries run
    // in spatial order and each takes the previous answer as its hint.
    tree_.build();
  }

  /// Squared distance of each point to the surface, in parallel; the result
  /// depends only on the points (one slot per point).
  std::vector<double> squared_distances(const std::vector<Vec3>& points) const {
    std::vector<double> result(points.size());
    closest_in_order(points, [&](std::size_t i, const Hit& hit) {
      result[i] = CGAL::squared_distance(to_cgal(points[i]), hit.first);
    });
    return result;
  }

  /// Nearest face and point of each point, in parallel (one slot per point).
  std::vector<NearestPoint> nearest(const std::vector<Vec3>& points) const {
    std::vector<NearestPoint> result(points.size());
    closest_in_order(points, [&](std::size_t i, const Hit& hit) {
      const int f = int(hit.second - triangles_.cbegin());
      const Vec3 q(hit.first.x(), hit.first.y(), hit.first.z());
      result[i] = {f, barycentric(f, q), (q - points[i]).squaredNorm()};
    });
    return result;
  }

 private:
  using Hit = Tree::Point_and_primitive_id;

  /// Calls visit(i, closest point and triangle of points[i]) for every
  /// point, in spatial order within fixed blocks of that order (the blocks run
  /// in parallel; within one, each query starts from the previous answer). The
  /// blocks do not depend on the schedule, so neither do the answers.
  template <class Visit>
  void closest_in_order(const std::vector<Vec3>& points, Visit visit) const {
    const std::vector<std::size_t> order = spatial_order(points);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, order.size(), 512),
        [&](const tbb::blocked_range<std::size_t>& range) {
          Hit hint(triangles_.front().vertex(0), triangles_.cbegin());
          for (std::size_t k = range.begin(); k != range.end(); ++k) {
            const std::size_t i = order[k];
            hint = tree_.closest_point_and_primitive(to_cgal(points[i]), hint);
            visit(i, hint);
          }
        },
        tbb::simple_partitioner());
  }

  // Barycentric coordinates of q (a point of face f) in f, clamped to [0, 1]
  // and summing to 1 (q lies in the face up to rounding).
  Vec3 barycentric(int f, const Vec3& q) const {
    const Triangle& t = mesh_.triangles[std::size_t(f)];
    const Vec3 a = mesh_.positions[t[0]], e1 = mesh_.positions[t[1]] - a,
               e2 = mesh_.positions[t[2]] - a, d = q - a;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const double r1 = d.dot(e1), r2 = d.dot(e2), det = d11 * d22 - d12 * d12;
    if (!(det > 0)) {  // a degenerate face: its corner nearest to q
      int k = 0;
      for (int c = 1; c < 3; ++c)
        if ((mesh_.positions[t[c]] - q).squaredNorm() < (mesh_.positions[t[k]] - q).squaredNorm())
          k = c;
      return Vec3::Unit(k);
    }
    const double u = std::clamp((d22 * r1 - d12 * r2) / det, 0.0, 1.0);
    const double v = std::clamp((d11 * r2 - d12 * r1) / det, 0.0, 1.0);
    const double sum = u + v;
    const Vec3 b = sum > 1 ? Vec3(0, u / sum, v / sum) : Vec3(1 - sum, u, v);
    return b;
  }

  const TriangleMesh& mesh_;
  CgalTriangles triangles_;  // the primitives point into this vector
  Tree tree_;
};

}  // namespace

std::vector<NearestPoint> nearest_points(const TriangleMesh& mesh,
                                         const std::vector<Vec3>& points) {
  check_mesh(mesh, "reference");
  return DistanceOracle(mesh).nearest(points);
}

SurfaceDistance surface_distance(const TriangleMesh& reference, const TriangleMesh& other,
                                 const SurfaceDistanceOptions& options) {
  check_mesh(reference, "reference");
  check_mesh(other, "other");
  const SurfaceSampler sampler_a(reference, "reference");
  const SurfaceSampler sampler_b(other, "other");

  const std::size_t count = std::max({reference.n_faces(), other.n_faces(), options.min_samples});
  // One sequence of numbers: the samples on the reference first (three
  // numbers each), then those on the other. The two directions run side by
  // side, the second from the generator moved past the first's numbers, so
  // the samples are those of one sequential draw.
  std::vector<double> d2_a, d2_b;
  tbb::parallel_invoke(
      [&] {
        std::mt19937_64 rng(options.seed);
        d2_a = DistanceOracle(other).squared_distances(sampler_a.sample(count, rng));
      },
      [&] {
        std::mt19937_64 rng(options.seed);
        rng.discard(3 * static_cast<unsigned long long>(count));
        d2_b = DistanceOracle(reference).squared_distances(sampler_b.sample(count, rng));
      });

  // Sequential reductions keep the result independent of the thread schedule.
  double sum_a = 0.0, sum_b = 0.0, max_d2 = 0.0;
  for (double d2 : d2_a) sum_a += d2, max_d2 = std::max(max_d2, d2);
  for (double d2 : d2_b) sum_b += d2, max_d2 = std::max(max_d2, d2);

  SurfaceDistance result;
  result.samples_a = d2_a.size();
  result.samples_b = d2_b.size();
  result.rms_a_to_b = std::sqrt(sum_a / static_cast<double>(result.samples_a));
  result.rms_b_to_a = std::sqrt(sum_b / static_cast<double>(result.samples_b));
  result.rms =
      std::sqrt((sum_a + sum_b) / static_cast<double>(result.samples_a + result.samples_b));
  result.hausdorff = std::sqrt(max_d2);
  result.peak = bounding_box_diagonal(reference);
  result.psnr_db = result.rms > 0.0 ? 20.0 * std::log10(result.peak / result.rms)
                                    : std::numeric_limits<double>::infinity();
  return result;
}

}  // namespace ism
