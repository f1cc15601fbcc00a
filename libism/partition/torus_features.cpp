// Automatic features for the 3×3 torus domain.
//
// A tree–cotree decomposition (Eppstein) gives two generator edges and, by
// peeling the dual tree, closed integer 1-forms θ_1, θ_2 dual to the two
// homology loops (zero on the primal tree). Their cotangent-harmonic
// representatives h_k = θ_k + d u_k integrate, along the primal tree, to u_k:
// the map u = (u_1, u_2) mod Z² is a harmonic map to a flat torus. Its
// conformal period lattice has the metric G⁻¹ (G the Dirichlet Gram matrix of
// h_1, h_2); Gauss reduction picks the two shortest lattice directions, so
// rows and columns follow the natural loops (tube and ring of a torus, handle
// and body of a mug) rather than twisted combinations.
//
// The conformal map squeezes whole regions (a teapot's body is a thin band
// of it), so a plain lattice in it bunches the features up. Candidates are
// therefore placed three ways: on three level curves of t spaced by length,
// each divided by its own length; and on lattices after re-spacing s and t
// by length or by area. Rows and columns are tried both ways round, with
// the lattice shifted by thirds of a cell. They are ranked by how evenly
// they cover the surface, and the best few that trace compete on length.
#include "partition/torus_features.hpp"

#include "domain/domain.hpp"
#include "mesh/union_find.hpp"
#include "partition/patches.hpp"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <unordered_map>

namespace ism {
namespace {

const char* const kNeed = "the 3x3 torus domain needs a closed genus-1 surface";

struct Topology {
  std::vector<std::array<int, 2>> edge_ends;   // a < b
  std::vector<std::array<int, 2>> edge_faces;  // face holding a->b, face holding b->a
  std::vector<std::array<int, 3>> face_edges;  // edge of (t[k], t[k+1])
  std::vector<char> used;                      // referenced by a triangle
};

// +1 if the face walks edge e from its first to its second end.
int sign_in_face(const Topology& topo, int e, int from) {
  return topo.edge_ends[e][0] == from ? 1 : -1;
}

// Edges of the surface, after checking that it is one closed, oriented,
// vertex-manifold component of genus 1 (anything else has no 3×3 torus net).
Topology closed_genus1_topology(const TriangleMesh& surface) {
  const int nv = int(surface.n_vertices()), nf = int(surface.n_faces());
  if (nf == 0) throw PartitionError(std::string("the surface has no triangles; ") + kNeed);
  Topology topo;
  topo.used.assign(nv, 0);
  topo.face_edges.resize(nf);
  std::unordered_map<std::uint64_t, int> edge_of, face_of;  // undirected key, directed key
  for (int f = 0; f < nf; ++f) {
    const Triangle& t = surface.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a < 0 || b < 0 || a >= nv || b >= nv || a == b)
        throw PartitionError("triangle " + std::to_string(f) +
                             " has a repeated or out-of-range corner; " + kNeed);
      topo.used[a] = 1;
      if (!face_of.emplace(directed_edge_key(a, b), f).second)
        throw PartitionError("edge " + std::to_string(a) + "-" + std::to_string(b) +
                             " is used twice in the same direction (not an oriented manifold); " +
                             kNeed);
      auto [it, inserted] =
          edge_of.try_emplace(undirected_edge_key(a, b), int(topo.edge_ends.size()));
      if (inserted) {
        topo.edge_ends.push_back({std::min(a, b), std::max(a, b)});
        topo.edge_faces.push_back({-1, -1});
      }
      topo.face_edges[f][k] = it->second;
      topo.edge_faces[it->second][a < b ? 0 : 1] = f;
    }
  }
  std::size_t boundary = 0;
  UnionFind components(nf);
  for (const auto& faces : topo.edge_faces) {
    if (faces[0] < 0 || faces[1] < 0)
      ++boundary;
    else
      components.unite(faces[0], faces[1]);
  }
  if (boundary)
    throw PartitionError("the surface has " + std::to_string(boundary) + " boundary edges; " +
                         kNeed);
  for (int f = 1; f < nf; ++f)
    if (components.find(f) != components.find(0))
      throw PartitionError(std::string("the surface has several components; ") + kNeed);

