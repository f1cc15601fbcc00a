// Compatible path networks on two surfaces (paper §4).
//
// The base mesh is not given: it grows as a graph embedded in both surfaces
// at once. Each edge is a pair of paths (one per surface) between the two
// vertices of a feature pair; each feature keeps one cyclic order of its
// edges (darts), the same on both surfaces, so the graph has one rotation
// system and therefore the same faces (boundary walks) on both.
//
// Greedy, as the paper: candidate pairs of paths wait in a queue ordered by
// the sum of their two (area-normalised) lengths, are traced again when the
// network changed since (lazily, when they come to the top), and the first
// valid one is inserted. Three phases keep every step consistent:
//  1. a spanning tree of the features: a path between two components never
//     separates the surface;
//  2. 2g non-separating cycles: an arc between two corners of one boundary
//     walk of the (single) region is non-separating exactly when it crosses
//     some closed curve of the region an odd number of times (homology mod 2);
//     the search runs on the two-sheeted cover that counts crossings of each
//     curve of a basis (tree-cotree on the region), which finds the shortest
//     non-separating arc directly. (The paper finds it by two breadth-first
//     searches after Lazarus et al.; the result is the same kind of arc.)
//     Then the single region is a disc on both surfaces, with one boundary
//     walk, the same on both;
//  3. paths between corners of one disc, each splitting it into two discs,
//     until every disc is a triangle.
// A path's ends must leave and enter its features in the same sectors
// (corners) on both surfaces. When the shortest paths of a pair disagree,
// each side's sectors are imposed on the other and the shorter pair is kept.
// Every insertion is checked on both surfaces (regions counted, the cyclic
// orders compared) and undone when they differ.
//
// Features are added as the paper does: on a cycle that would close on one
// feature (two) or join two features already joined (one), and on a splitting
// path whose two features are already joined (one), so that the base stays a
// simplicial mesh. Boundary loops are capped (network_surface.hpp); their
// centres are features; after tracing, the paths to a centre are clipped at
// the loop (the clip points become features), the loop between clip points
// becomes paths, and the faces this leaves that are not triangles are split
// by the same greedy; the caps are then removed.
#include "partition/compatible_networks.hpp"

#include "mesh/union_find.hpp"
#include "partition/compatible_detail.hpp"
#include "partition/network_surface.hpp"
#include "partition/patches.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <set>

namespace ism {

const char* to_string(FeatureOrigin origin) {
  switch (origin) {
    case FeatureOrigin::given:
      return "given";
    case FeatureOrigin::automatic:
      return "automatic";
    case FeatureOrigin::cycle:
      return "cycle";
    case FeatureOrigin::split:
      return "split";
    case FeatureOrigin::clip:
      return "clip";
  }
  return "?";
}

namespace {

using namespace partition_detail;

enum class Phase { tree, cycles, discs, done };

struct Feature {
  std::array<int, 2> v;
  FeatureOrigin origin;
  int centre_of = -1;  // loop whose centre this is
};

struct Edge {
  int i, j;
  std::array<std::vector<int>, 2> path;  // from feature i to feature j
};

struct Candidate {
  double priority = 0, length = 0;
  int i = -1, j = -1;
  int ki = -1, kj = -1;  // sectors at i and j
  std::array<std::vector<int>, 2> path;
  bool wrong_side = false, side_checked = false;
  std::size_t checked_with = 0;  // features when the sides were checked
  bool needs_split = false;      // a loop, or two features already joined
  bool lasso = false;            // path: a stem from i to a new feature; cycle: a loop there
  std::array<std::vector<int>, 2> cycle;
  std::uint64_t version = 0;
  int face_dart = -1;     // disc phase: a dart of the face the path splits
  std::vector<int> face;  // and that face's darts then, sorted
};

struct LaterFirst {
  bool operator()(const Candidate& a, const Candidate& b) const {
    if (a.wrong_side != b.wrong_side) return a.wrong_side;
    if (a.priority != b.priority) return a.priority > b.priority;
    return std::tie(a.i, a.j, a.ki, a.kj) > std::tie(b.i, b.j, b.ki, b.kj);
  }
};

// Runs fn(0) and fn(1), the same work on surface A and on B, side by side:
// the two surfaces share nothing that either call writes.
template <class Fn>
void on_both(const Fn& fn) {
  tbb::parallel_invoke([&] { fn(0); }, [&] { fn(1); });
}

class CompatibleTracer {
 public:
  CompatibleTracer(const std::array<const TriangleMesh*, 2>& surfaces,
                   const std::array<std::vector<std::vector<int>>, 2>& loops, int genus,
                   const CompatibleOptions& options)
      : surf_{NetworkSurface(*surfaces[0], loops[0]), NetworkSurface(*surfaces[1], loops[1])},
        genus_(genus),
        options_(options) {
    for (std::size_t l = 0; l < loops[0].size(); ++l)
      add_feature({surf_[0].centre(l), surf_[1].centre(l)}, FeatureOrigin::automatic, int(l));
  }

  int add_feature(std::array<int, 2> v, FeatureOrigin origin, int centre_of = -1) {
    const int f = int(features_.size());
    features_.push_back({v, origin, centre_of});
    rot_.emplace_back();
    darts_at_.emplace_back();
    component_.push_back(f);
    for (int s = 0; s < 2; ++s) surf_[s].mark_feature(v[s]);
    features_changed();
    return f;
  }

  const NetworkSurface& surface(int s) const { return surf_[s]; }
  const std::vector<Feature>& features() const { return features_; }
  const std::vector<Edge>& edges() const { return edges_; }
  std::atomic<std::size_t> candidates_traced = 0;
  std::size_t sector_conflicts = 0, swirl_delays = 0, reroutes = 0;

  /// Features on a loop are joined to the loop's centre first (one cap edge
  /// each), in the loop's order; the orders must agree on both surfaces.
  void connect_boundary_features();
  void prepare() {
    on_both([&](int s) {
      surf_[s].split_blocked_edges();
      regions_[s] = surf_[s].count_regions();
    });
  }
  void run();
  void clip_boundaries();
  /// Faces of length 3: (tail of each dart) in walk order.
  std::vector<std::array<int, 3>> triangles();

 private:
  // ---- the rotation system ----------------------------------------------
  int tail(int d) const { return d % 2 ? edges_[d / 2].j : edges_[d / 2].i; }
  int head(int d) const { return tail(d ^ 1); }
  /// The vertex of the feature a dart leaves, on surface s.
  int tail_vertex(int d, int s) const { return features_[tail(d)].v[s]; }
  int first_step(int d, int s) const {
    const auto& p = edges_[d / 2].path[s];
    return d % 2 ? p[p.size() - 2] : p[1];
  }
  int sectors(int f) const { return std::max<int>(1, int(rot_[f].size())); }
  SearchEnd end_at(int s, int f, int sector) const;
  /// Darts at f ordered counter-clockwise on surface s, starting with the smallest.
  std::vector<int> geometric_rotation(int s, int f) const;
  void compute_faces();
  int corner_face(int f, int k) const {
    return rot_[f].empty() ? -1 - f : face_of_dart_[rot_[f][k]];
  }

  // ---- state --------------------------------------------------------------
  void features_changed();
  /// An edge joins i and j (counted with multiplicity while edges split).
  bool joined(int i, int j) const {
    const auto it = adjacent_.find(std::minmax(i, j));
    return it != adjacent_.end() && it->second > 0;
  }
  /// Two features on one boundary loop: a path between them would leave,
  /// once the cap is gone, a loop edge beside it between the same two.
  bool on_same_loop(int i, int j) const {
    if (surf_[0].vertex_class(features_[i].v[0]) != VertexClass::boundary ||
        surf_[0].vertex_class(features_[j].v[0]) != VertexClass::boundary)
      return false;
    for (std::size_t c = 0; c < features_.size(); ++c)
      if (features_[c].centre_of >= 0 && joined(int(c), i) && joined(int(c), j)) return true;
    return false;
  }
  /// Makes feature f the first end of edge e (reverses it if needed).
  void orient_edge_from(int e, int f);
  int find(int f) const {
    while (component_[f] != f) f = component_[f];
    return f;
  }
  int components() const {
    int n = 0;
    for (std::size_t f = 0; f < features_.size(); ++f) n += find(int(f)) == int(f);
    return n;
  }
  Phase phase() const;

