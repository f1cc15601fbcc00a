#include "refine/flat_reembedding.hpp"

#include "map/flat_torus_overlay.hpp"
#include "mesh/edge_key.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace ism {

namespace {

Vec3 lift3(const Vec2& p) {
  return Vec3(p.x(), p.y(), 0.0);
}

}  // namespace

CornerWeights symmetrized(const std::vector<Triangle>& faces, const CornerWeights& weights) {
  std::unordered_map<std::uint64_t, double> sum;
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int m = 0; m < 2; ++m)
        sum[undirected_edge_key(faces[t][c], faces[t][(c + 1 + m) % 3])] += weights[t][c][m];
  // Each undirected edge appears four times (two faces, both directions).
  CornerWeights out(faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int m = 0; m < 2; ++m)
        out[t][c][m] = 0.25 * sum[undirected_edge_key(faces[t][c], faces[t][(c + 1 + m) % 3])];
  return out;
}

CornerWeights surface_mean_value_weights(const SurfaceMap& map) {
  const auto& x = map.positions();
  const auto& faces = map.faces();
  return mean_value_weights(faces, [&](int t) {
    return std::array<Vec3, 3>{x[faces[t][0]], x[faces[t][1]], x[faces[t][2]]};
  });
}

CornerWeights layout_mean_value_weights(const SurfaceMap& map, const FlatTorusLayout& layout) {
  const auto& faces = map.faces();
  return mean_value_weights(faces, [&](int t) {
    return std::array<Vec3, 3>{lift3(layout.corner(faces, t, 0)), lift3(layout.corner(faces, t, 1)),
                               lift3(layout.corner(faces, t, 2))};
  });
}

std::optional<FlatTorusLayout> solve_flat_layout(const SurfaceMap& map,
                                                 const FlatTorusLayout& classes,
                                                 const CornerWeights& weights, int fixed) {
  const auto& faces = map.faces();
  const std::size_t nv = map.positions().size();
  std::vector<int> unknown(nv, -1);
  int n = 0;
  for (std::size_t v = 0; v < nv; ++v)
    if (map.is_active(int(v))) unknown[v] = n++;
  if (fixed < 0 || std::size_t(fixed) >= nv || unknown[fixed] < 0) return std::nullopt;

  // Row i: Σ w_ij (x_i − x_j) = Σ w_ij (s_j − s_i), s the corner shifts.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(faces.size() * 12 + 1);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int i = faces[t][c];
      if (i == fixed) continue;
      for (int m = 0; m < 2; ++m) {
        const int cj = (c + 1 + m) % 3, j = faces[t][cj];
        const double w = weights[t][c][m];
        triplets.emplace_back(unknown[i], unknown[i], w);
        triplets.emplace_back(unknown[i], unknown[j], -w);
        const Vec2 ds = (classes.shift[t][cj] - classes.shift[t][c]).cast<double>();
        rhs.row(unknown[i]) += w * ds.transpose();
      }
    }
  triplets.emplace_back(unknown[fixed], unknown[fixed], 1.0);
  rhs.row(unknown[fixed]) = classes.position[fixed].transpose();
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(triplets.begin(), triplets.end());
  a.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> solver;
  solver.compute(a);
  if (solver.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
  FlatTorusLayout out = classes;
  for (std::size_t v = 0; v < nv; ++v)
    if (unknown[v] >= 0) out.position[v] = x.row(unknown[v]).transpose();
  return out;
}

namespace {

std::vector<int> all_faces(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t t = 0; t < out.size(); ++t) out[t] = int(t);
  return out;
}

}  // namespace

FlatLayoutEnergy::FlatLayoutEnergy(const SurfaceMap& map)
    : FlatLayoutEnergy(map, all_faces(map.n_faces()), map.faces()) {}

FlatLayoutEnergy::FlatLayoutEnergy(const SurfaceMap& map, const std::vector<int>& map_faces,
                                   std::vector<Triangle> faces)
    : FlatLayoutEnergy(
          Setting{map.positions(), map.faces(), map.surface_area(), map.domain().total_area(),
                  map.options().inverse_stretch_weight, map.options().anisotropy_weight,
                  anisotropy_onset(map.options()), [&map](int t) { return map.forward_weight(t); }},
          map_faces, std::move(faces)) {}