  // One fan of faces around every vertex: walk it and compare with the count.
  std::vector<int> incident(nv, 0);
  for (const Triangle& t : surface.triangles)
    for (int v : t) ++incident[v];
  std::vector<char> walked(nv, 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = surface.triangles[f][k];
      if (walked[v]) continue;
      walked[v] = 1;
      int g = f, count = 0;
      do {
        const Triangle& t = surface.triangles[g];
        const int c = int(std::find(t.begin(), t.end(), v) - t.begin());
        g = face_of.at(directed_edge_key(v, t[(c + 2) % 3]));  // across the edge entering v
      } while (++count <= incident[v] && g != f);
      if (count != incident[v])
        throw PartitionError("vertex " + std::to_string(v) + " is not manifold; " + kNeed);
    }

  const long used = long(std::count(topo.used.begin(), topo.used.end(), 1));
  const long chi = used - long(topo.edge_ends.size()) + long(nf);
  if (chi != 0)
    throw PartitionError("the surface has genus " + std::to_string((2 - chi) / 2) + "; " + kNeed);
  return topo;
}

// Closed integer 1-forms dual to the two homology generators of a
// tree–cotree decomposition: zero on a BFS spanning tree of the vertices,
// ±δ on the two generator edges, and fixed on the dual-tree edges by closing
// every face, leaves of the dual tree first.
std::array<std::vector<double>, 2> generator_forms(const TriangleMesh& surface,
                                                   const Topology& topo, int root) {
  const int nv = int(surface.n_vertices()), ne = int(topo.edge_ends.size());
  const int nf = int(surface.n_faces());
  std::vector<std::vector<int>> vertex_edges(nv);
  for (int e = 0; e < ne; ++e)
    for (int v : topo.edge_ends[e]) vertex_edges[v].push_back(e);

  enum : char { kFree, kTree, kCotree };
  std::vector<char> kind(ne, kFree);
  std::vector<char> reached(nv, 0);
  std::vector<int> queue{root};
  reached[root] = 1;
  for (std::size_t i = 0; i < queue.size(); ++i)
    for (int e : vertex_edges[queue[i]]) {
      const int w = topo.edge_ends[e][0] == queue[i] ? topo.edge_ends[e][1] : topo.edge_ends[e][0];
      if (reached[w]) continue;
      reached[w] = 1;
      kind[e] = kTree;
      queue.push_back(w);
    }

  std::vector<int> parent_edge(nf, -1), order{0};
  std::vector<char> seen(nf, 0);
  seen[0] = 1;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (int e : topo.face_edges[order[i]]) {
      if (kind[e] != kFree) continue;
      const auto [g0, g1] = topo.edge_faces[e];
      const int g = g0 == order[i] ? g1 : g0;
      if (seen[g]) continue;
      seen[g] = 1;
      kind[e] = kCotree;
      parent_edge[g] = e;
      order.push_back(g);
    }

  std::vector<int> generators;
  for (int e = 0; e < ne; ++e)
    if (kind[e] == kFree) generators.push_back(e);
  if (generators.size() != 2)  // cannot happen after the genus check
    throw PartitionError("tree-cotree decomposition found " + std::to_string(generators.size()) +
                         " generators instead of 2");

  std::array<std::vector<double>, 2> forms;
  for (int k = 0; k < 2; ++k) {
    std::vector<double>& theta = forms[k];
    theta.assign(ne, 0.0);
    theta[generators[k]] = 1.0;
    for (std::size_t i = order.size(); i-- > 1;) {
      const int f = order[i];
      const Triangle& t = surface.triangles[f];
      double rest = 0.0;
      int parent_sign = 0;
      for (int c = 0; c < 3; ++c) {
        const int e = topo.face_edges[f][c];
        const int sign = sign_in_face(topo, e, t[c]);
        if (e == parent_edge[f])
          parent_sign = sign;
        else
          rest += sign * theta[e];
      }
      theta[parent_edge[f]] = -rest * parent_sign;
    }
  }
  return forms;
}