  // ---- candidates ---------------------------------------------------------
  std::optional<TracedPath> trace_on(int s, int i, int ki, int j, int kj, bool cycle);
  std::optional<Candidate> trace_free(int i, int j, bool cycle);
  std::optional<Candidate> trace_fixed(int i, int ki, int j, int kj);
  std::optional<TracedPath> odd_walk(int s, int i, int ki);
  std::optional<std::array<std::vector<int>, 2>> lasso_of(int s, int i,
                                                          const TracedPath& walk) const;
  std::optional<Candidate> trace_lasso(int i);
  int sector_of(int s, int f, int w) const;
  void finish_candidate(Candidate& c) const;
  void generate(Phase phase, bool exhaustive);
  void generate_face(int face, bool exhaustive);
  bool stale(const Candidate& c) const;
  bool paths_free(const Candidate& c) const;
  bool pop(Phase phase, Candidate& out);
  struct Offence {
    int feature;              // a neighbouring feature
    std::array<int, 2> side;  // its side of the path on A and on B
  };
  std::optional<Offence> offence(const Candidate& c);
  bool wrong_side(const Candidate& c);
  std::optional<Candidate> reroute(const Candidate& c);

  // ---- insertion ----------------------------------------------------------
  struct Snapshot {
    std::size_t features, edges;
    std::vector<std::vector<int>> rot, darts_at;
    std::vector<int> component;
    std::map<std::pair<int, int>, int> adjacent;
    std::array<int, 2> regions;
  };
  Snapshot snapshot() const;
  void restore(const Snapshot& snap, const std::vector<std::array<std::vector<int>, 2>>& added);
  bool place(int e, int delta, std::initializer_list<int> check);
  std::optional<std::vector<std::array<std::size_t, 2>>> cuts_for(
      const std::array<std::vector<int>, 2>& path, bool closed) const;
  int add_edge(int i, int j, const std::array<std::vector<int>, 2>& path);
  bool commit(const Candidate& c, Phase phase);
  int split_edge(int e, const std::array<std::size_t, 2>& at, FeatureOrigin origin);
  std::optional<std::array<std::size_t, 2>> split_point(const std::array<std::vector<int>, 2>& path,
                                                        double fraction, std::size_t after) const;