FlatLayoutEnergy::FlatLayoutEnergy(const InterSurfaceMap& map)
    : FlatLayoutEnergy(map, map.energy_terms(), all_faces(map.meta().side[1].faces.size()),
                       map.meta().side[1].faces) {}

FlatLayoutEnergy::FlatLayoutEnergy(const InterSurfaceMap& map, const std::vector<int>& map_faces,
                                   std::vector<Triangle> faces)
    : FlatLayoutEnergy(map, map.energy_terms(), map_faces, std::move(faces)) {}

FlatLayoutEnergy::FlatLayoutEnergy(const InterSurfaceMap& map, const EnergyTerms& terms,
                                   const std::vector<int>& map_faces, std::vector<Triangle> faces)
    : FlatLayoutEnergy(
          Setting{map.meta().side[1].positions, map.meta().side[1].faces, terms.area1, terms.area0,
                  terms.inverse_weight, terms.anisotropy_weight, terms.anisotropy_onset,
                  [&map, terms](int t) { return terms.forward_weight(map.meta().side[1], t); }},
          map_faces, std::move(faces)) {}

FlatLayoutEnergy::FlatLayoutEnergy(const Setting& setting, const std::vector<int>& map_faces,
                                   std::vector<Triangle> faces)
    : faces_(std::move(faces)) {
  const auto& x = setting.positions;
  const std::size_t nf = faces_.size();
  gram_.resize(nf);
  std::vector<double> area(nf);
  for (std::size_t t = 0; t < nf; ++t) {
    const Triangle& f = setting.surface_faces[map_faces[t]];
    Eigen::Matrix<double, 3, 2> q;
    q << x[f[1]] - x[f[0]], x[f[2]] - x[f[0]];
    gram_[t] = q.transpose() * q;
    area[t] = 0.5 * q.col(0).cross(q.col(1)).norm();
  }
  const double total_surface = setting.total_surface;
  const double total_domain = setting.total_domain;
  const double c_forward = total_domain / (total_surface * total_surface);
  // The map's own energy: its inverse term weighted as its options say.
  const double c_backward = setting.inverse_weight * total_surface / (total_domain * total_domain);
  forward_.resize(nf);
  backward_.resize(nf);
  anisotropy_.resize(nf);
  for (std::size_t t = 0; t < nf; ++t) {
    forward_[t] = 0.5 * c_forward * setting.forward_weight(map_faces[t]) * area[t];
    backward_[t] = 0.5 * c_backward / (area[t] * area[t]);
    anisotropy_[t] = setting.anisotropy_weight * area[t] / total_surface;
  }
  surface_area_ = std::move(area);
  onset_ = setting.onset;
}

double FlatLayoutEnergy::operator()(const FlatTorusLayout& layout,
                                    std::vector<Vec2>* gradient) const {
  if (gradient) gradient->assign(layout.position.size(), Vec2::Zero());
  double sum = 0.0;
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    const Vec2 a = layout.corner(faces_, int(t), 0);
    Eigen::Matrix2d d;
    d << layout.corner(faces_, int(t), 1) - a, layout.corner(faces_, int(t), 2) - a;
    const double det = d.determinant();
    if (!(det > 0)) return HUGE_VAL;
    // f = |J|² = tr(M^T G M), M = D^{-1}; area a = det(D) / 2.
    const Eigen::Matrix2d m = d.inverse();
    const Eigen::Matrix2d gm = gram_[t] * m;
    const double f = (m.transpose() * gm).trace();
    const double area = 0.5 * det, area3 = area * area * area;
    sum += forward_[t] * f + backward_[t] * f * area3;
    // Anisotropy: r = |J|² / det J = f a / A.
    const double excess =
        anisotropy_[t] > 0 ? std::max(0.0, f * area / surface_area_[t] - onset_) : 0.0;
    sum += anisotropy_[t] * excess * excess;
    if (!gradient) continue;
    // ∂f/∂D = −2 M^T G M M^T, ∂a/∂D = a M^T.
    const Eigen::Matrix2d df = -2.0 * m.transpose() * gm * m.transpose();
    Eigen::Matrix2d g =
        (forward_[t] + backward_[t] * area3) * df + 3.0 * backward_[t] * f * area3 * m.transpose();
    // ∂r/∂D = (a ∂f/∂D + f a M^T) / A.
    if (excess > 0)
      g += 2.0 * anisotropy_[t] * excess * (area / surface_area_[t]) * (df + f * m.transpose());
    const Triangle& tri = faces_[t];
    (*gradient)[tri[1]] += g.col(0);
    (*gradient)[tri[2]] += g.col(1);
    (*gradient)[tri[0]] -= g.col(0) + g.col(1);
  }
  return sum;
}