// Cotangent weights, clamped to a small positive floor so that obtuse or
// sliver triangles keep the Laplacian positive definite.
std::vector<double> cotan_weights(const TriangleMesh& surface, const Topology& topo) {
  std::vector<double> w(topo.edge_ends.size(), 0.0);
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const Triangle& t = surface.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = surface.positions[t[k]];
      const Vec3 a = surface.positions[t[(k + 1) % 3]] - p,
                 b = surface.positions[t[(k + 2) % 3]] - p;
      const double cross = a.cross(b).norm(), dot = a.dot(b);
      const double cot = cross > 1e-300 ? std::clamp(dot / cross, -1e6, 1e6) : 0.0;
      w[topo.face_edges[f][(k + 1) % 3]] += 0.5 * cot;
    }
  }
  for (double& x : w) x = std::clamp(x, 1e-3, 1e6);
  return w;
}

// The harmonic map to the flat torus in the reduced lattice basis: per
// vertex (s, t), unwrapped (meaningful modulo 1); per face the changes from
// its first corner to the other two; the flat metric of coordinate changes.
// s runs along the columns of the domain and t along its rows.
struct TorusMap {
  std::vector<Eigen::Vector2d> coords;
  std::vector<std::array<Eigen::Vector2d, 2>> steps;
  Eigen::Matrix2d metric;
  std::vector<char> used;

  // The same map in coordinates a * (s, t), a unimodular.
  TorusMap transformed(const Eigen::Matrix2d& a) const {
    TorusMap out = *this;
    for (auto& c : out.coords) c = a * c;
    for (auto& s : out.steps) s = {a * s[0], a * s[1]};
    const Eigen::Matrix2d inverse = a.inverse();
    out.metric = inverse.transpose() * metric * inverse;
    return out;
  }
};

TorusMap harmonic_torus_map(const TriangleMesh& surface) {
  const Topology topo = closed_genus1_topology(surface);
  const int nv = int(surface.n_vertices()), ne = int(topo.edge_ends.size());
  const int root = int(std::find(topo.used.begin(), topo.used.end(), 1) - topo.used.begin());
  const auto theta = generator_forms(surface, topo, root);
  const std::vector<double> w = cotan_weights(surface, topo);

  // Harmonic projection: minimise sum_e w_e (θ_e + u_b - u_a)², u_root = 0.
  std::vector<int> unknown(nv, -1);
  int n = 0;
  for (int v = 0; v < nv; ++v)
    if (topo.used[v] && v != root) unknown[v] = n++;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  for (int e = 0; e < ne; ++e) {
    const auto [a, b] = topo.edge_ends[e];
    const int ia = unknown[a], ib = unknown[b];
    if (ia >= 0) triplets.emplace_back(ia, ia, w[e]);
    if (ib >= 0) triplets.emplace_back(ib, ib, w[e]);
    if (ia >= 0 && ib >= 0) {
      triplets.emplace_back(ia, ib, -w[e]);
      triplets.emplace_back(ib, ia, -w[e]);
    }
    for (int k = 0; k < 2; ++k) {
      if (ia >= 0) rhs(ia, k) += w[e] * theta[k][e];
      if (ib >= 0) rhs(ib, k) -= w[e] * theta[k][e];
    }
  }
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  if (solver.info() != Eigen::Success)
    throw PartitionError("the harmonic map to the torus could not be computed (degenerate mesh)");
  const Eigen::MatrixXd solution = solver.solve(rhs);
  std::vector<Eigen::Vector2d> u(nv, Eigen::Vector2d::Zero());
  for (int v = 0; v < nv; ++v)
    if (unknown[v] >= 0) u[v] = solution.row(unknown[v]).transpose();
  std::vector<Eigen::Vector2d> h(ne);  // harmonic forms on the edges, first to second end
  for (int e = 0; e < ne; ++e)
    h[e] = Eigen::Vector2d(theta[0][e], theta[1][e]) + u[topo.edge_ends[e][1]] -
           u[topo.edge_ends[e][0]];

  // Dirichlet Gram matrix (the cotan energy with the same weights) and the
  // signed image area, which is the degree of the map: ±1.
  Eigen::Matrix2d gram = Eigen::Matrix2d::Zero();
  for (int e = 0; e < ne; ++e) gram += w[e] * h[e] * h[e].transpose();
  std::vector<std::array<Eigen::Vector2d, 2>> steps(surface.n_faces());  // t0->t1, t0->t2
  double degree = 0.0;
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const Triangle& t = surface.triangles[f];
    auto step = [&](int c) {
      const int e = topo.face_edges[f][c];
      return (sign_in_face(topo, e, t[c]) * h[e]).eval();
    };
    steps[f] = {step(0), (-step(2)).eval()};
    degree += 0.5 * (steps[f][0].x() * steps[f][1].y() - steps[f][1].x() * steps[f][0].y());
  }
  if (!(std::abs(degree) > 0.5))
    throw PartitionError("the harmonic map to the torus is degenerate (degree " +
                         std::to_string(degree) + ")");

  // Gauss reduction of the period lattice Z² in the conformal metric G⁻¹
  // (taken as adj(G): the scale does not matter).
  const Eigen::Matrix2d metric{{gram(1, 1), -gram(0, 1)}, {-gram(1, 0), gram(0, 0)}};
  using Lattice = Eigen::Matrix<long long, 2, 1>;
  auto dot = [&](const Lattice& a, const Lattice& b) {
    return a.cast<double>().dot(metric * b.cast<double>());
  };
  Lattice b1(1, 0), b2(0, 1);
  for (int iteration = 0; iteration < 200; ++iteration) {
    if (dot(b1, b1) > dot(b2, b2)) std::swap(b1, b2);
    const long long mu = std::llround(dot(b1, b2) / dot(b1, b1));
    if (mu == 0) break;
    b2 -= mu * b1;
  }
  // The domain's cells are split along b1 + b2: make that the shorter diagonal.
  if (dot(b1, b2) > 0) b2 = -b2;
  // Columns (s) and rows (t) counter-clockwise seen from outside, like the domain.
  if (degree * double(b1.x() * b2.y() - b2.x() * b1.y()) < 0) std::swap(b1, b2);
  Eigen::Matrix2d basis;
  basis << double(b1.x()), double(b2.x()), double(b1.y()), double(b2.y());
  const Eigen::Matrix2d inverse = basis.inverse();

  TorusMap map;
  map.used = topo.used;
  map.coords.resize(nv);
  for (int v = 0; v < nv; ++v) map.coords[v] = inverse * u[v];
  map.steps.resize(surface.n_faces());
  for (std::size_t f = 0; f < surface.n_faces(); ++f)
    map.steps[f] = {inverse * steps[f][0], inverse * steps[f][1]};
  map.metric = basis.transpose() * metric * basis;
  map.metric /= map.metric.trace();
  return map;
}