  std::array<NetworkSurface, 2> surf_;
  int genus_;
  CompatibleOptions options_;
  std::vector<Feature> features_;
  std::vector<Edge> edges_;
  std::vector<std::vector<int>> rot_;            // counter-clockwise darts per feature
  std::vector<std::vector<int>> darts_at_;       // unordered, kept in step with edges_
  std::vector<int> component_;                   // union-find parents
  std::map<std::pair<int, int>, int> adjacent_;  // edges per feature pair
  std::array<int, 2> regions_{1, 1};
  std::vector<int> face_of_dart_;
  std::vector<std::vector<int>> faces_;
  std::vector<std::vector<int>> nearest_;
  std::vector<char> extremity_;
  std::uint64_t version_ = 1;
  std::array<std::uint64_t, 2> cycles_version_{0, 0};
  std::array<std::vector<EdgeSet>, 2> cycles_;
  std::priority_queue<Candidate, std::vector<Candidate>, LaterFirst> queue_;
  std::set<std::tuple<int, int, int, int>> rejected_;  // until the next insertion
  std::map<std::pair<int, int>, Candidate> traced_;    // disc phase: by corner darts
};

// ---------------------------------------------------------------------------

SearchEnd CompatibleTracer::end_at(int s, int f, int sector) const {
  SearchEnd e;
  const NetworkSurface& surf = surf_[s];
  e.vertex = features_[f].v[s];
  const auto& rot = rot_[f];
  const int n = sectors(f);
  for (int k = 0; k < n; ++k) {
    if (sector >= 0 && k != sector) continue;
    std::vector<int> ring;
    if (rot.empty())
      ring = surf.ring(e.vertex);
    else
      ring = surf.ring_between(e.vertex, first_step(rot[k], s),
                               first_step(rot[(k + 1) % rot.size()], s));
    for (int w : ring)
      if (surf.may_leave_through(e.vertex, w)) {
        e.ring.push_back(w);
        e.sector.push_back(k);
      }
  }
  return e;
}

std::vector<int> CompatibleTracer::geometric_rotation(int s, int f) const {
  const std::vector<int> ring = surf_[s].ring(features_[f].v[s]);
  std::vector<std::pair<std::size_t, int>> order;
  for (int d : darts_at_[f]) {
    const auto at = std::find(ring.begin(), ring.end(), first_step(d, s));
    order.push_back({std::size_t(at - ring.begin()), d});
  }
  std::sort(order.begin(), order.end());
  std::vector<int> out;
  for (const auto& [position, d] : order) out.push_back(d);
  if (!out.empty()) std::rotate(out.begin(), std::min_element(out.begin(), out.end()), out.end());
  return out;
}

// Faces are the orbits of next(d): at the head of d, the dart just before
// reverse(d) counter-clockwise. The face of d lies on its left; the corner
// (f, k) between darts k and k+1 is the face of dart k.
void CompatibleTracer::compute_faces() {
  const int darts = int(2 * edges_.size());
  std::vector<int> position(darts, -1);
  for (const auto& rot : rot_)
    for (std::size_t k = 0; k < rot.size(); ++k) position[rot[k]] = int(k);
  face_of_dart_.assign(darts, -1);
  faces_.clear();
  for (int d0 = 0; d0 < darts; ++d0) {
    if (face_of_dart_[d0] >= 0) continue;
    std::vector<int> face;
    int d = d0;
    do {
      face_of_dart_[d] = int(faces_.size());
      face.push_back(d);
      const auto& rot = rot_[head(d)];
      const int p = position[d ^ 1], m = int(rot.size());
      d = rot[(p + m - 1) % m];
    } while (d != d0);
    faces_.push_back(std::move(face));
  }
}

void CompatibleTracer::features_changed() {
  const std::size_t n = features_.size();
  auto distance = [&](std::size_t a, std::size_t b) {
    double d = 0;
    for (int s = 0; s < 2; ++s)
      d += (surf_[s].position(features_[a].v[s]) - surf_[s].position(features_[b].v[s])).norm() *
           surf_[s].scale();
    return d;
  };
  nearest_.assign(n, {});
  std::vector<double> spread(n, 0);
  for (std::size_t a = 0; a < n; ++a) {
    std::vector<std::pair<double, int>> d;
    for (std::size_t b = 0; b < n; ++b)
      if (a != b) d.push_back({distance(a, b), int(b)});
    std::sort(d.begin(), d.end());
    for (std::size_t k = 0; k < d.size() && int(k) < options_.nearest; ++k)
      nearest_[a].push_back(d[k].second);
    // Extremities (paper §4, swirls): mean distance to the 8 nearest.
    const std::size_t k = std::min<std::size_t>(8, d.size());
    for (std::size_t t = 0; t < k; ++t) spread[a] += d[t].first / double(k);
  }
  extremity_.assign(n, 0);
  if (n >= 4) {
    std::vector<double> sorted = spread;
    std::sort(sorted.begin(), sorted.end());
    const double threshold = sorted[n - std::max<std::size_t>(1, n / 4)];
    for (std::size_t a = 0; a < n; ++a) extremity_[a] = spread[a] >= threshold;
  }
}

Phase CompatibleTracer::phase() const {
  if (components() > 1) return Phase::tree;
  const long cycles = long(edges_.size()) - long(features_.size()) + 1;
  if (cycles < 2 * genus_) return Phase::cycles;
  for (const auto& face : faces_)
    if (face.size() > 3) return Phase::discs;
  return Phase::done;
}

// ---------------------------------------------------------------------------

std::optional<TracedPath> CompatibleTracer::trace_on(int s, int i, int ki, int j, int kj,
                                                     bool cycle) {
  NetworkSurface& surf = surf_[s];
  ++candidates_traced;
  if (!cycle) return surf.shortest_path(end_at(s, i, ki), end_at(s, j, kj));
  if (cycles_version_[s] != version_) {
    cycles_[s] = surf.complement_cycles();
    cycles_version_[s] = version_;
  }
  // An arc between corners of different boundary walks never separates; one
  // between corners of the same walk must cross some basis curve oddly.
  const SearchEnd to = end_at(s, j, kj);
  std::optional<TracedPath> best;
  for (int k = 0; k < sectors(i); ++k) {
    if (ki >= 0 && k != ki) continue;
    const SearchEnd from = end_at(s, i, k);
    ParityRule rule;
    rule.odd.assign(sectors(j), 0);
    bool any_odd = false;
    for (int t = 0; t < sectors(j); ++t)
      any_odd |= rule.odd[t] = corner_face(i, k) == corner_face(j, t);
    auto keep = [&](std::optional<TracedPath> p) {
      if (p && (!best || p->length < best->length)) best = std::move(p);
    };
    if (!any_odd) {
      keep(surf.shortest_path(from, to));
      continue;
    }
    for (const EdgeSet& curve : cycles_[s]) {
      rule.crossing = &curve;
      keep(surf.shortest_path(from, to, &rule, best ? best->length : INFINITY));
    }
  }
  return best;
}

int CompatibleTracer::sector_of(int s, int f, int w) const {
  const SearchEnd e = end_at(s, f, -1);
  for (std::size_t k = 0; k < e.ring.size(); ++k)
    if (e.ring[k] == w) return e.sector[k];
  return -1;
}

// The shortest closed walk from feature i back to it that crosses some basis
// curve of the complement an odd number of times (it may pass a vertex twice).
std::optional<TracedPath> CompatibleTracer::odd_walk(int s, int i, int ki) {
  NetworkSurface& surf = surf_[s];
  if (cycles_version_[s] != version_) {
    cycles_[s] = surf.complement_cycles();
    cycles_version_[s] = version_;
  }
  const SearchEnd to = end_at(s, i, -1);
  std::optional<TracedPath> best;
  for (int k = 0; k < sectors(i); ++k) {
    if (ki >= 0 && k != ki) continue;
    const SearchEnd from = end_at(s, i, k);
    ParityRule rule;
    rule.odd.assign(sectors(i), 1);
    for (const EdgeSet& curve : cycles_[s]) {
      rule.crossing = &curve;
      ++candidates_traced;
      auto p = surf.shortest_path(from, to, &rule, best ? best->length : INFINITY, true);
      if (p && (!best || p->length < best->length)) best = std::move(p);
    }
  }
  return best;
}

// A lasso from an odd closed walk: a stem from i to a vertex P and a simple
// cycle through P, crossing the walk's basis curve oddly. A walk that passes
// a vertex twice goes out along the stem, around the cycle and back; a
// simple walk is pushed off i through i's ring (P is then its first vertex),
// which keeps its crossings' parity.
std::optional<std::array<std::vector<int>, 2>> CompatibleTracer::lasso_of(
    int s, int i, const TracedPath& walk) const {
  const std::vector<int>& w = walk.vertices;
  const std::size_t m = w.size() - 1;  // w[0] == w[m] == feature
  std::vector<int> stem, cycle;
  if (walk.simple) {
    const NetworkSurface& surf = surf_[s];
    const int v = features_[i].v[s];
    const std::set<int> on_walk(w.begin(), w.end());
    std::optional<std::vector<int>> arc;
    for (int side = 0; side < 2; ++side) {
      std::vector<int> a =
          side ? surf.ring_between(v, w[1], w[m - 1]) : surf.ring_between(v, w[m - 1], w[1]);
      if (side) std::reverse(a.begin(), a.end());
      bool ok = true;
      for (int r : a) ok &= surf.may_leave_through(v, r) && !on_walk.count(r);
      if (ok && (!arc || a.size() < arc->size())) arc = std::move(a);
    }
    if (!arc) return std::nullopt;
    stem = {w[0], w[1]};
    cycle.assign(w.begin() + 1, w.begin() + std::ptrdiff_t(m));
    cycle.insert(cycle.end(), arc->begin(), arc->end());
    cycle.push_back(w[1]);
  } else {
    // The innermost repeat whose two visits are on different sheets.
    std::size_t a0 = 0, b0 = 0;
    for (std::size_t a = 1; a < m; ++a)
      for (std::size_t b = a + 1; b < m; ++b)
        if (w[a] == w[b] && walk.sheet[a] != walk.sheet[b] && (!b0 || b - a < b0 - a0)) {
          const std::set<int> inner(w.begin() + std::ptrdiff_t(a) + 1,
                                    w.begin() + std::ptrdiff_t(b));
          if (inner.size() == b - a - 1 && !inner.count(w[a])) a0 = a, b0 = b;
        }
    if (!b0) return std::nullopt;
    cycle.assign(w.begin() + std::ptrdiff_t(a0), w.begin() + std::ptrdiff_t(b0) + 1);
    // The stem ends where it first meets the cycle.
    const std::set<int> on_cycle(cycle.begin(), cycle.end());
    std::size_t q = 1;
    while (!on_cycle.count(w[q])) ++q;
    stem.assign(w.begin(), w.begin() + std::ptrdiff_t(q) + 1);
    if (std::set<int>(stem.begin(), stem.end()).size() != stem.size()) return std::nullopt;
    const auto at = std::find(cycle.begin(), cycle.end() - 1, w[q]);
    std::vector<int> rotated(at, cycle.end() - 1);
    rotated.insert(rotated.end(), cycle.begin(), at);
    rotated.push_back(w[q]);
    cycle = std::move(rotated);
  }
  if (cycle.size() < 4) return std::nullopt;  // room for two features
  return std::array<std::vector<int>, 2>{std::move(stem), std::move(cycle)};
}

// A cycle for feature i alone (paper §4: "we trace non-separating cycles
// connecting to one of the existing features ... and create two new feature
// constraints"): a simple loop through i, or else a lasso.
std::optional<Candidate> CompatibleTracer::trace_lasso(int i) {
  if (auto loop = trace_free(i, i, true)) return loop;
  if (features_[i].centre_of >= 0) return std::nullopt;  // a stem would run along the loop
  std::array<std::optional<TracedPath>, 2> walk;
  on_both([&](int s) { walk[s] = odd_walk(s, i, -1); });
  if (!walk[0] || !walk[1]) return std::nullopt;
  std::array<std::optional<std::array<std::vector<int>, 2>>, 2> lasso{lasso_of(0, i, *walk[0]),
                                                                      lasso_of(1, i, *walk[1])};
  auto sector = [&](int s) { return sector_of(s, i, (*lasso[s])[0][1]); };
  if (lasso[0] && lasso[1] && sector(0) != sector(1)) {
    // Each side's stem sector imposed on the other; the shorter pair wins.
    ++sector_conflicts;
    std::array<std::optional<std::array<std::vector<int>, 2>>, 2> alt;
    for (int s = 0; s < 2; ++s)
      if (auto w = odd_walk(s, i, sector(1 - s))) alt[s] = lasso_of(s, i, *w);
    auto total = [&](int s, const std::optional<std::array<std::vector<int>, 2>>& l) {
      return l ? surf_[s].length((*l)[0]) + surf_[s].length((*l)[1]) : INFINITY;
    };
    const double keep_a = total(0, lasso[0]) + total(1, alt[1]);
    const double keep_b = total(0, alt[0]) + total(1, lasso[1]);
    if (!std::isfinite(keep_a) && !std::isfinite(keep_b)) return std::nullopt;
    if (keep_a <= keep_b)
      lasso[1] = alt[1];
    else
      lasso[0] = alt[0];
  }
  if (!lasso[0] || !lasso[1]) return std::nullopt;
  Candidate c;
  c.i = c.j = i;
  c.ki = c.kj = sector_of(0, i, (*lasso[0])[0][1]);
  c.lasso = c.needs_split = true;
  for (int s = 0; s < 2; ++s) {
    c.path[s] = (*lasso[s])[0];
    c.cycle[s] = (*lasso[s])[1];
  }
  finish_candidate(c);
  c.length += surf_[0].length(c.cycle[0]) + surf_[1].length(c.cycle[1]);
  c.priority = c.length;
  return c;
}

void CompatibleTracer::finish_candidate(Candidate& c) const {
  c.length = surf_[0].length(c.path[0]) + surf_[1].length(c.path[1]);
  const bool extreme = options_.swirl_heuristics && (extremity_[c.i] || extremity_[c.j]);
  c.priority = extreme ? 0.5 * c.length : c.length;
  c.version = version_;
}

std::optional<Candidate> CompatibleTracer::trace_free(int i, int j, bool cycle) {
  if (on_same_loop(i, j)) return std::nullopt;
  std::array<std::optional<TracedPath>, 2> p;
  on_both([&](int s) { p[s] = trace_on(s, i, -1, j, -1, cycle); });
  auto& pa = p[0];
  auto& pb = p[1];
  if (!pa || !pb) return std::nullopt;
  Candidate c;
  c.i = i, c.j = j;
  if (pa->leave_sector != pb->leave_sector || pa->enter_sector != pb->enter_sector) {
    // The two shortest paths use different corners: impose each side's
    // corners on the other and keep the better pair.
    ++sector_conflicts;
    std::array<std::optional<TracedPath>, 2> q;
    on_both([&](int s) {
      q[s] = trace_on(s, i, p[1 - s]->leave_sector, j, p[1 - s]->enter_sector, cycle);
    });
    auto& pa2 = q[0];
    auto& pb2 = q[1];
    const double first = pb2 ? pa->length + pb2->length : INFINITY;
    const double second = pa2 ? pa2->length + pb->length : INFINITY;
    if (!std::isfinite(first) && !std::isfinite(second)) return std::nullopt;
    if (first <= second)
      pb = std::move(pb2);
    else
      pa = std::move(pa2);
  }
  c.ki = pa->leave_sector, c.kj = pa->enter_sector;
  c.path = {std::move(pa->vertices), std::move(pb->vertices)};
  c.needs_split = i == j || joined(i, j);
  finish_candidate(c);
  return c;
}

std::optional<Candidate> CompatibleTracer::trace_fixed(int i, int ki, int j, int kj) {
  std::array<std::optional<TracedPath>, 2> p;
  on_both([&](int s) { p[s] = trace_on(s, i, ki, j, kj, false); });
  auto& pa = p[0];
  auto& pb = p[1];
  if (!pa || !pb) return std::nullopt;
  Candidate c;
  c.i = i, c.j = j, c.ki = ki, c.kj = kj;
  c.path = {std::move(pa->vertices), std::move(pb->vertices)};
  c.needs_split = joined(i, j);
  c.face_dart = rot_[i][ki];
  c.face = faces_[face_of_dart_[c.face_dart]];
  std::sort(c.face.begin(), c.face.end());
  finish_candidate(c);
  return c;
}

void CompatibleTracer::generate(Phase phase, bool exhaustive) {
  queue_ = {};
  const int n = int(features_.size());
  std::set<std::pair<int, int>> pairs;
  if (phase == Phase::tree) {
    for (int i = 0; i < n; ++i) {
      for (int j : nearest_[i])
        if (find(i) != find(j)) pairs.insert(std::minmax(i, j));
      // The nearest feature of another component, wherever it is.
      int best = -1;
      double best_d = INFINITY;
      for (int j = 0; j < n; ++j) {
        if (find(i) == find(j)) continue;
        double d = 0;
        for (int s = 0; s < 2; ++s)
          d +=
              (surf_[s].position(features_[i].v[s]) - surf_[s].position(features_[j].v[s])).norm() *
              surf_[s].scale();
        if (d < best_d) best_d = d, best = j;
      }
      if (best >= 0) pairs.insert(std::minmax(i, best));
      if (exhaustive)
        for (int j = 0; j < n; ++j)
          if (find(i) != find(j)) pairs.insert(std::minmax(i, j));
    }
    for (const auto& [i, j] : pairs)
      if (auto c = trace_free(i, j, false)) queue_.push(std::move(*c));
  } else if (phase == Phase::cycles) {
    for (int i = 0; i < n; ++i) {
      for (int j : nearest_[i]) pairs.insert(std::minmax(i, j));
      if (exhaustive)
        for (int j = 0; j < n; ++j) pairs.insert(std::minmax(i, j));
    }
    for (const auto& [i, j] : pairs)
      if (auto c = trace_free(i, j, true)) queue_.push(std::move(*c));
    // Cycles closing on one feature (features added on each) only when no
    // cycle between two features can be found.
    if (queue_.empty())
      for (int i = 0; i < n; ++i)
        if (auto c = trace_lasso(i)) queue_.push(std::move(*c));
  } else if (phase == Phase::discs) {
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (faces_[f].size() > 3) generate_face(int(f), exhaustive);
  }
}

// Paths between corners of one face: to the nearest features, or all; when
// every other corner's feature is already joined, paths that will carry a
// new feature (paper §4).
void CompatibleTracer::generate_face(int face, bool exhaustive) {
  const std::vector<int>& darts = faces_[face];
  const std::size_t m = darts.size();
  auto position = [&](int d) {
    const auto& rot = rot_[tail(d)];
    return int(std::find(rot.begin(), rot.end(), d) - rot.begin());
  };
  std::vector<std::pair<int, int>> near, all, blocked;
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 2; b < m; ++b) {
      if (a == 0 && b == m - 1) continue;  // consecutive corners
      const int i = tail(darts[a]), j = tail(darts[b]);
      if (i == j) continue;
      if (joined(i, j)) {
        blocked.push_back({darts[a], darts[b]});
        continue;
      }
      if (on_same_loop(i, j)) continue;
      all.push_back({darts[a], darts[b]});
      const auto& ni = nearest_[i];
      const auto& nj = nearest_[j];
      if (std::find(ni.begin(), ni.end(), j) != ni.end() ||
          std::find(nj.begin(), nj.end(), i) != nj.end())
        near.push_back({darts[a], darts[b]});
    }
  const auto& chosen = !near.empty() && !exhaustive ? near : !all.empty() ? all : blocked;
  for (const auto& [da, db] : chosen) {
    const int i = tail(da), j = tail(db), ki = position(da), kj = position(db);
    if (rejected_.count({i, ki, j, kj})) continue;
    // A pair traced before for these corners is kept while it is still free
    // and leaves and enters through the same corners (paper: lazy
    // revalidation); the face it splits may have shrunk meanwhile.
    auto cached = traced_.find({da, db});
    if (cached != traced_.end()) {
      Candidate& c = cached->second;
      bool valid = c.i == i && c.j == j && paths_free(c);
      for (int s = 0; s < 2 && valid; ++s)
        valid = sector_of(s, i, c.path[s][1]) == ki &&
                sector_of(s, j, c.path[s][c.path[s].size() - 2]) == kj;
      if (valid) {
        c.ki = ki, c.kj = kj;
        c.needs_split = joined(i, j);
        c.face = darts;
        std::sort(c.face.begin(), c.face.end());
        if (c.checked_with != features_.size()) c.side_checked = c.wrong_side = false;
        queue_.push(c);
        continue;
      }
      traced_.erase(cached);
    }
    if (auto c = trace_fixed(i, ki, j, kj)) {
      traced_[{da, db}] = *c;
      queue_.push(std::move(*c));
    }
  }
}

bool CompatibleTracer::paths_free(const Candidate& c) const {
  for (int s = 0; s < 2; ++s)
    for (std::size_t k = 1; k + 1 < c.path[s].size(); ++k)
      if (surf_[s].on_network(c.path[s][k])) return false;
  return true;
}

bool CompatibleTracer::stale(const Candidate& c) const {
  if (c.face_dart >= 0) {  // the face is as it was
    std::vector<int> face = faces_[face_of_dart_[c.face_dart]];
    std::sort(face.begin(), face.end());
    return face != c.face;
  }
  return c.version != version_;
}

bool CompatibleTracer::pop(Phase phase, Candidate& out) {
  while (!queue_.empty()) {
    Candidate c = queue_.top();
    queue_.pop();
    if (rejected_.count({c.i, c.ki, c.j, c.kj})) continue;
    if (phase == Phase::tree && find(c.i) == find(c.j)) continue;
    if (phase == Phase::discs && !stale(c) && joined(c.i, c.j) != c.needs_split) {
      // The two features were joined elsewhere meanwhile: the face's paths
      // are chosen again.
      generate_face(face_of_dart_[c.face_dart], false);
      continue;
    }
    if (stale(c) && phase == Phase::tree && paths_free(c)) {
      // Still free: valid if both still leave and enter in one corner.
      const int ki = sector_of(0, c.i, c.path[0][1]);
      const int kj = sector_of(0, c.j, c.path[0][c.path[0].size() - 2]);
      if (ki == sector_of(1, c.i, c.path[1][1]) &&
          kj == sector_of(1, c.j, c.path[1][c.path[1].size() - 2])) {
        c.ki = ki, c.kj = kj;
        c.version = version_;
        if (c.checked_with != features_.size()) c.side_checked = c.wrong_side = false;
        queue_.push(std::move(c));
        continue;
      }
    }
    if (stale(c)) {
      if (phase == Phase::discs) continue;  // its face was split: new ones are queued
      auto fresh = c.i == c.j ? trace_lasso(c.i) : trace_free(c.i, c.j, phase == Phase::cycles);
      if (fresh) queue_.push(std::move(*fresh));
      continue;
    }
    if (options_.swirl_heuristics && !c.side_checked && phase != Phase::cycles) {
      c.side_checked = true;
      c.checked_with = features_.size();
      c.wrong_side = wrong_side(c);
      if (c.wrong_side) {
        ++swirl_delays;
        queue_.push(std::move(c));
        continue;
      }
    }
    if (c.wrong_side) {
      // Only paths on the wrong side of a neighbour are left: re-route the
      // best one on the side it has on the other surface (paper §4).
      if (auto better = reroute(c)) {
        ++reroutes;
        out = std::move(*better);
        return true;
      }
    }
    out = std::move(c);
    return true;
  }
  return false;
}

// The paper's second swirl heuristic: a neighbouring feature (among the
// nearest of either end) that lies on different sides of the two paths.
std::optional<CompatibleTracer::Offence> CompatibleTracer::offence(const Candidate& c) {
  std::set<int> neighbours;
  for (int f : {c.i, c.j})
    for (std::size_t k = 0; k < nearest_[f].size() && k < 4; ++k) neighbours.insert(nearest_[f][k]);
  neighbours.erase(c.i);
  neighbours.erase(c.j);
  std::vector<int> listed;
  std::array<std::vector<int>, 2> vertices;
  for (int n : neighbours)
    if (features_[n].centre_of < 0) {
      listed.push_back(n);
      for (int s = 0; s < 2; ++s) vertices[s].push_back(features_[n].v[s]);
    }
  if (listed.empty()) return std::nullopt;
  std::array<std::vector<int>, 2> side;
  on_both([&](int s) { side[s] = surf_[s].sides_of(c.path[s], vertices[s]); });
  const std::vector<int>& a = side[0];
  const std::vector<int>& b = side[1];
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k] * b[k] < 0) return Offence{listed[k], {a[k], b[k]}};
  return std::nullopt;
}

