// Automatic feature pairs (paper §4: "our algorithm automatically inserts
// additional pairs" when the user's are too few for the genus). The rule is
// fixed and symmetric: farthest-point sampling on one surface, matched on the
// other by geodesic distances to the features both already share.
#include "partition/compatible_detail.hpp"
#include "partition/partition.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace ism::partition_detail {
namespace {

class Distances {
 public:
  explicit Distances(const TriangleMesh& surface)
      : surface_(surface), neighbours_(surface.n_vertices()) {
    for (const Triangle& t : surface.triangles)
      for (int k = 0; k < 3; ++k) neighbours_[t[k]].push_back(t[(k + 1) % 3]);
    const double area = surface_area(surface);
    scale_ = area > 0 ? 1 / std::sqrt(area) : 1;
  }

  /// Geodesic (edge-graph) distances from the sources, scaled to unit area.
  std::vector<double> from(const std::vector<int>& sources) const {
    std::vector<double> d(surface_.n_vertices(), INFINITY);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    for (int s : sources) d[s] = 0, open.push({0.0, s});
    while (!open.empty()) {
      const auto [dv, v] = open.top();
      open.pop();
      if (dv > d[v]) continue;
      for (int w : neighbours_[v]) {
        const double dw = dv + (surface_.positions[w] - surface_.positions[v]).norm() * scale_;
        if (dw < d[w]) d[w] = dw, open.push({dw, w});
      }
    }
    return d;
  }

 private:
  const TriangleMesh& surface_;
  std::vector<std::vector<int>> neighbours_;
  double scale_ = 1;
};

// Vertex farthest from the area-weighted centroid.
int farthest_from_centroid(const TriangleMesh& surface, const std::vector<char>& allowed) {
  Vec3 centroid = Vec3::Zero();
  double area = 0;
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const Triangle& t = surface.triangles[f];
    const double a = face_area(surface, f);
    centroid +=
        a * (surface.positions[t[0]] + surface.positions[t[1]] + surface.positions[t[2]]) / 3;
    area += a;
  }
  if (area > 0) centroid /= area;
  int best = -1;
  double best_d = -1;
  for (std::size_t v = 0; v < surface.n_vertices(); ++v) {
    if (!allowed[v]) continue;
    const double d = (surface.positions[v] - centroid).squaredNorm();
    if (d > best_d) best_d = d, best = int(v);
  }
  return best;
}

struct Match {
  std::array<int, 2> pair{-1, -1};
  double mismatch = INFINITY;
};

// The vertex of surface `from` farthest from its anchors, and its best match
// on `to` by the distance profile.
Match farthest_and_match(int from, const std::array<const Distances*, 2>& distances,
                         const std::array<std::vector<std::vector<double>>, 2>& profile,
                         const std::array<std::vector<char>, 2>& allowed) {
  const int to = 1 - from;
  const std::size_t k = profile[from].size();
  const std::size_t n_from = allowed[from].size(), n_to = allowed[to].size();
  auto nearest_anchor = [&](int side, std::size_t v) {
    double d = INFINITY;
    for (const auto& p : profile[side]) d = std::min(d, p[v]);
    return d;
  };
  int far = -1;
  double far_d = -1;
  for (std::size_t v = 0; v < n_from; ++v)
    if (allowed[from][v] && std::isfinite(nearest_anchor(from, v)) &&
        nearest_anchor(from, v) > far_d)
      far_d = nearest_anchor(from, v), far = int(v);
  if (far < 0) return {};
  // Candidates on the other side: not closer to an anchor than half the
  // farthest vertex there is.
  double to_far = 0;
  for (std::size_t v = 0; v < n_to; ++v)
    if (allowed[to][v] && std::isfinite(nearest_anchor(to, v)))
      to_far = std::max(to_far, nearest_anchor(to, v));
  Match best;
  for (std::size_t v = 0; v < n_to; ++v) {
    if (!allowed[to][v]) continue;
    const double near = nearest_anchor(to, v);
    if (!std::isfinite(near) || near < 0.5 * to_far) continue;
    double mismatch = 0;
    for (std::size_t a = 0; a < k; ++a) {
      const double diff = profile[to][a][v] - profile[from][a][far];
      mismatch += diff * diff;
    }
    // Ties (one anchor: a whole level set) go to the farthest vertex.
    mismatch -= 1e-9 * near;
    if (mismatch < best.mismatch) {
      best.mismatch = mismatch;
      best.pair[from] = far;
      best.pair[to] = int(v);
    }
  }
  (void)distances;
  return best;
}

}  // namespace

std::vector<std::array<int, 2>> automatic_pairs(const std::array<const TriangleMesh*, 2>& surfaces,
                                                const std::array<std::vector<Anchor>, 2>& anchors,
                                                const std::array<std::vector<char>, 2>& allowed,
                                                std::size_t count) {
  const Distances da(*surfaces[0]), db(*surfaces[1]);
  const std::array<const Distances*, 2> distances{&da, &db};
  std::array<std::vector<std::vector<double>>, 2> profile;
  for (int s = 0; s < 2; ++s)
    for (const Anchor& a : anchors[s]) profile[s].push_back(distances[s]->from(a));
  std::array<std::vector<char>, 2> free = allowed;
  std::vector<std::array<int, 2>> out;
  while (out.size() < count) {
    std::array<int, 2> pair{-1, -1};
    if (profile[0].empty()) {
      for (int s = 0; s < 2; ++s) pair[s] = farthest_from_centroid(*surfaces[s], free[s]);
    } else {
      const Match m0 = farthest_and_match(0, distances, profile, free);
      const Match m1 = farthest_and_match(1, distances, profile, free);
      pair = m0.mismatch <= m1.mismatch ? m0.pair : m1.pair;
    }
    if (pair[0] < 0 || pair[1] < 0)
      throw PartitionError(
          "no room for automatic features (every vertex is taken or on a boundary)");
    for (int s = 0; s < 2; ++s) {
      free[s][pair[s]] = 0;
      profile[s].push_back(distances[s]->from({pair[s]}));
    }
    out.push_back(pair);
  }
  return out;
}

}  // namespace ism::partition_detail