double wrap(double x) {
  return x - std::round(x);
}  // into [-1/2, 1/2]
double fraction(double x) {
  return x - std::floor(x);
}

// Mass over the periodic interval [0, 1), in bins.
class Histogram {
 public:
  explicit Histogram(int bins) : mass_(bins, 0.0) {}

  // Spreads `mass` evenly over [lo, hi] (unwrapped), so that coarse meshes
  // leave no empty bins.
  void add(double lo, double hi, double mass) {
    const int bins = int(mass_.size());
    const double shift = std::floor(lo);
    lo -= shift;
    hi = std::min(hi - shift, lo + 1.0);
    const int first = int(lo * bins), last = std::min(int(hi * bins), first + bins - 1);
    for (int b = first; b <= last; ++b) {
      const double share =
          hi - lo < 1e-12
              ? double(b == first)
              : (std::min(hi, double(b + 1) / bins) - std::max(lo, double(b) / bins)) / (hi - lo);
      mass_[b % bins] += share * mass;
    }
  }
  void smooth() {
    const int bins = int(mass_.size());
    std::vector<double> out(bins);
    for (int b = 0; b < bins; ++b)
      out[b] = 0.25 * mass_[(b + bins - 1) % bins] + 0.5 * mass_[b] + 0.25 * mass_[(b + 1) % bins];
    mass_ = std::move(out);
  }
  const std::vector<double>& mass() const { return mass_; }

 private:
  std::vector<double> mass_;
};