bool CompatibleTracer::wrong_side(const Candidate& c) {
  return offence(c).has_value();
}

// Re-routes a path that passes a neighbouring feature n on different sides
// on A and B (paper §4): on one surface, shortest paths from n to both ends
// are laid as temporary walls, and the path is traced again leaving and
// entering its features on the side of those walls that puts n where the
// other surface has it. Both surfaces are tried; the shorter pair is kept.
std::optional<Candidate> CompatibleTracer::reroute(const Candidate& c) {
  if (c.lasso || c.i == c.j) return std::nullopt;
  const auto off = offence(c);
  if (!off) return std::nullopt;
  std::optional<Candidate> best;
  for (int s = 0; s < 2; ++s) {
    NetworkSurface& surf = surf_[s];
    const int want = off->side[1 - s];
    const int n = features_[off->feature].v[s];
    // Walls from n to each end, under the usual rules.
    std::vector<std::vector<int>> walls;
    for (int f : {c.i, c.j}) {
      SearchEnd from{n, {}, {}};
      for (int w : surf.ring(n))
        if (surf.may_leave_through(n, w)) from.ring.push_back(w), from.sector.push_back(0);
      auto wall = surf.shortest_path(from, end_at(s, f, -1));
      if (!wall) break;
      surf.add_path(wall->vertices);
      walls.push_back(std::move(wall->vertices));
    }
    std::optional<TracedPath> path;
    if (walls.size() == 2) {
      // The part of the end's sector on the wanted side of its wall.
      auto split_end = [&](int f, int k, const std::vector<int>& wall, bool leaving) {
        SearchEnd e = end_at(s, f, k);
        const int v = features_[f].v[s];
        const int t = wall[wall.size() - 2];  // the wall's last step into f
        const auto& rot = rot_[f];
        if (rot.empty()) return e;
        const int start = first_step(rot[k], s), stop = first_step(rot[(k + 1) % rot.size()], s);
        // n left of the path: the wall lies counter-clockwise after the
        // path where it leaves, before it where it enters.
        const bool before_wall = leaving == (want > 0);
        const std::vector<int> keep =
            before_wall ? surf.ring_between(v, start, t) : surf.ring_between(v, t, stop);
        SearchEnd out{e.vertex, {}, {}};
        for (std::size_t q = 0; q < e.ring.size(); ++q)
          if (std::find(keep.begin(), keep.end(), e.ring[q]) != keep.end())
            out.ring.push_back(e.ring[q]), out.sector.push_back(e.sector[q]);
        return out;
      };
      path = surf.shortest_path(split_end(c.i, c.ki, walls[0], true),
                                split_end(c.j, c.kj, walls[1], false));
    }
    for (const auto& wall : walls) surf.remove_path(wall);
    if (!path) continue;
    if (surf.sides_of(path->vertices, {n})[0] != want) continue;
    Candidate r = c;
    r.path[s] = std::move(path->vertices);
    r.wrong_side = false;
    finish_candidate(r);
    r.version = c.version;
    if (!best || r.length < best->length) best = std::move(r);
  }
  return best;
}

