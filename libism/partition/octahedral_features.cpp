// Automatic features for the octahedral domain: the surface vertices at the
// extremes of the three principal axes (well separated on any shape that is
// not nearly round), assigned to ±x, ±y, ±z of domain::octahedron(). Both
// chiralities are traced and the valid one with the shorter network wins; if
// the extremes coincide or neither works, farthest-point samples on geodesic
// distance are tried.
#include "domain/domain.hpp"
#include "partition/partition.hpp"
#include "partition/patches.hpp"

#include <Eigen/Eigenvalues>

#include <tbb/parallel_for.h>

#include <mutex>
#include <optional>
#include <queue>
#include <set>

namespace ism {
namespace {

// Vertices at the ends of the principal axes, as +x, -x, +y, -y, +z, -z of a
// right-handed frame.
std::vector<int> principal_extremes(const TriangleMesh& surface) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : surface.positions) mean += p;
  mean /= double(surface.n_vertices());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : surface.positions) covariance += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes = solver.eigenvectors().rowwise().reverse();  // largest first
  if (axes.col(0).cross(axes.col(1)).dot(axes.col(2)) < 0) axes.col(2) *= -1;
  std::vector<int> features;
  for (int k = 0; k < 3; ++k) {
    int best_max = 0, best_min = 0;
    for (std::size_t v = 0; v < surface.n_vertices(); ++v) {
      const double s = axes.col(k).dot(surface.positions[v] - mean);
      if (s > axes.col(k).dot(surface.positions[best_max] - mean)) best_max = int(v);
      if (s < axes.col(k).dot(surface.positions[best_min] - mean)) best_min = int(v);
    }
    features.push_back(best_max);
    features.push_back(best_min);
  }
  return features;
}

// Farthest-point sampling on edge-path (geodesic) distance, paired so that
// each sample's antipode is the sample farthest from it.
std::vector<int> farthest_points(const TriangleMesh& surface, int first) {
  const std::size_t n = surface.n_vertices();
  std::vector<std::vector<std::pair<int, double>>> adjacency(n);
  for (const Triangle& t : surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a < b) {
        const double l = (surface.positions[a] - surface.positions[b]).norm();
        adjacency[a].push_back({b, l});
        adjacency[b].push_back({a, l});
      }
    }
  auto distances_from = [&](int source) {
    std::vector<double> d(n, HUGE_VAL);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    d[source] = 0;
    open.push({0, source});
    while (!open.empty()) {
      auto [dv, v] = open.top();
      open.pop();
      if (dv > d[v]) continue;
      for (auto [w, l] : adjacency[v])
        if (dv + l < d[w]) open.push({d[w] = dv + l, w});
    }
    return d;
  };
  std::vector<int> samples{first};
  std::vector<std::vector<double>> from;
  std::vector<double> nearest(n, HUGE_VAL);
  while (samples.size() < 6) {
    from.push_back(distances_from(samples.back()));
    for (std::size_t v = 0; v < n; ++v) nearest[v] = std::min(nearest[v], from.back()[v]);
    samples.push_back(int(std::max_element(nearest.begin(), nearest.end()) - nearest.begin()));
  }
  from.push_back(distances_from(samples.back()));
  // Pair greedily: the first sample with its farthest, then the next pair.
  std::vector<int> ordered;
  std::vector<char> used(6, 0);
  for (int i = 0; i < 6; ++i) {
    if (used[i]) continue;
    int partner = -1;
    for (int j = 0; j < 6; ++j)
      if (j != i && !used[j] && (partner < 0 || from[i][samples[j]] > from[i][samples[partner]]))
        partner = j;
    used[i] = used[partner] = 1;
    ordered.push_back(samples[i]);
    ordered.push_back(samples[partner]);
  }
  return ordered;
}

}  // namespace

std::vector<PathNetwork> trace_octahedral_networks(const TriangleMesh& surface,
                                                   const PartitionOptions& options) {
  const TriangleMesh octahedron = domain::octahedron();
  std::vector<std::vector<int>> attempts;
  const std::vector<int> extremes = principal_extremes(surface);
  if (std::set<int>(extremes.begin(), extremes.end()).size() == 6) attempts.push_back(extremes);
  const std::vector<int> spread = farthest_points(surface, extremes[0]);
  if (attempts.empty() || std::set<int>(spread.begin(), spread.end()) !=
                              std::set<int>(extremes.begin(), extremes.end()))
    attempts.push_back(spread);

  // Which antipodal pair sits on ±z matters when the metric tells the poles
  // from the equator (right isosceles: flat poles, cone equator): cycle the
  // pairs through the three roles. Then both chiralities of each.
  const int roles = options.distinguish_poles ? 3 : 1;
  std::vector<std::vector<int>> assignments;
  for (const auto& features : attempts)
    for (int role = 0; role < roles; ++role)
      for (int chirality = 0; chirality < 2; ++chirality) {
        std::vector<int> assigned(6);
        for (int k = 0; k < 6; ++k) assigned[k] = features[(k + 2 * role) % 6];
        if (chirality) std::swap(assigned[4], assigned[5]);  // mirror: swap +z and -z
        assignments.push_back(std::move(assigned));
      }
  // The traces are independent: side by side, taken in order.
  std::vector<std::optional<PathNetwork>> traced(assignments.size());
  std::vector<std::string> errors(assignments.size());
  PartitionOptions step = options;
  step.progress = nullptr;
  std::mutex progress_mutex;
  std::size_t done = 0;
  tbb::parallel_for(std::size_t(0), assignments.size(), [&](std::size_t i) {
    try {
      traced[i] = trace_path_network(surface, octahedron, assignments[i], step);
    } catch (const PartitionError& e) {
      errors[i] = e.what();
    }
    if (options.progress) {
      std::lock_guard lock(progress_mutex);
      options.progress(double(++done) / double(assignments.size()));
    }
  });
  std::vector<PathNetwork> valid;
  std::string last_error;
  for (std::size_t i = 0; i < traced.size(); ++i) {
    if (traced[i])
      valid.push_back(std::move(*traced[i]));
    else
      last_error = errors[i];
  }
  if (valid.empty()) throw PartitionError("no octahedral path network found: " + last_error);
  std::stable_sort(valid.begin(), valid.end(), [](const PathNetwork& a, const PathNetwork& b) {
    return a.total_length() < b.total_length();
  });
  return valid;
}

PathNetwork trace_octahedral_network(const TriangleMesh& surface, const PartitionOptions& options) {
  return std::move(trace_octahedral_networks(surface, options).front());
}

}  // namespace ism