// Monotone map of the circle [0, 1) onto itself with a derivative
// proportional to a piecewise-constant density (uniform if it has no mass).
class Remap {
 public:
  explicit Remap(const std::vector<double>& density) : cumulative_(density.size() + 1, 0.0) {
    for (std::size_t b = 0; b < density.size(); ++b)
      cumulative_[b + 1] = cumulative_[b] + std::max(density[b], 0.0);
    const double total = cumulative_.back();
    for (std::size_t b = 0; b < cumulative_.size(); ++b)
      cumulative_[b] =
          total > 0 && std::isfinite(total) ? cumulative_[b] / total : double(b) / density.size();
  }
  double forward(double x) const {
    const int bins = int(cumulative_.size()) - 1;
    const double position = fraction(x) * bins;
    const int b = std::clamp(int(position), 0, bins - 1);
    return fraction(cumulative_[b] + (position - b) * (cumulative_[b + 1] - cumulative_[b]));
  }
  double inverse(double y) const {
    const int bins = int(cumulative_.size()) - 1;
    y = fraction(y);
    int b = int(std::upper_bound(cumulative_.begin(), cumulative_.end(), y) - cumulative_.begin());
    b = std::clamp(b - 1, 0, bins - 1);
    const double width = cumulative_[b + 1] - cumulative_[b];
    return (b + (width > 0 ? (y - cumulative_[b]) / width : 0.0)) / bins;
  }

 private:
  std::vector<double> cumulative_;
};

enum class Spacing { kLength, kArea };

// Spacing of one coordinate over the whole surface: equal steps cover equal
// length across its level sets (kLength: band area over the integral of
// |grad x|, the mean distance between level sets) or equal area (kArea).
Remap axis_spacing(const TriangleMesh& surface, const TorusMap& map, int axis, Spacing spacing) {
  const int bins = std::clamp(int(surface.n_faces() / 100), 16, 256);
  Histogram area(bins), gradient(bins);
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const Triangle& t = surface.triangles[f];
    const Vec3 &p0 = surface.positions[t[0]], &p1 = surface.positions[t[1]],
               &p2 = surface.positions[t[2]];
    const double x0 = map.coords[t[0]][axis];
    const double d1 = map.steps[f][0][axis], d2 = map.steps[f][1][axis];
    const double lo = x0 + std::min({0.0, d1, d2}), hi = x0 + std::max({0.0, d1, d2});
    area.add(lo, hi, 0.5 * (p1 - p0).cross(p2 - p0).norm());
    gradient.add(lo, hi, 0.5 * (d1 * (p0 - p2) + d2 * (p1 - p0)).norm());  // area * |grad x|
  }
  area.smooth();
  gradient.smooth();
  std::vector<double> density(area.mass());
  if (spacing == Spacing::kLength)
    for (int b = 0; b < bins; ++b)
      density[b] = gradient.mass()[b] > 0 ? area.mass()[b] / gradient.mass()[b] : 0.0;
  return Remap(density);
}

// The unused vertex nearest to (s, t) on the flat torus.
int flat_nearest(const TorusMap& map, const Eigen::Vector2d& target,
                 const std::vector<int>& taken) {
  int best = -1;
  double best_distance = HUGE_VAL;
  for (std::size_t v = 0; v < map.coords.size(); ++v) {
    if (!map.used[v] || std::find(taken.begin(), taken.end(), int(v)) != taken.end()) continue;
    const Eigen::Vector2d d(wrap(map.coords[v].x() - target.x()),
                            wrap(map.coords[v].y() - target.y()));
    const double distance = d.dot(map.metric * d);
    if (distance < best_distance) {
      best_distance = distance;
      best = int(v);
    }
  }
  if (best < 0) throw PartitionError("the surface has fewer than 9 vertices");
  return best;
}

// Features at the lattice ((col + offset_s) / 3, (row + offset_t) / 3) after
// re-spacing s and t separately.
std::vector<int> lattice_features(const TriangleMesh& surface, const TorusMap& map, Spacing spacing,
                                  double offset_s, double offset_t) {
  const Remap s = axis_spacing(surface, map, 0, spacing),
              t = axis_spacing(surface, map, 1, spacing);
  std::vector<int> features;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) {
      const Eigen::Vector2d target(s.inverse((col + offset_s) / 3),
                                   t.inverse((row + offset_t) / 3));
      features.push_back(flat_nearest(map, target, features));
    }
  return features;
}

// A piece of the level set t = const in one face, with s at its ends.
struct Segment {
  int face;
  Vec3 a, b;
  double sa, sb;
};