// ---------------------------------------------------------------------------

void CompatibleTracer::orient_edge_from(int e, int f) {
  Edge& edge = edges_[e];
  if (edge.i == f) return;
  const int old_i = edge.i, old_j = edge.j;
  std::swap(edge.i, edge.j);
  for (auto& p : edge.path) std::reverse(p.begin(), p.end());
  // Dart 2e leaves the first end: it moves from old_i to old_j and back.
  for (auto* list : {&rot_[old_i], &darts_at_[old_i], &rot_[old_j], &darts_at_[old_j]})
    for (int& d : *list)
      if (d / 2 == e) d ^= 1;
  compute_faces();
}

int CompatibleTracer::add_edge(int i, int j, const std::array<std::vector<int>, 2>& path) {
  const int e = int(edges_.size());
  edges_.push_back({i, j, path});
  ++adjacent_[std::minmax(i, j)];
  darts_at_[i].push_back(2 * e);
  darts_at_[j].push_back(2 * e + 1);
  return e;
}

// The vertices at `fraction` of each path's length, after index `after`,
// where a feature can go (interior vertices off the loops).
std::optional<std::array<std::size_t, 2>> CompatibleTracer::split_point(
    const std::array<std::vector<int>, 2>& path, double fraction, std::size_t after) const {
  std::array<std::size_t, 2> at{0, 0};
  for (int s = 0; s < 2; ++s) {
    const auto& p = path[s];
    const double total = surf_[s].length(p);
    double run = 0, best = INFINITY;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      run += surf_[s].length({p[k - 1], p[k]});
      if (k <= after || surf_[s].vertex_class(p[k]) != VertexClass::interior) continue;
      const double miss = std::abs(run - fraction * total);
      if (miss < best) best = miss, at[s] = k;
    }
    if (!std::isfinite(best)) return std::nullopt;
  }
  return at;
}

// Splits edge e at path vertex `at` (on each surface) into e = (i, x) and a
// new edge (x, j); x is a new feature. Returns x.
int CompatibleTracer::split_edge(int e, const std::array<std::size_t, 2>& at,
                                 FeatureOrigin origin) {
  const std::array<int, 2> v{edges_[e].path[0][at[0]], edges_[e].path[1][at[1]]};
  const int x = int(features_.size());
  features_.push_back({v, origin, -1});
  rot_.emplace_back();
  darts_at_.emplace_back();
  component_.push_back(find(edges_[e].i));
  for (int s = 0; s < 2; ++s) surf_[s].mark_feature(v[s]);
  const int j = edges_[e].j;
  std::array<std::vector<int>, 2> tail_path;
  for (int s = 0; s < 2; ++s) {
    auto& p = edges_[e].path[s];
    tail_path[s].assign(p.begin() + std::ptrdiff_t(at[s]), p.end());
    p.resize(at[s] + 1);
  }
  edges_[e].j = x;
  const int e2 = add_edge(x, j, tail_path);
  // Dart 2e+1 now leaves x; dart 2e2+1 takes its place at j.
  auto& at_j = darts_at_[j];
  at_j.erase(std::find(at_j.begin(), at_j.end(), 2 * e + 1));
  darts_at_[x].push_back(2 * e + 1);
  for (int& d : rot_[j])
    if (d == 2 * e + 1) d = 2 * e2 + 1;
  rot_[x] = {2 * e + 1, 2 * e2};
  --adjacent_[std::minmax(edges_[e].i, j)];
  ++adjacent_[std::minmax(edges_[e].i, x)];  // (x, j) is counted by add_edge
  features_changed();
  return x;
}

// Where features go on a path that needs them: half way, or at thirds of a
// closed one; nothing when the path is too short to carry them.
std::optional<std::vector<std::array<std::size_t, 2>>> CompatibleTracer::cuts_for(
    const std::array<std::vector<int>, 2>& path, bool closed) const {
  const std::vector<double> fractions =
      closed ? std::vector<double>{1.0 / 3, 2.0 / 3} : std::vector<double>{0.5};
  std::vector<std::array<std::size_t, 2>> cuts;
  std::size_t after = 0;
  for (double fraction : fractions) {
    auto at = split_point(path, fraction, after);
    // Every cut after the previous one on both surfaces.
    if (at && !cuts.empty() && ((*at)[0] <= cuts.back()[0] || (*at)[1] <= cuts.back()[1]))
      at = split_point(path, fraction, std::max(cuts.back()[0], cuts.back()[1]));
    if (!at || (!cuts.empty() && ((*at)[0] <= cuts.back()[0] || (*at)[1] <= cuts.back()[1])))
      return std::nullopt;
    after = std::min((*at)[0], (*at)[1]);
    cuts.push_back(*at);
  }
  return cuts;
}

CompatibleTracer::Snapshot CompatibleTracer::snapshot() const {
  return {features_.size(), edges_.size(), rot_, darts_at_, component_, adjacent_, regions_};
}

void CompatibleTracer::restore(const Snapshot& snap,
                               const std::vector<std::array<std::vector<int>, 2>>& added) {
  for (const auto& path : added)
    for (int s = 0; s < 2; ++s) surf_[s].remove_path(path[s]);
  for (std::size_t f = snap.features; f < features_.size(); ++f)
    for (int s = 0; s < 2; ++s) surf_[s].unmark_feature(features_[f].v[s]);
  features_.resize(snap.features);
  edges_.resize(snap.edges);
  rot_ = snap.rot;
  darts_at_ = snap.darts_at;
  component_ = snap.component;
  adjacent_ = snap.adjacent;
  regions_ = snap.regions;
  features_changed();
  compute_faces();
}