namespace {

// Largest t in (0, 1] … such that every face of the layout moved by t·step
// keeps a positive signed area (the smallest positive root of the per-face
// quadratic), or HUGE_VAL if none turns over.
double max_injective_step(const std::vector<Triangle>& faces, const FlatTorusLayout& layout,
                          const std::vector<Vec2>& step) {
  auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  double t_max = HUGE_VAL;
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Triangle& f = faces[t];
    const Vec2 a = layout.corner(faces, int(t), 0);
    const Vec2 e1 = layout.corner(faces, int(t), 1) - a, e2 = layout.corner(faces, int(t), 2) - a;
    const Vec2 f1 = step[f[1]] - step[f[0]], f2 = step[f[2]] - step[f[0]];
    const double c0 = cross(e1, e2), c1 = cross(e1, f2) + cross(f1, e2), c2 = cross(f1, f2);
    // Smallest positive root of c0 + c1 t + c2 t² (c0 > 0).
    double root = HUGE_VAL;
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc >= 0) {
      // Stable roots: q = -(c1 + sign(c1) √disc) / 2, roots q / c2 and c0 / q
      // (c2 = 0 leaves the root c0 / q = -c0 / c1).
      const double q = -0.5 * (c1 + (c1 >= 0 ? std::sqrt(disc) : -std::sqrt(disc)));
      if (q != 0)
        for (double r : {c2 != 0 ? q / c2 : HUGE_VAL, c0 / q})
          if (r > 0) root = std::min(root, r);
    }
    t_max = std::min(t_max, root);
  }
  return t_max;
}

// Cotangent Laplacian of the surface, weights clamped to a positive floor
// so that it is positive semi-definite with the constants as kernel, plus a
// small multiple of the identity: a fixed, factorised preconditioner.
// Rows of vertices that do not move are the identity (their gradient is
// zeroed, so their step is zero).
struct SurfacePreconditioner {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  bool ok = false;
  SurfacePreconditioner(const std::vector<Vec3>& x, const std::vector<Triangle>& faces,
                        const std::vector<char>& movable) {
    const int n = int(x.size());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(faces.size() * 12 + x.size());
    double diagonal = 0.0;
    std::size_t moving = 0;
    for (std::size_t t = 0; t < faces.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Triangle& f = faces[t];
        const Vec3 u = x[f[(k + 1) % 3]] - x[f[k]], v = x[f[(k + 2) % 3]] - x[f[k]];
        const double cot = u.dot(v) / std::max(u.cross(v).norm(), 1e-300);
        const double w = 0.5 * std::clamp(cot, 1e-2, 1e2);  // edge opposite corner k
        const int i = f[(k + 1) % 3], j = f[(k + 2) % 3];
        if (movable[i]) triplets.emplace_back(i, i, w);
        if (movable[j]) triplets.emplace_back(j, j, w);
        if (movable[i] && movable[j]) {
          triplets.emplace_back(i, j, -w);
          triplets.emplace_back(j, i, -w);
        }
        diagonal += 2 * w;
      }
    for (int v = 0; v < n; ++v) moving += movable[v] != 0;
    const double regular = 1e-8 * diagonal / double(std::max<std::size_t>(1, moving));
    for (int v = 0; v < n; ++v) triplets.emplace_back(v, v, movable[v] ? regular : 1.0);
    Eigen::SparseMatrix<double> l(n, n);
    l.setFromTriplets(triplets.begin(), triplets.end());
    solver.compute(l);
    ok = solver.info() == Eigen::Success;
  }
  Eigen::MatrixXd apply(const Eigen::MatrixXd& g) const { return solver.solve(g); }
};