std::vector<Segment> level_set(const TriangleMesh& surface, const TorusMap& map, double level) {
  std::vector<Segment> segments;
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    const Triangle& tri = surface.triangles[f];
    const Eigen::Vector2d c0 = map.coords[tri[0]];
    const std::array<Eigen::Vector2d, 3> c{c0, c0 + map.steps[f][0], c0 + map.steps[f][1]};
    const double lo = std::min({c[0].y(), c[1].y(), c[2].y()});
    const double hi = std::max({c[0].y(), c[1].y(), c[2].y()});
    for (double value = level + std::ceil(lo - level); value <= hi; value += 1.0) {
      std::vector<std::pair<Vec3, double>> ends;
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if ((c[i].y() >= value) == (c[j].y() >= value)) continue;
        const double r = (value - c[i].y()) / (c[j].y() - c[i].y());
        ends.push_back({surface.positions[tri[i]] +
                            r * (surface.positions[tri[j]] - surface.positions[tri[i]]),
                        c[i].x() + r * (c[j].x() - c[i].x())});
      }
      if (ends.size() == 2)
        segments.push_back({int(f), ends[0].first, ends[1].first, ends[0].second, ends[1].second});
    }
  }
  return segments;
}

// Features on three level sets of t spaced by length over the surface, each
// row spaced by length along its own level set: this follows the surface
// where the conformal map squeezes it (a teapot's body seen from its handle).
std::vector<int> row_features(const TriangleMesh& surface, const TorusMap& map, double offset_s,
                              double offset_t) {
  const Remap rows = axis_spacing(surface, map, 1, Spacing::kLength);
  std::vector<int> features;
  for (int row = 0; row < 3; ++row) {
    const double level = rows.inverse((row + offset_t) / 3);
    const std::vector<Segment> segments = level_set(surface, map, level);
    Histogram length(128);
    for (const Segment& g : segments)
      length.add(std::min(g.sa, g.sb), std::max(g.sa, g.sb), (g.b - g.a).norm());
    const Remap along(length.mass());
    for (int col = 0; col < 3; ++col) {
      const double s = along.inverse((col + offset_s) / 3);
      int chosen = -1;
      for (const Segment& g : segments) {
        const double lo = std::min(g.sa, g.sb), hi = std::max(g.sa, g.sb);
        const double value = s + std::ceil(lo - s);
        if (value > hi) continue;
        const double r = hi > lo ? (value - g.sa) / (g.sb - g.sa) : 0.0;
        const Vec3 point = g.a + r * (g.b - g.a);
        // The nearest free corner of the face the point lies in.
        double best = HUGE_VAL;
        for (int v : surface.triangles[g.face]) {
          const double d = (surface.positions[v] - point).squaredNorm();
          if (d < best && std::find(features.begin(), features.end(), v) == features.end()) {
            best = d;
            chosen = v;
          }
        }
        break;
      }
      if (chosen < 0) chosen = flat_nearest(map, {s, level}, features);
      features.push_back(chosen);
    }
  }
  return features;
}

// How evenly a feature set covers the surface: the area-weighted RMS
// edge-path distance to the nearest feature (the centroidal Voronoi energy),
// relative to the square root of the area. Lower is better spread.
class SpreadMeter {
 public:
  explicit SpreadMeter(const TriangleMesh& surface)
      : adjacency_(surface.n_vertices()), area_(surface.n_vertices(), 0.0) {
    for (std::size_t f = 0; f < surface.n_faces(); ++f) {
      const Triangle& t = surface.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        adjacency_[a].push_back({b, (surface.positions[a] - surface.positions[b]).norm()});
        area_[a] += face_area(surface, f) / 3;
      }
    }
    for (double a : area_) total_ += a;
  }

  double operator()(const std::vector<int>& features) const {
    std::vector<double> distance(adjacency_.size(), HUGE_VAL);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    for (int f : features) open.push({distance[f] = 0.0, f});
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > distance[v]) continue;
      for (const auto& [w, l] : adjacency_[v])
        if (d + l < distance[w]) open.push({distance[w] = d + l, w});
    }
    double energy = 0.0;
    for (std::size_t v = 0; v < distance.size(); ++v)
      if (area_[v] > 0) energy += area_[v] * distance[v] * distance[v];
    return total_ > 0 ? std::sqrt(energy) / total_ : 0.0;
  }

 private:
  std::vector<std::vector<std::pair<int, double>>> adjacency_;  // directed edges, each once
  std::vector<double> area_;
  double total_ = 0.0;
};