// Puts edge e on both surfaces and checks it: regions grow by `delta` on
// both, and the cyclic orders at `check` agree (a closed edge's two ends
// may be swapped on B to make them agree).
bool CompatibleTracer::place(int e, int delta, std::initializer_list<int> check) {
  std::array<int, 2> regions;
  on_both([&](int s) {
    surf_[s].add_path(edges_[e].path[s]);
    regions[s] = surf_[s].count_regions();
  });
  for (int s = 0; s < 2; ++s)
    if (regions[s] != regions_[s] + delta) return false;
  regions_ = regions;
  for (int f : check) {
    std::vector<int> ra = geometric_rotation(0, f), rb = geometric_rotation(1, f);
    if (ra != rb && edges_[e].i == edges_[e].j) {
      auto& p = edges_[e].path[1];
      std::reverse(p.begin(), p.end());
      rb = geometric_rotation(1, f);
    }
    if (ra != rb) return false;
    rot_[f] = ra;
  }
  return true;
}

bool CompatibleTracer::commit(const Candidate& c, Phase phase) {
  // Split points first, so that a path too short to carry its features is
  // refused before anything changes.
  std::vector<std::array<std::size_t, 2>> cuts;
  if (c.needs_split) {
    auto found = cuts_for(c.lasso ? c.cycle : c.path, c.lasso || c.i == c.j);
    if (!found) return false;
    cuts = std::move(*found);
  }
  const Snapshot snap = snapshot();
  std::vector<std::array<std::vector<int>, 2>> added;
  auto fail = [&] {
    restore(snap, added);
    return false;
  };
  int loop_edge = -1;  // the edge that carries the new features
  if (c.lasso) {
    // A stem to a new feature, and a non-separating cycle through it.
    const int p = int(features_.size());
    features_.push_back({{c.path[0].back(), c.path[1].back()}, FeatureOrigin::cycle, -1});
    rot_.emplace_back();
    darts_at_.emplace_back();
    component_.push_back(find(c.i));
    for (int s = 0; s < 2; ++s) surf_[s].mark_feature(features_[p].v[s]);
    const int stem = add_edge(c.i, p, c.path);
    added.push_back(c.path);
    if (!place(stem, 0, {c.i})) return fail();
    rot_[p] = geometric_rotation(0, p);
    loop_edge = add_edge(p, p, c.cycle);
    added.push_back(c.cycle);
    if (!place(loop_edge, 0, {p})) return fail();
  } else {
    const int e = add_edge(c.i, c.j, c.path);
    added.push_back(c.path);
    if (c.i == c.j ? !place(e, 0, {c.i}) : !place(e, phase == Phase::discs ? 1 : 0, {c.i, c.j}))
      return fail();
    const int ci = find(c.i), cj = find(c.j);
    if (ci != cj) component_[ci] = cj;
    loop_edge = e;
  }
  // Features on the path where the base needs them (loops, joined features).
  if (c.needs_split) {
    const FeatureOrigin origin =
        phase == Phase::discs ? FeatureOrigin::split : FeatureOrigin::cycle;
    int edge = loop_edge;
    std::array<std::size_t, 2> offset{0, 0};
    for (const auto& cut : cuts) {
      split_edge(edge, {cut[0] - offset[0], cut[1] - offset[1]}, origin);
      offset = cut;
      edge = int(edges_.size()) - 1;
    }
  }
  // Steiner vertices where paths may still go: not in the triangles this
  // insertion finished.
  compute_faces();
  std::array<std::vector<std::array<int, 2>>, 2> finished;
  for (std::size_t e = snap.edges; e < edges_.size(); ++e)
    for (int d : {int(2 * e), int(2 * e + 1)}) {
      if (faces_[face_of_dart_[d]].size() != 3) continue;
      for (int s = 0; s < 2; ++s) finished[s].push_back({tail_vertex(d, s), first_step(d, s)});
    }
  on_both([&](int s) { surf_[s].split_blocked_edges(finished[s]); });
  features_changed();
  ++version_;
  rejected_.clear();
  return true;
}

void CompatibleTracer::connect_boundary_features() {
  for (std::size_t f = 0; f < features_.size(); ++f) {
    const int loop = features_[f].centre_of;
    if (loop < 0) continue;
    // Loop features on this centre's loop, in ring order of the centre on A.
    const std::vector<int> ring = surf_[0].ring(features_[f].v[0]);
    std::vector<std::pair<std::size_t, int>> on_loop;
    for (std::size_t g = 0; g < features_.size(); ++g) {
      if (g == f) continue;
      const auto at = std::find(ring.begin(), ring.end(), features_[g].v[0]);
      if (at != ring.end()) on_loop.push_back({std::size_t(at - ring.begin()), int(g)});
    }
    std::sort(on_loop.begin(), on_loop.end());
    for (const auto& [position, g] : on_loop) {
      if (!surf_[1].adjacent(features_[f].v[1], features_[g].v[1]))
        throw PartitionError("feature pair " + std::to_string(g) + " is on boundary loop " +
                             std::to_string(loop) + " of A but not on the corresponding loop of B");
      const int e = add_edge(int(f), g,
                             {std::vector<int>{features_[f].v[0], features_[g].v[0]},
                              std::vector<int>{features_[f].v[1], features_[g].v[1]}});
      for (int s = 0; s < 2; ++s) surf_[s].add_path(edges_[e].path[s]);
      component_[find(g)] = find(int(f));
    }
    const std::vector<int> ra = geometric_rotation(0, int(f)), rb = geometric_rotation(1, int(f));
    if (ra != rb)
      throw PartitionError("the feature pairs on boundary loop " + std::to_string(loop) +
                           " are in different orders along the loop on A and on B");
    rot_[f] = ra;
    for (const auto& [position, g] : on_loop) rot_[g] = geometric_rotation(0, g);
  }
  compute_faces();
}

void CompatibleTracer::run() {
  Phase current = Phase::done;
  bool exhaustive = false;
  for (;;) {
    const Phase now = phase();
    if (now == Phase::done) break;
    if (now != current) {
      current = now;
      exhaustive = false;
      generate(now, exhaustive);
    }
    Candidate c;
    if (!pop(now, c)) {
      if (!exhaustive) {
        exhaustive = true;
        generate(now, exhaustive);
        continue;
      }
      const char* what = now == Phase::tree     ? "join the features into one tree"
                         : now == Phase::cycles ? "find a non-separating cycle on both surfaces"
                                                : "split the patches into triangles";
      throw PartitionError(std::string("cannot ") + what +
                           " with paths that agree on both surfaces (" +
                           std::to_string(features_.size()) + " features, " +
                           std::to_string(edges_.size()) + " paths so far)");
    }
    const std::size_t first_new = edges_.size();
    if (!commit(c, now)) {
      rejected_.insert({c.i, c.ki, c.j, c.kj});
      continue;
    }
    exhaustive = false;
    if (now == Phase::discs) {
      // The two faces beside the new path (and the features on it) get
      // their own candidates; other faces keep theirs.
      std::set<int> touched;
      for (std::size_t e = first_new; e < edges_.size(); ++e)
        for (int d : {int(2 * e), int(2 * e + 1)}) touched.insert(face_of_dart_[d]);
      for (int face : touched)
        if (faces_[face].size() > 3) generate_face(face, false);
    }
    // Other phases: stale candidates are traced again when they come up.
    if (options_.progress) {
      const double chi = 2.0 - 2.0 * genus_;
      const double total = 3.0 * (double(features_.size()) - chi);
      options_.progress(std::min(1.0, double(edges_.size()) / std::max(1.0, total)));
    }
  }
}

