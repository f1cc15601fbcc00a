#include "refine/disc_relaxation.hpp"

#include "mesh/mean_value_weights.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace ism {

namespace {

// Up to this many unknowns (a disc) the system is solved dense.
constexpr int kDense = 300;

// The positions where every free vertex is the mean-value combination of
// its neighbours (weights from the surface's triangles), the others fixed.
std::optional<std::vector<Vec2>> mean_value_positions(const DiscLayout& disc,
                                                      const std::vector<Vec3>& surface) {
  const CornerWeights weights = mean_value_weights(disc.local, [&](int i) {
    const Triangle& t = disc.local[i];
    return std::array<Vec3, 3>{surface[t[0]], surface[t[1]], surface[t[2]]};
  });
  std::vector<int> unknown(disc.vertex.size(), -1);
  int m = 0;
  for (std::size_t u = 0; u < unknown.size(); ++u)
    if (disc.free[u]) unknown[u] = m++;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
  for (std::size_t i = 0; i < disc.local.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const int row = unknown[disc.local[i][c]];
      if (row < 0) continue;
      for (int k = 0; k < 2; ++k) {
        const int j = disc.local[i][(c + 1 + k) % 3];
        const double w = weights[i][c][k];
        triplets.emplace_back(row, row, w);
        if (unknown[j] >= 0)
          triplets.emplace_back(row, unknown[j], -w);
        else
          rhs.row(row) += w * disc.position[j].transpose();
      }
    }
  Eigen::MatrixXd x;
  if (m <= kDense) {  // a disc: factored dense
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
    for (const auto& t : triplets) a(t.row(), t.col()) += t.value();
    x = a.partialPivLu().solve(rhs);
  } else {
    Eigen::SparseMatrix<double> a(m, m);
    a.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
    solver.compute(a);
    if (solver.info() != Eigen::Success) return std::nullopt;
    x = solver.solve(rhs);
    if (solver.info() != Eigen::Success) return std::nullopt;
  }
  if (!x.allFinite()) return std::nullopt;
  std::vector<Vec2> out = disc.position;
  for (std::size_t u = 0; u < out.size(); ++u)
    if (unknown[u] >= 0) out[u] = x.row(unknown[u]).transpose();
  return out;
}

// The disc's free vertices from their mean-value positions (if lower) or
// where they are, descended together; `positions`: the 3D position of each
// map vertex.
void descend_disc(const FlatLayoutEnergy& energy, const std::vector<Vec3>& positions,
                  DiscLayout& disc, const FlatDescentOptions& options) {
  std::vector<Vec3> surface(disc.vertex.size());
  for (std::size_t u = 0; u < surface.size(); ++u) surface[u] = positions[disc.vertex[u]];
  FlatTorusLayout layout{disc.position, {}};
  layout.shift.assign(disc.face.size(),
                      {Eigen::Vector2i::Zero(), Eigen::Vector2i::Zero(), Eigen::Vector2i::Zero()});
  double e = energy(layout);
  if (std::optional<std::vector<Vec2>> start = mean_value_positions(disc, surface)) {
    std::swap(layout.position, *start);
    const double e_start = energy(layout);
    if (e_start < e)
      e = e_start;
    else
      std::swap(layout.position, *start);
  }
  descend_layout(energy, disc.local, surface, disc.free, layout, options);
  disc.position = layout.position;
}

}  // namespace

double reembed_disc(SurfaceMap& map, const std::vector<int>& vertices,
                    const FlatDescentOptions& options) {
  std::optional<DiscLayout> disc = map.disc_layout(vertices);
  if (!disc) return 0.0;
  descend_disc(FlatLayoutEnergy(map, disc->face, disc->local), map.positions(), *disc, options);
  return map.set_disc_layout(*disc);
}

double reembed_disc(InterSurfaceMap& map, const std::vector<int>& vertices,
                    const FlatDescentOptions& options) {
  std::optional<DiscLayout> disc = map.disc_layout(vertices);
  if (!disc) return 0.0;
  descend_disc(FlatLayoutEnergy(map, disc->face, disc->local), map.meta().side[1].positions, *disc,
               options);
  return map.set_disc_layout(*disc);
}

double disc_relaxation(SurfaceMap& map, double outlier, std::size_t max_discs, std::size_t& tried,
                       std::size_t& applied, bool validate_each_step) {
  const std::size_t nf = map.n_faces();
  std::vector<std::pair<double, int>> worst;
  double total = 0.0;
  for (std::size_t t = 0; t < nf; ++t) {
    const double e = map.face_energy(int(t));
    total += e;
    worst.push_back({e, int(t)});
  }
  if (nf == 0 || !(total < HUGE_VAL)) return 0.0;
  const double limit = outlier * total / double(nf);
  worst.erase(
      std::remove_if(worst.begin(), worst.end(), [&](const auto& p) { return p.first <= limit; }),
      worst.end());
  std::sort(worst.begin(), worst.end(), std::greater<>());
  if (worst.size() > max_discs) worst.resize(max_discs);
  double gain = 0.0;
  for (const auto& [e, t] : worst) {
    if (map.face_energy(t) <= limit) continue;  // opened by an earlier disc
    for (int rings = 1; rings <= 8; rings *= 2) {
      std::vector<int> disc;
      for (int v : map.faces()[t]) {
        const std::vector<int> around = map.rings_around(v, rings);
        disc.insert(disc.end(), around.begin(), around.end());
      }
      ++tried;
      const double g = reembed_disc(map, disc);
      if (validate_each_step)
        if (auto problem = map.validate())
          throw std::runtime_error("map invalid after re-embedding a disc around face " +
                                   std::to_string(t) + ": " + *problem);
      if (g <= 0) continue;
      gain += g;
      ++applied;
      break;
    }
  }
  return gain;
}

}  // namespace ism