Eigen::MatrixXd as_matrix(const std::vector<Vec2>& v) {
  Eigen::MatrixXd m(v.size(), 2);
  for (std::size_t i = 0; i < v.size(); ++i) m.row(i) = v[i].transpose();
  return m;
}

}  // namespace

FlatDescentStats descend_flat_layout(const SurfaceMap& map, FlatTorusLayout& layout,
                                     const FlatDescentOptions& options) {
  std::vector<char> active(map.positions().size());
  for (std::size_t v = 0; v < active.size(); ++v) active[v] = map.is_active(int(v));
  return descend_layout(FlatLayoutEnergy(map), map.faces(), map.positions(), active, layout,
                        options);
}

FlatDescentStats descend_layout(const FlatLayoutEnergy& energy, const std::vector<Triangle>& faces,
                                const std::vector<Vec3>& surface, const std::vector<char>& movable,
                                FlatTorusLayout& layout, const FlatDescentOptions& options) {
  FlatDescentStats stats;
  std::vector<Vec2> gradient;
  // The energy's gradient with the rows of fixed vertices zeroed.
  auto evaluate = [&](const FlatTorusLayout& at, std::vector<Vec2>& g) {
    const double e = energy(at, &g);
    for (std::size_t v = 0; v < g.size(); ++v)
      if (!movable[v]) g[v] = Vec2::Zero();
    return e;
  };
  double e = evaluate(layout, gradient);
  stats.energy_before = stats.energy_after = e;
  if (!(e < HUGE_VAL)) return stats;
  const SurfacePreconditioner preconditioner(surface, faces, movable);
  if (!preconditioner.ok) return stats;
  const std::size_t n = layout.position.size();
  auto dot = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a.array() * b.array()).sum();
  };
  std::vector<Eigen::MatrixXd> s_history, y_history;
  std::vector<double> rho;
  Eigen::MatrixXd g = as_matrix(gradient);
  FlatTorusLayout trial = layout;
  std::vector<Vec2> step(n), trial_gradient;
  std::vector<double> history{e};
  for (int it = 0; it < options.max_iterations; ++it) {
    // L-BFGS two-loop recursion with the Laplacian as initial Hessian.
    Eigen::MatrixXd q = g;
    const int m = int(s_history.size());
    std::vector<double> alpha(m);
    for (int i = m - 1; i >= 0; --i) {
      alpha[i] = rho[i] * dot(s_history[i], q);
      q -= alpha[i] * y_history[i];
    }
    Eigen::MatrixXd r = preconditioner.apply(q);
    if (m > 0) {
      const Eigen::MatrixXd hy = preconditioner.apply(y_history[m - 1]);
      r *= dot(s_history[m - 1], y_history[m - 1]) / dot(y_history[m - 1], hy);
    }
    for (int i = 0; i < m; ++i) {
      const double beta = rho[i] * dot(y_history[i], r);
      r += (alpha[i] - beta) * s_history[i];
    }
    Eigen::MatrixXd d = -r;
    double slope = dot(g, d);
    if (!(slope < 0)) {  // not a descent direction: restart from the preconditioned gradient
      s_history.clear(), y_history.clear(), rho.clear();
      d = -preconditioner.apply(g);
      slope = dot(g, d);
      if (!(slope < 0)) break;
    }
    for (std::size_t v = 0; v < n; ++v) step[v] = d.row(v).transpose();
    const double t_max = max_injective_step(faces, layout, step);
    double t = std::min(1.0, 0.9 * t_max);
    if (m == 0) {
      // First step: at most a small fraction of the domain per vertex.
      const double largest = d.rowwise().norm().maxCoeff();
      if (largest > 0) t = std::min(t, 0.01 / largest);
    }
    double e_trial = HUGE_VAL;
    bool accepted = false;
    for (int k = 0; k < 40; ++k, t *= 0.5) {
      for (std::size_t v = 0; v < n; ++v) trial.position[v] = layout.position[v] + t * step[v];
      e_trial = evaluate(trial, trial_gradient);
      if (e_trial <= e + 1e-4 * t * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    ++stats.iterations;
    const Eigen::MatrixXd g_new = as_matrix(trial_gradient);
    const Eigen::MatrixXd s = t * d, y = g_new - g;
    const double sy = dot(s, y);
    if (sy > 1e-16 * std::sqrt(dot(s, s) * dot(y, y))) {
      s_history.push_back(s);
      y_history.push_back(y);
      rho.push_back(1.0 / sy);
      if (int(s_history.size()) > options.memory) {
        s_history.erase(s_history.begin());
        y_history.erase(y_history.begin());
        rho.erase(rho.begin());
      }
    }
    std::swap(layout.position, trial.position);
    g = g_new;
    e = e_trial;
    // Stop when the last `window` iterations together gained too little
    // (single L-BFGS steps vary too much to judge by one).
    history.push_back(e);
    const int window = options.window;
    if (int(history.size()) > window &&
        history[history.size() - 1 - window] - e < window * options.relative_gain * e)
      break;
  }
  stats.energy_after = e;
  return stats;
}

FlatReembeddingStats global_flat_reembedding(SurfaceMap& map,
                                             const FlatReembeddingOptions& options) {
  FlatReembeddingStats stats;
  std::optional<FlatTorusLayout> layout = map.flat_layout();
  if (!layout) return stats;
  stats.energy_before = stats.energy_after = map.energy();
  stats.iterations = descend_flat_layout(map, *layout, options.descent).iterations;
  if (map.layout_energy(*layout) < stats.energy_before * (1 - 1e-9) &&
      map.set_flat_layout(*layout, stats.energy_before)) {
    stats.applied = true;
    stats.energy_after = map.energy();
  }
  return stats;
}

bool untangle_layout(const std::vector<Triangle>& faces, FlatTorusLayout& layout, int passes) {
  std::vector<std::vector<std::array<int, 2>>> around(layout.position.size());  // face, corner
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int c = 0; c < 3; ++c) around[faces[t][c]].push_back({int(t), c});
  auto turned = [&] {
    std::vector<int> out;
    for (std::size_t t = 0; t < faces.size(); ++t)
      if (!(orient(layout.corner(faces, int(t), 0), layout.corner(faces, int(t), 1),
                   layout.corner(faces, int(t), 2)) > 0))
        out.insert(out.end(), faces[t].begin(), faces[t].end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<int> vertices = turned();
    if (vertices.empty()) return true;
    for (int v : vertices) {
      // v at the origin: each face around it counter-clockwise where v is
      // left of its opposite edge.
      std::vector<std::array<Vec2, 2>> edges;
      for (const auto& [t, c] : around[v]) {
        const Vec2 o = layout.corner(faces, t, c);
        edges.push_back(
            {layout.corner(faces, t, (c + 1) % 3) - o, layout.corner(faces, t, (c + 2) % 3) - o});
      }
      if (const auto k = kernel_centroid(edges)) layout.position[v] += *k;
    }
  }
  return turned().empty();
}

FlatReembeddingStats global_flat_reembedding(InterSurfaceMap& map, const DomainGeometry& domain,
                                             const FlatReembeddingOptions& options) {
  FlatReembeddingStats stats;
  for (int s = 0; s < 2; ++s)
    for (std::size_t v = 0; v < map.meta().side[s].n_vertices(); ++v)
      if (map.is_pinned(s, int(v))) return stats;
  std::optional<FlatTorusLayout> layout = flat_layout(map, domain);
  if (!layout || !untangle_layout(map.meta().side[1].faces, *layout)) return stats;
  stats.energy_before = stats.energy_after = map.energy();
  const FlatLayoutEnergy energy(map);
  std::vector<char> active(map.meta().side[1].n_vertices());
  for (std::size_t v = 0; v < active.size(); ++v) active[v] = map.is_active(1, int(v));
  stats.iterations = descend_layout(energy, map.meta().side[1].faces, map.meta().side[1].positions,
                                    active, *layout, options.descent)
                         .iterations;
  if (!(energy(*layout) < stats.energy_before * (1 - 1e-9))) return stats;
  const auto overlay = flat_torus_overlay(map, domain, *layout);
  if (!overlay) return stats;
  const double gain = map.replace_overlay(*overlay);
  stats.applied = gain > 0;
  stats.energy_after = stats.energy_before - gain;
  return stats;
}

}  // namespace ism