// Clip the paths to each loop's centre where they meet the loop (paper §4):
// the loop vertex next to the centre becomes a feature, and the loop between
// two such features becomes a path. The faces this leaves that are not
// triangles are split by run() afterwards.
void CompatibleTracer::clip_boundaries() {
  for (std::size_t f = 0; f < features_.size(); ++f) {
    if (features_[f].centre_of < 0) continue;
    const std::vector<int> darts = rot_[f];
    std::vector<int> clip;  // feature at the loop, per dart, counter-clockwise
    for (int d : darts) {
      const int e = d / 2;
      if (edges_[e].path[0].size() == 2) {
        clip.push_back(head(d));
        continue;
      }
      orient_edge_from(e, int(f));
      clip.push_back(split_edge(e, {1, 1}, FeatureOrigin::clip));
    }
    rot_[f] = geometric_rotation(0, int(f));
    for (int x : clip) rot_[x] = geometric_rotation(0, x);
    compute_faces();
    for (std::size_t k = 0; k < clip.size(); ++k) {
      const int a = clip[k], b = clip[(k + 1) % clip.size()];
      std::array<std::vector<int>, 2> path;
      for (int s = 0; s < 2; ++s) {
        const int centre = features_[f].v[s];
        path[s].push_back(features_[a].v[s]);
        for (int w : surf_[s].ring_between(centre, features_[a].v[s], features_[b].v[s])) {
          if (surf_[s].on_network(w))
            throw PartitionError("internal: a path touches boundary loop " +
                                 std::to_string(features_[f].centre_of) + " away from its centre");
          path[s].push_back(w);
        }
        path[s].push_back(features_[b].v[s]);
      }
      Candidate c;
      c.i = a, c.j = b;
      c.path = path;
      if (!commit(c, Phase::discs))
        throw PartitionError("boundary loop " + std::to_string(features_[f].centre_of) +
                             " cannot be cut consistently on both surfaces");
    }
  }
}

std::vector<std::array<int, 3>> CompatibleTracer::triangles() {
  compute_faces();
  std::vector<std::array<int, 3>> out;
  for (const auto& face : faces_) {
    if (face.size() != 3) throw PartitionError("internal: a face is not a triangle");
    out.push_back({tail(face[0]), tail(face[1]), tail(face[2])});
  }
  return out;
}

// ---------------------------------------------------------------------------
// Assembling the result.

// A PathNetwork from the traced graph: `index` maps traced features to
// domain vertices (-1: dropped), `keep_vertex` maps surface vertices to the
// output's (-1: dropped, with the faces using them).
PathNetwork make_network(const TriangleMesh& surface, std::size_t original_vertices,
                         const std::vector<int>& vertex_map, const TriangleMesh& domain,
                         const std::vector<Feature>& features, const std::vector<int>& index,
                         const std::vector<Edge>& edges, int s) {
  PathNetwork net;
  for (std::size_t v = 0; v < surface.n_vertices(); ++v)
    if (vertex_map[v] >= 0) net.surface.positions.push_back(surface.positions[v]);
  for (const Triangle& t : surface.triangles) {
    if (vertex_map[t[0]] < 0 || vertex_map[t[1]] < 0 || vertex_map[t[2]] < 0) continue;
    net.surface.triangles.push_back({vertex_map[t[0]], vertex_map[t[1]], vertex_map[t[2]]});
  }
  net.original_vertices = original_vertices;
  net.features.assign(domain.n_vertices(), -1);
  for (std::size_t f = 0; f < features.size(); ++f)
    if (index[f] >= 0) net.features[index[f]] = vertex_map[features[f].v[s]];
  std::unordered_set<std::uint64_t> cuts;
  for (const Edge& e : edges) {
    int a = index[e.i], b = index[e.j];
    if (a < 0 || b < 0) continue;
    std::vector<int> path;
    for (int v : e.path[s]) path.push_back(vertex_map[v]);
    if (a > b) {
      std::swap(a, b);
      std::reverse(path.begin(), path.end());
    }
    for (std::size_t k = 1; k < path.size(); ++k)
      cuts.insert(undirected_edge_key(path[k - 1], path[k]));
    net.domain_edges.push_back({a, b});
    net.paths.push_back(std::move(path));
  }
  // Sort paths by domain edge so that both surfaces list them alike.
  std::vector<std::size_t> order(net.paths.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return net.domain_edges[x] < net.domain_edges[y];
  });
  std::vector<std::array<int, 2>> domain_edges;
  std::vector<std::vector<int>> paths;
  for (std::size_t k : order) {
    domain_edges.push_back(net.domain_edges[k]);
    paths.push_back(std::move(net.paths[k]));
  }
  net.domain_edges = std::move(domain_edges);
  net.paths = std::move(paths);
  // Patches: the face left of a path edge is the domain face left of its edge.
  std::map<std::pair<int, int>, int> left_face;
  for (std::size_t f = 0; f < domain.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      left_face[{domain.triangles[f][k], domain.triangles[f][(k + 1) % 3]}] = int(f);
  int count = 0;
  const std::vector<int> region = regions(net.surface, cuts, &count);
  const DirectedEdgeFaces faces(net.surface);
  std::vector<int> label(count, -1);
  for (std::size_t e = 0; e < net.paths.size(); ++e) {
    const auto [a, b] = net.domain_edges[e];
    const auto& p = net.paths[e];
    for (const auto& [from, to, x, y] :
         {std::tuple{p[0], p[1], a, b}, std::tuple{p[1], p[0], b, a}}) {
      const int face = faces(from, to);
      const auto domain_face = left_face.find({x, y});
      if (face >= 0 && domain_face != left_face.end())
        label[region[std::size_t(face)]] = domain_face->second;
    }
  }
  net.face_patch.resize(net.surface.n_faces());
  for (std::size_t f = 0; f < net.surface.n_faces(); ++f) {
    if (label[region[f]] < 0) throw PartitionError("internal: a patch without a base face");
    net.face_patch[f] = label[region[f]];
  }
  return net;
}

}  // namespace