struct Candidate {
  std::vector<int> features;
  double spread = 0.0;
  Eigen::Matrix2d frame;  // the torus map's coordinates the lattice was laid in
  bool mirrored = false;
};

const Eigen::Matrix2d kIdentity{{1, 0}, {0, 1}};
// Rows and columns exchanged, orientation kept: (s, t) -> (t, -s); the cells
// are then split along the other diagonal.
const Eigen::Matrix2d kExchange{{0, 1}, {-1, 0}};
// The grid mirrored: its order can only be realised with twisted paths.
const Eigen::Matrix2d kMirror{{0, 1}, {1, 0}};

// Feature sets from both assignments of the torus directions to rows and
// columns, three ways of spacing, and the 3×3 lattice offsets by thirds of a
// cell; distinct sets only, the best spread first.
std::vector<Candidate> torus_candidates(const TriangleMesh& surface, const TorusMap& map,
                                        bool mirrored, const SpreadMeter& spread) {
  std::vector<Candidate> candidates;
  std::set<std::vector<int>> seen;
  Eigen::Matrix2d transform;
  auto add = [&](std::vector<int> features) {
    if (seen.insert(features).second)
      candidates.push_back({std::move(features), 0.0, transform, mirrored});
  };
  for (const Eigen::Matrix2d& a : {kIdentity, kExchange}) {
    transform = mirrored ? Eigen::Matrix2d(kMirror * a) : a;
    const TorusMap frame = map.transformed(transform);
    for (int i = 0; i < 9; ++i) {
      const double offset_s = (i % 3) / 3.0, offset_t = (i / 3) / 3.0;
      add(row_features(surface, frame, offset_s, offset_t));
      add(lattice_features(surface, frame, Spacing::kLength, offset_s, offset_t));
      add(lattice_features(surface, frame, Spacing::kArea, offset_s, offset_t));
    }
  }
  for (Candidate& c : candidates) c.spread = spread(c.features);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.spread < b.spread; });
  return candidates;
}

// Candidates are traced in order of spread; once one is valid, those with a
// spread up to this factor worse compete on total length, at most kMaxValid.
constexpr double kSpreadTolerance = 1.05;
constexpr int kMaxValid = 6;
// Bounds the time spent on surfaces where the tracer keeps failing.
constexpr int kMaxTraced = 32;

// Points of the surface on the flat torus for the homotopy guide of
// trace_path_network: the torus map in the frame the features were laid in,
// each axis re-spaced by area. Re-spacing is a monotone map of each circle,
// so the homotopy classes are the torus map's, but the features come close
// to the grid points even where the conformal map squeezes the surface into
// a sliver (all of a teapot's body sits within 0.05 of one point of it).
std::vector<Eigen::Vector2d> guide_points(const TriangleMesh& surface, const TorusMap& map,
                                          const Eigen::Matrix2d& frame) {
  const TorusMap framed = map.transformed(frame);
  const Remap s = axis_spacing(surface, framed, 0, Spacing::kArea),
              t = axis_spacing(surface, framed, 1, Spacing::kArea);
  std::vector<Eigen::Vector2d> points;
  points.reserve(framed.coords.size());
  for (const Eigen::Vector2d& c : framed.coords)
    points.emplace_back(s.forward(c.x()), t.forward(c.y()));
  return points;
}

PartitionOptions guided(const PartitionOptions& options, std::vector<Eigen::Vector2d> points,
                        const TriangleMesh& domain) {
  PartitionOptions out = options;
  out.surface_torus_points = std::move(points);
  for (const Vec3& p : domain.positions) out.domain_torus_points.emplace_back(p.x(), p.y());
  return out;
}

}  // namespace

std::vector<int> choose_torus_features(const TriangleMesh& surface) {
  const TorusMap map = harmonic_torus_map(surface);
  return torus_candidates(surface, map, false, SpreadMeter(surface)).front().features;
}