CompatibleNetworks trace_compatible_networks(const TriangleMesh& a, const TriangleMesh& b,
                                             const std::vector<std::array<int, 2>>& pairs,
                                             const CompatibleOptions& options) {
  const std::array<const TriangleMesh*, 2> surfaces{&a, &b};
  const std::array<std::string, 2>& name = options.names;
  for (int s = 0; s < 2; ++s) {
    if (surfaces[s]->n_faces() == 0) throw PartitionError(name[s] + " has no faces");
    std::vector<char> used(surfaces[s]->n_vertices(), 0);
    for (const Triangle& t : surfaces[s]->triangles)
      for (int v : t) {
        if (v < 0 || std::size_t(v) >= used.size())
          throw PartitionError(name[s] + ": a face has a vertex index out of range");
        used[v] = 1;
      }
    if (const auto it = std::find(used.begin(), used.end(), 0); it != used.end())
      throw PartitionError(name[s] + ": vertex " + std::to_string(it - used.begin()) +
                           " belongs to no face");
  }
  auto loops_text = [](std::size_t n) {
    return std::to_string(n) + (n == 1 ? " boundary loop" : " boundary loops");
  };

  // Topology.
  std::array<std::vector<std::vector<int>>, 2> loops{boundary_loops(a), boundary_loops(b)};
  const std::array<int, 2> genus{genus_of(a, loops[0].size()), genus_of(b, loops[1].size())};
  if (genus[0] != genus[1])
    throw PartitionError(name[0] + " has genus " + std::to_string(genus[0]) + ", " + name[1] +
                         " genus " + std::to_string(genus[1]) +
                         ": no continuous map joins surfaces of different genus");
  if (loops[0].size() != loops[1].size())
    throw PartitionError(name[0] + " has " + loops_text(loops[0].size()) + ", " + name[1] + " " +
                         loops_text(loops[1].size()) +
                         ": no continuous map joins surfaces with different boundaries");

  // Pairs: in range, no vertex twice, boundary to boundary.
  std::array<std::vector<int>, 2> loop_of;  // per vertex, -1 off the boundary
  for (int s = 0; s < 2; ++s) {
    loop_of[s].assign(surfaces[s]->n_vertices(), -1);
    for (std::size_t l = 0; l < loops[s].size(); ++l)
      for (int v : loops[s][l]) loop_of[s][v] = int(l);
  }
  std::array<std::map<int, std::size_t>, 2> seen;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (int s = 0; s < 2; ++s) {
      const int v = pairs[k][s];
      if (v < 0 || std::size_t(v) >= surfaces[s]->n_vertices())
        throw PartitionError("pair " + std::to_string(k) + ": vertex " + std::to_string(v) +
                             " of " + name[s] + " out of range (" + name[s] + " has " +
                             std::to_string(surfaces[s]->n_vertices()) + " vertices)");
      if (const auto [it, fresh] = seen[s].emplace(v, k); !fresh)
        throw PartitionError("pairs " + std::to_string(it->second) + " and " + std::to_string(k) +
                             " use the same vertex " + std::to_string(v) + " of " + name[s]);
    }
  // Loops correspond through the pairs on them.
  std::vector<int> loop_match(loops[0].size(), -1), matched_by(loops[1].size(), -1);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const int la = loop_of[0][pairs[k][0]], lb = loop_of[1][pairs[k][1]];
    if ((la < 0) != (lb < 0))
      throw PartitionError(
          "pair " + std::to_string(k) + ": vertex " + std::to_string(pairs[k][la < 0 ? 1 : 0]) +
          " of " + name[la < 0 ? 1 : 0] + " is on a boundary, vertex " +
          std::to_string(pairs[k][la < 0 ? 0 : 1]) + " of " + name[la < 0 ? 0 : 1] + " is not");
    if (la < 0) continue;
    if ((loop_match[la] >= 0 && loop_match[la] != lb) ||
        (matched_by[lb] >= 0 && matched_by[lb] != la))
      throw PartitionError("pair " + std::to_string(k) +
                           " matches boundary loops that other pairs match differently");
    loop_match[la] = lb;
    matched_by[lb] = la;
  }
  {
    // Loops no pair names: one left on each side, or lengths (relative to the
    // square root of the area) that tell them apart.
    std::array<std::vector<std::pair<double, int>>, 2> open;
    for (int s = 0; s < 2; ++s) {
      const double scale = 1 / std::sqrt(std::max(1e-300, surface_area(*surfaces[s])));
      for (std::size_t l = 0; l < loops[s].size(); ++l) {
        if ((s == 0 ? loop_match[l] : matched_by[l]) >= 0) continue;
        double length = 0;
        const auto& loop = loops[s][l];
        for (std::size_t k = 0; k < loop.size(); ++k)
          length += (surfaces[s]->positions[loop[k]] -
                     surfaces[s]->positions[loop[(k + 1) % loop.size()]])
                        .norm();
        open[s].push_back({length * scale, int(l)});
      }
      std::sort(open[s].begin(), open[s].end());
    }
    for (int s = 0; s < 2 && open[0].size() > 1; ++s)
      for (std::size_t k = 1; k < open[s].size(); ++k)
        if (open[s][k].first < 1.2 * open[s][k - 1].first)
          throw PartitionError(
              "cannot tell which boundary loops correspond (" + std::to_string(open[0].size()) +
              " loops of similar length): give a pair of boundary vertices for each loop");
    for (std::size_t k = 0; k < open[0].size(); ++k) {
      loop_match[open[0][k].second] = open[1][k].second;
      matched_by[open[1][k].second] = open[0][k].second;
    }
  }
  std::vector<std::vector<int>> loops_b(loops[0].size());
  for (std::size_t l = 0; l < loops[0].size(); ++l) loops_b[l] = loops[1][loop_match[l]];
  loops[1] = std::move(loops_b);
  for (std::size_t l = 0; l < loops[1].size(); ++l)
    for (int v : loops[1][l]) loop_of[1][v] = int(l);

  CompatibleTracer tracer(surfaces, loops, genus[0], options);
  for (const auto& p : pairs) tracer.add_feature(p, FeatureOrigin::given);

  // Automatic pairs: four features (with the loops' centres) on genus 0, one
  // on any other genus.
  const std::size_t have = tracer.features().size();
  const std::size_t need = genus[0] == 0 ? 4 : 1;
  if (have < need) {
    std::array<std::vector<Anchor>, 2> anchors;
    std::array<std::vector<char>, 2> allowed;
    for (int s = 0; s < 2; ++s) {
      allowed[s].assign(surfaces[s]->n_vertices(), 1);
      for (int v = 0; v < int(surfaces[s]->n_vertices()); ++v)
        if (loop_of[s][v] >= 0) allowed[s][v] = 0;
      for (const Feature& f : tracer.features()) {
        if (f.centre_of >= 0)
          anchors[s].push_back(loops[s][f.centre_of]);
        else
          anchors[s].push_back({f.v[s]}), allowed[s][f.v[s]] = 0;
      }
    }
    for (const auto& p : automatic_pairs(surfaces, anchors, allowed, need - have))
      tracer.add_feature(p, FeatureOrigin::automatic);
  }

  tracer.connect_boundary_features();
  tracer.prepare();
  tracer.run();
  if (!loops[0].empty()) {
    tracer.clip_boundaries();
    tracer.run();
  }

  // Domain vertex order: the features in the order they came (the given
  // ones first), the loops' centres after them in the capped base.
  const auto& features = tracer.features();
  const std::size_t nloops = loops[0].size();
  std::vector<int> capped_index(features.size()), open_index(features.size(), -1);
  int next_open = 0;
  for (std::size_t f = 0; f < features.size(); ++f)
    if (features[f].centre_of < 0) open_index[f] = next_open++;
  for (std::size_t f = 0; f < features.size(); ++f)
    capped_index[f] = features[f].centre_of < 0 ? open_index[f] : next_open + features[f].centre_of;

  CompatibleNetworks out;
  out.genus = genus[0];
  out.boundary_loops = nloops;
  out.candidates_traced = tracer.candidates_traced;
  out.sector_conflicts = tracer.sector_conflicts;
  out.swirl_delays = tracer.swirl_delays;
  out.reroutes = tracer.reroutes;
  TriangleMesh capped_base;
  capped_base.positions.resize(features.size());
  for (std::size_t f = 0; f < features.size(); ++f)
    capped_base.positions[capped_index[f]] = tracer.surface(0).position(features[f].v[0]);
  std::vector<Triangle> cap_faces;
  for (const auto& t : tracer.triangles()) {
    const Triangle mapped{capped_index[t[0]], capped_index[t[1]], capped_index[t[2]]};
    const bool cap = features[t[0]].centre_of >= 0 || features[t[1]].centre_of >= 0 ||
                     features[t[2]].centre_of >= 0;
    (cap ? cap_faces : capped_base.triangles).push_back(mapped);
  }
  out.base.positions.assign(capped_base.positions.begin(),
                            capped_base.positions.begin() + next_open);
  out.base.triangles = capped_base.triangles;
  capped_base.triangles.insert(capped_base.triangles.end(), cap_faces.begin(), cap_faces.end());
  for (std::size_t f = 0; f < features.size(); ++f)
    if (features[f].centre_of < 0) {
      FeaturePair p;
      p.origin = features[f].origin;
      for (int s = 0; s < 2; ++s) p.vertex[s] = features[f].v[s];
      out.features.push_back(p);
    }

  for (int s = 0; s < 2; ++s) {
    const TriangleMesh mesh = tracer.surface(s).triangle_mesh();
    const std::size_t input = surfaces[s]->n_vertices();
    std::vector<int> identity(mesh.n_vertices());
    std::iota(identity.begin(), identity.end(), 0);
    if (nloops == 0) {
      out.networks[s] =
          make_network(mesh, input, identity, out.base, features, capped_index, tracer.edges(), s);
      continue;
    }
    out.capped.networks[s] = make_network(mesh, input + nloops, identity, capped_base, features,
                                          capped_index, tracer.edges(), s);
    std::vector<int> open_vertex(mesh.n_vertices());
    for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
      open_vertex[v] = v < input ? int(v) : v < input + nloops ? -1 : int(v - nloops);
    out.networks[s] =
        make_network(mesh, input, open_vertex, out.base, features, open_index, tracer.edges(), s);
    for (FeaturePair& p : out.features) p.vertex[s] = open_vertex[p.vertex[s]];
  }
  if (nloops) {
    out.capped.base = std::move(capped_base);
    out.capped.loops = nloops;
  }
  if (auto problem = validate_compatible(out))
    throw PartitionError("the traced networks are inconsistent: " + *problem);
  return out;
}

std::optional<std::string> validate_compatible(const CompatibleNetworks& n) {
  const TriangleMesh& base = n.base;
  // The base: every directed edge once, every undirected edge in one or two
  // faces, no face twice, no vertex twice in a face.
  std::set<std::pair<int, int>> directed;
  std::set<std::array<int, 3>> faces;
  for (const Triangle& t : base.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return "a base face repeats a vertex";
    for (int k = 0; k < 3; ++k)
      if (!directed.insert({t[k], t[(k + 1) % 3]}).second) return "a base edge is used twice";
    std::array<int, 3> sorted{t[0], t[1], t[2]};
    std::sort(sorted.begin(), sorted.end());
    if (!faces.insert(sorted).second) return "two base faces share their three vertices";
  }
  if (n.features.size() != base.n_vertices()) return "feature count differs from the base's";
  for (int s = 0; s < 2; ++s) {
    const PathNetwork& net = n.networks[s];
    if (auto problem = validate_network(net, base))
      return std::string(s ? "B" : "A") + ": " + *problem;  // surfaces as in the call
    for (std::size_t i = 0; i < n.features.size(); ++i)
      if (net.features[i] != n.features[i].vertex[s])
        return "feature " + std::to_string(i) + " is not the network's";
    if (n.capped.loops) {
      if (auto problem = validate_network(n.capped.networks[s], n.capped.base))
        return std::string(s ? "B" : "A") + " (capped): " + *problem;
    }
  }
  if (n.networks[0].domain_edges != n.networks[1].domain_edges)
    return "the two networks have different paths";
  return std::nullopt;
}

void write_compatible_dumps(const CompatibleNetworks& networks, const std::filesystem::path& a,
                            const std::filesystem::path& b) {
  write_patch_dump(networks.networks[0], a);
  write_patch_dump(networks.networks[1], b);
}

}  // namespace ism