std::vector<PathNetwork> trace_torus_networks(const TriangleMesh& surface,
                                              const PartitionOptions& options) {
  const TorusMap map = harmonic_torus_map(surface);
  const SpreadMeter spread(surface);
  const TriangleMesh domain = domain::torus_3x3();
  // One progress bar over all traces: monotone, an estimate of the share done.
  double shown = 0.0;
  int attempt = 0;
  PartitionOptions step = options;
  if (options.progress)
    step.progress = [&](double p) {
      shown = std::max(shown, std::min(1.0, (attempt - 1 + p) / kMaxValid));
      options.progress(shown);
    };
  std::string last_error = "no candidates";
  // The mirrored grid only when no candidate of the right orientation works.
  for (bool mirrored : {false, true}) {
    const std::vector<Candidate> candidates = torus_candidates(surface, map, mirrored, spread);
    const int budget = mirrored ? kMaxTraced / 4 : kMaxTraced;
    std::vector<PathNetwork> valid_networks;
    double best_spread = 0.0;
    int valid = 0, traced = 0;
    for (const Candidate& c : candidates) {
      if (valid && (c.spread > kSpreadTolerance * best_spread || valid == kMaxValid)) break;
      if (traced++ == budget) break;
      ++attempt;
      try {
        PathNetwork network = trace_path_network(
            surface, domain, c.features,
            c.mirrored ? step : guided(step, guide_points(surface, map, c.frame), domain));
        if (!valid++) best_spread = c.spread;
        valid_networks.push_back(std::move(network));
      } catch (const PartitionError& e) {
        last_error = e.what();
      }
    }
    if (!valid_networks.empty()) {
      if (options.progress) options.progress(1.0);
      std::stable_sort(valid_networks.begin(), valid_networks.end(),
                       [](const PathNetwork& a, const PathNetwork& b) {
                         return a.total_length() < b.total_length();
                       });
      return valid_networks;
    }
  }
  throw PartitionError("no 3x3 torus path network found (" + std::to_string(attempt) +
                       " feature sets tried); the last error: " + last_error);
}

PathNetwork trace_torus_network(const TriangleMesh& surface, const PartitionOptions& options) {
  return std::move(trace_torus_networks(surface, options).front());
}

PathNetwork trace_torus_network(const TriangleMesh& surface, const std::vector<int>& features,
                                const PartitionOptions& options) {
  const TriangleMesh domain = domain::torus_3x3();
  if (features.size() != domain.n_vertices())
    throw PartitionError(std::to_string(features.size()) +
                         " features given, the 3x3 torus has 9 vertices");
  for (std::size_t i = 0; i < features.size(); ++i)
    if (features[i] < 0 || std::size_t(features[i]) >= surface.n_vertices())
      throw PartitionError("feature " + std::to_string(i) + ": vertex index " +
                           std::to_string(features[i]) + " out of range (the surface has " +
                           std::to_string(surface.n_vertices()) + " vertices)");
  const TorusMap map = harmonic_torus_map(surface);
  // Of the four orientation-preserving frames (rows and columns along the
  // reduced lattice directions), the one and the translation in which the
  // features sit closest to the grid points.
  std::vector<Eigen::Vector2d> best_points;
  double best_error = INFINITY;
  for (const Eigen::Matrix2d& frame :
       {kIdentity, kExchange, Eigen::Matrix2d(-kIdentity), Eigen::Matrix2d(-kExchange)}) {
    std::vector<Eigen::Vector2d> points = guide_points(surface, map, frame);
    std::vector<Eigen::Vector2d> offsets;  // feature point minus grid point
    for (std::size_t i = 0; i < features.size(); ++i)
      offsets.push_back(points[features[i]] -
                        Eigen::Vector2d(domain.positions[i].x(), domain.positions[i].y()));
    for (const Eigen::Vector2d& shift : offsets) {
      double error = 0;
      for (const Eigen::Vector2d& o : offsets)
        error += Eigen::Vector2d(wrap(o.x() - shift.x()), wrap(o.y() - shift.y())).squaredNorm();
      if (error < best_error) best_error = error, best_points = points;
    }
  }
  return trace_path_network(surface, domain, features,
                            guided(options, std::move(best_points), domain));
}

}  // namespace ism
