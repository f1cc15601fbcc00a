// Constrained progressive mesh (paper §3 step 2, after Sander et al. 2001):
// greedy half-edge collapses vs -> vt ordered by the Garland-Heckbert quadric
// error at vt's position, with lazy invalidation of queue entries.
//
// Implementation choice: an indexed face set with per-vertex face lists, not
// OpenMesh's TriMesh. A half-edge collapse only rewrites vs to vt in the faces
// around vs and drops the two faces on the edge, so faces keep their indices
// and hence their patch labels (a plain array beside them), vertices keep the
// input's indices (no garbage collection to map back), and every test we need
// (link condition, network rules, normal flips) is a scan of one or two vertex
// fans. The same structure replays the splits (replay.cpp). OpenMesh would
// bring status flags, property handles and a half-edge surgery we would have
// to mirror for the labels, for no gain in speed or memory at these sizes.
//
// Why the checks below keep the path network (all collapses on a closed,
// connected 2-manifold; Lk = link, N = neighbour set):
//  1. Link condition N(vs) ∩ N(vt) = {vl, vr}, and neither vl nor vr of
//     valence 3 (on a closed manifold with the first condition, valence 3
//     happens only when the component is a tetrahedron). Then the collapse is a
//     homeomorphism of the surface: no duplicate edge or face can appear, the
//     only edges that merge are (vs,x) with (vt,x) for x in {vl, vr}.
//  2. Every face keeps its patch label, so each patch loses exactly the faces
//     (vs,vt,vl), (vt,vs,vr) that lie in it and keeps its other faces.
//  3. An interior vertex vs (not on a path) has all its faces in one patch P.
//     Lk_P(vs) = Lk(vs), so Lk_P(vs) ∩ Lk_P(vt) ⊆ {vl, vr} = Lk_P(vs vt): the
//     link condition holds inside P, and contracting an edge of a 2-complex
//     under its link condition keeps its topology: P stays a disc. The other
//     patches keep their faces and vertices; only their vertex vt gains
//     edges inside P. Paths keep their vertices and edges (a merged edge
//     (vt,x) keeps the path status (vt,x) had, (vs,x) had none).
//  4. A path vertex vs (on path p between path neighbours a and b) collapses
//     only into b (or a), along p. The two faces on the edge are one in each
//     patch beside p, P and Q. Inside P, Lk_P(vs) is an arc from a to b and
//     Lk_P(vs) ∩ Lk_P(b) = {vl}: vr is on Q's side and could be in P's arc
//     only as a, and a in Lk_P(b) would need an edge (a,b) with a face in P
//     while its face (b,vs,a) is in Q, i.e. a path edge (a,b); that is the
//     case rejected in 5. So P (and Q likewise) stays a disc, and p stays a
//     simple path a..b with one vertex fewer; paths still meet only at
//     features because vertex sets only shrink and only vs leaves.
//  5. Rejected: the merge of two path edges (vs,x) and (vt,x). That is the
//     one way a collapse could join two paths (or glue a path onto itself)
//     or remove the last face of a patch: a patch whose only face is
//     (vs,vt,x) has all three sides on paths.
//  6. Features are never vs, so all of them survive.
// When only features remain, every patch is a disc with three boundary
// vertices and no interior vertex, i.e. one triangle, so the base mesh has
// the domain's faces; we still verify that at the end.
//
// Normal flips are a soft constraint: each vertex's queue entry is its
// cheapest target among collapses that are legal and flip-free; if none is
// flip-free, its cheapest legal one waits in a second queue. Only when the
// first queue is empty do we take one collapse from the second (counted in
// relaxed_collapses), then return to flip-free collapses around it.
#include "mesh/edge_key.hpp"
#include "pm/pm.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ism {
namespace {

std::string edge_name(int a, int b) {
  std::string name = "(";  // appended piecewise: GCC 12 warns (-Wrestrict) on "(" + ...
  name += std::to_string(a);
  name += ", ";
  name += std::to_string(b);
  name += ")";
  return name;
}

int corner_of(const Triangle& t, int v) {
  return t[0] == v ? 0 : t[1] == v ? 1 : 2;
}

bool contains(const Triangle& t, int v) {
  return t[0] == v || t[1] == v || t[2] == v;
}

/// Symmetric 4x4 plane quadric (Garland-Heckbert), upper triangle row-major.
struct Quadric {
  std::array<double, 10> q{};

  static Quadric plane(const Vec3& n, double d, double weight) {
    Quadric Q;
    const double v[4] = {n.x(), n.y(), n.z(), d};
    int k = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) Q.q[k++] = weight * v[i] * v[j];
    return Q;
  }
  Quadric& operator+=(const Quadric& o) {
    for (int i = 0; i < 10; ++i) q[i] += o.q[i];
    return *this;
  }
  /// (this + o)(p): the squared-distance error of moving both onto p.
  double error_sum(const Quadric& o, const Vec3& p) const {
    double s[10];
    for (int i = 0; i < 10; ++i) s[i] = q[i] + o.q[i];
    const double x = p.x(), y = p.y(), z = p.z();
    return s[0] * x * x + 2 * s[1] * x * y + 2 * s[2] * x * z + 2 * s[3] * x + s[4] * y * y +
           2 * s[5] * y * z + 2 * s[6] * y + s[7] * z * z + 2 * s[8] * z + s[9];
  }
};

struct Candidate {
  double cost;
  int vs, vt;
  std::uint32_t version;  // of vs when the entry was made
};

/// Orders a std::priority_queue so that the cheapest collapse is on top;
/// equal costs go by (vs, vt) so that runs are reproducible.
struct CostlierFirst {
  bool operator()(const Candidate& a, const Candidate& b) const {
    if (a.cost != b.cost) return a.cost > b.cost;
    if (a.vs != b.vs) return a.vs > b.vs;
    return a.vt > b.vt;
  }
};

using CandidateQueue = std::priority_queue<Candidate, std::vector<Candidate>, CostlierFirst>;

enum class Kind : std::uint8_t { interior, path, feature };

class Simplifier {
 public:
  explicit Simplifier(const TriangleMesh& mesh)
      : positions_(mesh.positions),
        faces_(mesh.triangles),
        vertex_faces_(mesh.n_vertices()),
        face_alive_(mesh.n_faces(), 1),
        kind_(mesh.n_vertices(), Kind::interior),
        path_prev_(mesh.n_vertices(), -1),
        path_next_(mesh.n_vertices(), -1),
        alive_(mesh.n_vertices(), 1),
        version_(mesh.n_vertices(), 0),
        mark_(mesh.n_vertices(), 0),
        alive_count_(mesh.n_vertices()) {
    const int nv = static_cast<int>(positions_.size());
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      const Triangle& t = faces_[f];
      for (int v : t)
        if (v < 0 || v >= nv)
          throw std::runtime_error("pm: face " + std::to_string(f) + " has vertex index " +
                                   std::to_string(v) + " out of range");
      if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
        throw std::runtime_error("pm: face " + std::to_string(f) + " repeats a vertex");
      for (int v : t) vertex_faces_[v].push_back(static_cast<int>(f));
    }
    check_closed_manifold();
    compute_quadrics();
  }

  /// Installs the network's constraints; throws when the network does not
  /// describe paths of `domain`'s edges cutting the surface into its faces.
  void constrain(const PathNetwork& network, const TriangleMesh& domain);

  /// Keeps `centres` and makes each loop a closed path: a loop vertex
  /// collapses only into a loop neighbour, and a loop keeps three vertices.
  void hold_loops(const std::vector<std::vector<int>>& loops, const std::vector<int>& centres,
                  std::size_t max_span);

  /// Collapses until `target` vertices remain or nothing legal is left.
  void run(std::size_t target, const SimplifyOptions& options);

  std::size_t alive_count() const { return alive_count_; }
  bool alive(int v) const { return alive_[v] != 0; }

  /// Faces still present, in index order.
  std::vector<int> alive_faces() const {
    std::vector<int> out;
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (face_alive_[f]) out.push_back(static_cast<int>(f));
    return out;
  }
  const Triangle& face(int f) const { return faces_[f]; }

  /// Collapses in the order done; a ProgressiveMesh wants them reversed.
  const std::vector<VertexSplit>& collapses() const { return collapses_; }
  std::size_t relaxed_collapses() const { return relaxed_collapses_; }

  /// A vertex that is left over although it is no feature, for messages.
  std::string describe_leftover() const;

 private:
  // ---- adjacency -------------------------------------------------------
  /// The face around v whose corner after v is x: (v, x, *) counter-clockwise.
  int face_after(int v, int x) const {
    for (int f : vertex_faces_[v]) {
      const Triangle& t = faces_[f];
      if (t[(corner_of(t, v) + 1) % 3] == x) return f;
    }
    return -1;
  }
  bool adjacent(int u, int v) const { return face_after(u, v) >= 0 || face_after(v, u) >= 0; }

  std::uint32_t next_stamp() {
    if (++stamp_ == 0) {  // wrapped around: clear the marks once
      std::fill(mark_.begin(), mark_.end(), 0);
      stamp_ = 1;
    }
    return stamp_;
  }

  void collect_neighbours(int v, std::vector<int>& out) {
    next_stamp();
    out.clear();
    for (int f : vertex_faces_[v])
      for (int w : faces_[f])
        if (w != v && mark_[w] != stamp_) {
          mark_[w] = stamp_;
          out.push_back(w);
        }
  }

  void check_closed_manifold() const;
  void compute_quadrics();

  // ---- rules -----------------------------------------------------------
  bool is_path_edge(int x, int y) const {
    if (kind_[x] == Kind::path) return path_prev_[x] == y || path_next_[x] == y;
    if (kind_[y] == Kind::path) return path_prev_[y] == x || path_next_[y] == x;
    if (kind_[x] == Kind::feature && kind_[y] == Kind::feature)
      return direct_paths_.count({std::min(x, y), std::max(x, y)}) != 0;
    return false;
  }

  /// Third corners of the faces (vs, vt, vl) and (vt, vs, vr); false if vs
  /// and vt are not adjacent.
  bool wings(int vs, int vt, int& vl, int& vr) const {
    vl = vr = -1;
    for (int f : vertex_faces_[vs]) {
      const Triangle& t = faces_[f];
      const int k = corner_of(t, vs);
      if (t[(k + 1) % 3] == vt) vl = t[(k + 2) % 3];
      if (t[(k + 2) % 3] == vt) vr = t[(k + 1) % 3];
    }
    return vl >= 0 && vr >= 0;
  }

  bool link_condition(int vs, int vt, int vl, int vr) {
    if (vertex_faces_[vl].size() <= 3 || vertex_faces_[vr].size() <= 3) return false;
    next_stamp();
    for (int f : vertex_faces_[vs])
      for (int w : faces_[f]) mark_[w] = stamp_;
    for (int f : vertex_faces_[vt])
      for (int w : faces_[f])
        if (w != vs && w != vt && w != vl && w != vr && mark_[w] == stamp_) return false;
    return true;
  }

  bool network_allows(int vs, int vt, int vl, int vr) const {
    if (kind_[vs] == Kind::feature) return false;
    if (kind_[vs] == Kind::path && vt != path_prev_[vs] && vt != path_next_[vs]) return false;
    if (!bridges_.empty() && kind_[vs] == Kind::path && loop_position_[vs] >= 0) {
      // The loop edge left behind, from vs's other loop neighbour to vt
      // (loop positions first .. first + span), spans at most max_span_
      // edges of the input loop, nor both ends of an input edge across the
      // loop (an ear's third edge, say): the faces between would lie on one
      // straight base edge, with no area (bounded_base refuses such a base).
      const bool forward = vt == path_next_[vs];
      const int other = forward ? path_prev_[vs] : path_next_[vs];
      const int n = loop_size_[vs];
      const int first = loop_position_[forward ? other : vt];
      const int span = (loop_position_[forward ? vt : other] - first + n) % n;
      if (max_span_ && std::size_t(span) > max_span_) return false;
      for (const auto& [i, j] : bridges_[std::size_t(loop_index_[vs])])
        if ((i - first + n) % n <= span && (j - first + n) % n <= span) return false;
    }
    for (int x : {vl, vr})
      if (is_path_edge(vs, x) && is_path_edge(vt, x)) return false;
    return true;
  }

  bool topology_allows(int vs, int vt) {
    int vl, vr;
    return wings(vs, vt, vl, vr) && network_allows(vs, vt, vl, vr) &&
           link_condition(vs, vt, vl, vr);
  }

  /// Calls fn(a, b) for the faces (vs, a, b) that survive the collapse
  /// vs -> vt (those without vt), in their counter-clockwise order, caps'
  /// faces (is_cap_face) left out with `skip_caps`; stops early when fn
  /// returns false.
  template <class Fn>
  bool for_each_surviving_face(int vs, int vt, const Fn& fn, bool skip_caps = false) const {
    for (int f : vertex_faces_[vs]) {
      const Triangle& t = faces_[f];
      if (contains(t, vt) || (skip_caps && is_cap_face(t))) continue;
      const int k = corner_of(t, vs);
      if (!fn(positions_[t[(k + 1) % 3]], positions_[t[(k + 2) % 3]])) return false;
    }
    return true;
  }

  /// No face that survives turns by more than 90 degrees or degenerates.
  bool keeps_normals(int vs, int vt) const {
    const Vec3& ps = positions_[vs];
    const Vec3& pt = positions_[vt];
    return for_each_surviving_face(vs, vt, [&](const Vec3& a, const Vec3& b) {
      const Vec3 before = (a - ps).cross(b - ps);
      const Vec3 after = (a - pt).cross(b - pt);
      if (before.dot(after) < 0.0) return false;
      // Degenerate: sine of the angle at pt (or worse) below ~1e-10.
      const double longest =
          std::max({(a - pt).squaredNorm(), (b - pt).squaredNorm(), (a - b).squaredNorm()});
      return after.squaredNorm() > 1e-20 * longest * longest;
    });
  }

  /// Smallest shape quality 4√3·area/Σ|edge|² (1 equilateral, 0 degenerate)
  /// of the faces that survive the collapse vs -> vt, caps' faces (those on
  /// a centre of hold_loops()) aside: a cap's fan is thin by construction.
  double quality_after(int vs, int vt) const {
    const Vec3& pt = positions_[vt];
    double worst = 1.0;
    for_each_surviving_face(
        vs, vt,
        [&](const Vec3& a, const Vec3& b) {
          const double twice_area = (a - pt).cross(b - pt).norm();
          const double lengths =
              (a - pt).squaredNorm() + (b - pt).squaredNorm() + (a - b).squaredNorm();
          worst = std::min(worst, lengths > 0 ? 2.0 * std::sqrt(3.0) * twice_area / lengths : 0.0);
          return true;
        },
        /*skip_caps=*/true);
    return worst;
  }
  bool is_cap_face(const Triangle& t) const {
    return !centre_.empty() && (centre_[t[0]] || centre_[t[1]] || centre_[t[2]]);
  }

  double collapse_cost(int vs, int vt) const {
    if (priority_ == SimplifyPriority::quadric)
      return quadrics_[vs].error_sum(quadrics_[vt], positions_[vt]);
    // Size of the merged region (surface area the two vertices stand for),
    // inflated by the shape it would leave.
    // Squared shape quality: postpones poor triangles more than large regions.
    const double quality = quality_after(vs, vt);
    const double cost =
        (region_area_[vs] + region_area_[vt]) / std::pow(std::max(quality, 1e-3), 2);
    int vl, vr;
    if (valence_weight_ == 0 || !wings(vs, vt, vl, vr)) return cost;
    // Valences after the collapse: vt gains vs's fan less the two wings, the
    // wings lose one each.
    // 6, or the valence that makes a vertex's cone (valence·60°) match the
    // angle defect of the surface it stands for.
    auto deviation = [&](int v, double valence) {
      const double ideal =
          valence_from_curvature_ ? 6.0 - 3.0 * region_curvature_[v] / std::numbers::pi : 6.0;
      return (valence - ideal) * (valence - ideal);
    };
    const auto valence = [&](int v) { return double(vertex_faces_[v].size()); };
    return cost * (1 + valence_weight_ *
                           (deviation(vt, valence(vt) + valence(vs) - 4) +
                            deviation(vl, valence(vl) - 1) + deviation(vr, valence(vr) - 1)));
  }

  // ---- queue -----------------------------------------------------------
  void evaluate(int vs);
  bool pop_legal(CandidateQueue& queue, bool allow_flips, Candidate& out);
  void collapse(int vs, int vt);

  std::vector<Vec3> positions_;
  std::vector<Triangle> faces_;
  std::vector<std::vector<int>> vertex_faces_;
  std::vector<std::uint8_t> face_alive_;
  std::vector<Quadric> quadrics_;
  SimplifyPriority priority_ = SimplifyPriority::quadric;
  double valence_weight_ = 0.0;
  bool valence_from_curvature_ = false;
  std::vector<double> region_area_;       // input surface area each vertex stands for
  std::vector<char> centre_;              // hold_loops(): the caps' centres (empty: none)
  std::vector<double> region_curvature_;  // and its Gaussian curvature (angle defects)

  // Network: kind of each vertex; for path vertices their neighbours along
  // the path (towards the path's first and last feature); feature pairs
  // (min, max) joined by a path of one edge.
  std::vector<Kind> kind_;
  std::vector<int> path_prev_, path_next_;
  // hold_loops(): each loop vertex's position in its input loop, the loop's
  // size, and the longest loop edge a collapse may leave (0: any).
  std::vector<int> loop_position_, loop_size_;
  std::size_t max_span_ = 0;
  // hold_loops(): each loop vertex's loop, and per loop the positions of
  // the ends of its bridges (input edges joining two of its vertices that
  // are not loop neighbours).
  std::vector<int> loop_index_;
  std::vector<std::vector<std::pair<int, int>>> bridges_;
  std::set<std::pair<int, int>> direct_paths_;

  std::vector<std::uint8_t> alive_;
  std::vector<std::uint32_t> version_;
  std::vector<std::uint32_t> mark_;
  std::uint32_t stamp_ = 0;
  std::size_t alive_count_;

  CandidateQueue flip_free_, flipping_;
  std::vector<VertexSplit> collapses_;
  std::size_t relaxed_collapses_ = 0;

  // Scratch buffers of evaluate().
  std::vector<int> targets_;
  std::vector<std::pair<double, int>> scored_;
};

void Simplifier::check_closed_manifold() const {
  // Every directed edge once, with its opposite: closed and edge-manifold.
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * faces_.size());
  for (const Triangle& t : faces_)
    for (int k = 0; k < 3; ++k) directed.push_back(directed_edge_key(t[k], t[(k + 1) % 3]));
  std::sort(directed.begin(), directed.end());
  for (std::size_t i = 0; i < directed.size(); ++i) {
    const int a = static_cast<int>(directed[i] >> 32);
    const int b = static_cast<int>(directed[i] & 0xffffffffu);
    if (i + 1 < directed.size() && directed[i + 1] == directed[i])
      throw std::runtime_error("pm: edge " + edge_name(a, b) +
                               " is non-manifold or inconsistently oriented");
    if (!std::binary_search(directed.begin(), directed.end(), directed_edge_key(b, a)))
      throw std::runtime_error("pm: edge " + edge_name(a, b) +
                               " is on a boundary; a closed surface is needed");
  }
  // Every vertex used, and its faces form one fan.
  for (std::size_t v = 0; v < vertex_faces_.size(); ++v) {
    const auto& fan = vertex_faces_[v];
    if (fan.empty())
      throw std::runtime_error("pm: vertex " + std::to_string(v) + " belongs to no face");
    const int vi = static_cast<int>(v);
    int f = fan.front();
    std::size_t steps = 0;
    do {
      const Triangle& t = faces_[f];
      f = face_after(vi, t[(corner_of(t, vi) + 2) % 3]);
      ++steps;
    } while (f != fan.front() && f >= 0 && steps <= fan.size());
    if (steps != fan.size())
      throw std::runtime_error("pm: vertex " + std::to_string(v) + " is non-manifold");
  }
}

void Simplifier::compute_quadrics() {
  quadrics_.assign(positions_.size(), Quadric{});
  for (const Triangle& t : faces_) {
    const Vec3& a = positions_[t[0]];
    const Vec3 n = (positions_[t[1]] - a).cross(positions_[t[2]] - a);
    const double twice_area = n.norm();
    if (!(twice_area > 0.0)) continue;  // a zero-area face has no plane
    const Vec3 unit = n / twice_area;
    const Quadric Q = Quadric::plane(unit, -unit.dot(a), 0.5 * twice_area);
    for (int v : t) quadrics_[v] += Q;
  }
}

void Simplifier::constrain(const PathNetwork& network, const TriangleMesh& domain) {
  auto fail = [](const std::string& why) {
    throw std::runtime_error("simplify_constrained: " + why);
  };
  const int nv = static_cast<int>(positions_.size());
  const std::size_t n_domain_faces = domain.n_faces();

  if (network.features.size() != domain.n_vertices())
    fail(std::to_string(network.features.size()) + " features for a domain of " +
         std::to_string(domain.n_vertices()) + " vertices");
  for (std::size_t i = 0; i < network.features.size(); ++i) {
    const int v = network.features[i];
    if (v < 0 || v >= nv) fail("feature " + std::to_string(i) + " is out of range");
    if (kind_[v] == Kind::feature)
      fail("surface vertex " + std::to_string(v) + " is the feature of two domain vertices");
    kind_[v] = Kind::feature;
  }

  // The paths must be exactly one per domain edge.
  std::set<std::pair<int, int>> domain_edges;
  for (const Triangle& t : domain.triangles)
    for (int k = 0; k < 3; ++k)
      domain_edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  if (network.domain_edges.size() != domain_edges.size() ||
      network.paths.size() != domain_edges.size())
    fail(std::to_string(network.paths.size()) + " paths for a domain of " +
         std::to_string(domain_edges.size()) + " edges");
  std::set<std::pair<int, int>> seen_edges;
  for (std::size_t e = 0; e < network.paths.size(); ++e) {
    const auto [a, b] = network.domain_edges[e];
    if (!domain_edges.count({a, b}) || !seen_edges.insert({a, b}).second)
      fail("domain edge " + edge_name(a, b) + " of path " + std::to_string(e) +
           " is not a (single) edge of the domain");
    const std::vector<int>& path = network.paths[e];
    if (path.size() < 2 || path.front() != network.features[a] ||
        path.back() != network.features[b])
      fail("path " + std::to_string(e) + " does not run from feature " + std::to_string(a) +
           " to feature " + std::to_string(b));
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      const int v = path[i];
      if (v < 0 || v >= nv) fail("path " + std::to_string(e) + " has a vertex out of range");
      if (kind_[v] != Kind::interior)
        fail("surface vertex " + std::to_string(v) +
             " is on two paths or is a feature inside path " + std::to_string(e));
      kind_[v] = Kind::path;
      path_prev_[v] = path[i - 1];
      path_next_[v] = path[i + 1];
    }
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      if (!adjacent(path[i], path[i + 1]))
        fail("path " + std::to_string(e) + " jumps between non-adjacent vertices " +
             edge_name(path[i], path[i + 1]));
    if (path.size() == 2)
      direct_paths_.insert({std::min(path[0], path[1]), std::max(path[0], path[1])});
  }

  // Faces on either side of an edge share a patch exactly when the edge is on
  // no path.
  const std::vector<int>& patch = network.face_patch;
  if (patch.size() != faces_.size()) fail("face_patch does not have one entry per face");
  for (int p : patch)
    if (p < 0 || static_cast<std::size_t>(p) >= n_domain_faces)
      fail("face_patch has a patch index out of range");
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const Triangle& t = faces_[f];
    for (int k = 0; k < 3; ++k) {
      const int u = t[k], v = t[(k + 1) % 3];
      const int g = face_after(v, u);
      const bool same_patch = patch[f] == patch[g];
      if (same_patch == is_path_edge(u, v))
        fail("edge " + edge_name(u, v) +
             (same_patch ? " is on a path inside one patch"
                         : " separates two patches but is on no path"));
    }
  }

  // Same Euler characteristic, otherwise the base cannot be reached.
  const long surface_chi = static_cast<long>(nv) - static_cast<long>(faces_.size()) / 2;
  const long domain_chi =
      static_cast<long>(domain.n_vertices()) - static_cast<long>(domain.n_faces()) / 2;
  if (surface_chi != domain_chi)
    fail("the surface (Euler characteristic " + std::to_string(surface_chi) + ") and the domain (" +
         std::to_string(domain_chi) + ") have different topology");
}

void Simplifier::hold_loops(const std::vector<std::vector<int>>& loops,
                            const std::vector<int>& centres, std::size_t max_span) {
  max_span_ = max_span;
  loop_position_.assign(positions_.size(), -1);
  loop_size_.assign(positions_.size(), 0);
  loop_index_.assign(positions_.size(), -1);
  const int nv = static_cast<int>(positions_.size());
  auto check = [&](int v) {
    if (v < 0 || v >= nv || kind_[v] != Kind::interior)
      throw std::runtime_error("simplify_capped_to: vertex " + std::to_string(v) +
                               " is out of range or held twice");
  };
  centre_.assign(positions_.size(), 0);
  for (int c : centres) check(c), kind_[c] = Kind::feature, centre_[c] = 1;
  for (const std::vector<int>& loop : loops) {
    if (loop.size() < 3) throw std::runtime_error("simplify_capped_to: a loop of fewer than 3");
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int v = loop[i];
      check(v);
      kind_[v] = Kind::path;
      loop_position_[v] = int(i);
      loop_size_[v] = int(loop.size());
      path_prev_[v] = loop[(i + loop.size() - 1) % loop.size()];
      path_next_[v] = loop[(i + 1) % loop.size()];
      loop_index_[v] = int(&loop - loops.data());
    }
  }
  bridges_.assign(loops.size(), {});
  for (const Triangle& t : faces_)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a > b || loop_index_[a] < 0 || loop_index_[a] != loop_index_[b]) continue;
      if (path_next_[a] == b || path_prev_[a] == b) continue;
      bridges_[std::size_t(loop_index_[a])].emplace_back(loop_position_[a], loop_position_[b]);
    }
}

void Simplifier::evaluate(int vs) {
  ++version_[vs];
  if (!alive_[vs] || kind_[vs] == Kind::feature) return;
  if (kind_[vs] == Kind::path)
    targets_.assign({path_prev_[vs], path_next_[vs]});
  else
    collect_neighbours(vs, targets_);
  scored_.clear();
  for (int vt : targets_) scored_.emplace_back(collapse_cost(vs, vt), vt);
  std::sort(scored_.begin(), scored_.end());

  bool have_flipping = false;
  Candidate flipping{};
  for (const auto& [cost, vt] : scored_) {
    if (!topology_allows(vs, vt)) continue;
    if (keeps_normals(vs, vt)) {
      flip_free_.push({cost, vs, vt, version_[vs]});
      return;
    }
    if (!have_flipping) {
      flipping = {cost, vs, vt, version_[vs]};
      have_flipping = true;
    }
  }
  if (have_flipping) flipping_.push(flipping);
}

bool Simplifier::pop_legal(CandidateQueue& queue, bool allow_flips, Candidate& out) {
  while (!queue.empty()) {
    const Candidate c = queue.top();
    queue.pop();
    if (!alive_[c.vs] || c.version != version_[c.vs]) continue;  // stale
    // A current entry is still legal (its neighbourhood was not touched);
    // re-checking is cheap insurance.
    if (!topology_allows(c.vs, c.vt) || (!allow_flips && !keeps_normals(c.vs, c.vt))) {
      evaluate(c.vs);
      continue;
    }
    out = c;
    return true;
  }
  return false;
}

void Simplifier::collapse(int vs, int vt) {
  int vl, vr;
  wings(vs, vt, vl, vr);
  collapses_.push_back({vs, vt, vl, vr, positions_[vs]});

  for (int f : vertex_faces_[vs]) {
    Triangle& t = faces_[f];
    if (contains(t, vt)) {
      face_alive_[f] = 0;
      for (int w : t)
        if (w != vs) std::erase(vertex_faces_[w], f);
    } else {
      t[corner_of(t, vs)] = vt;
      vertex_faces_[vt].push_back(f);
    }
  }
  vertex_faces_[vs].clear();
  vertex_faces_[vs].shrink_to_fit();
  quadrics_[vt] += quadrics_[vs];
  if (!region_area_.empty()) {
    region_area_[vt] += region_area_[vs];
    region_curvature_[vt] += region_curvature_[vs];
  }

  if (kind_[vs] == Kind::path) {
    // Unlink vs from its path: its other path neighbour now meets vt.
    const bool forward = vt == path_next_[vs];
    const int other = forward ? path_prev_[vs] : path_next_[vs];
    if (kind_[vt] == Kind::path) (forward ? path_prev_[vt] : path_next_[vt]) = other;
    if (kind_[other] == Kind::path) (forward ? path_next_[other] : path_prev_[other]) = vt;
    if (kind_[vt] == Kind::feature && kind_[other] == Kind::feature)
      direct_paths_.insert({std::min(vt, other), std::max(vt, other)});
  }

  alive_[vs] = 0;
  ++version_[vs];
  --alive_count_;
}

void Simplifier::run(std::size_t target, const SimplifyOptions& options) {
  priority_ = options.priority;
  valence_weight_ = options.valence_weight;
  valence_from_curvature_ = options.valence_from_curvature;
  region_area_.assign(positions_.size(), 0.0);
  region_curvature_.assign(positions_.size(), 2 * std::numbers::pi);
  for (const Triangle& t : faces_) {
    // A cap stands for no surface: its area counts for no vertex.
    const double third = is_cap_face(t) ? 0.0
                                        : (positions_[t[1]] - positions_[t[0]])
                                                  .cross(positions_[t[2]] - positions_[t[0]])
                                                  .norm() /
                                              6.0;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = positions_[t[k]];
      const Vec3 a = positions_[t[(k + 1) % 3]] - p, b = positions_[t[(k + 2) % 3]] - p;
      region_area_[t[k]] += third;
      region_curvature_[t[k]] -= std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  for (std::size_t v = 0; v < positions_.size(); ++v) evaluate(static_cast<int>(v));

  const std::size_t total = alive_count_ > target ? alive_count_ - target : 0;
  const std::size_t report_every = std::max<std::size_t>(1, total / 100);
  std::size_t done = 0;
  std::vector<int> ring;
  while (alive_count_ > target) {
    Candidate c;
    bool relaxed = false;
    if (!pop_legal(flip_free_, false, c)) {
      if (!pop_legal(flipping_, true, c)) break;  // stuck: nothing legal left
      relaxed = true;
    }
    collapse(c.vs, c.vt);
    if (relaxed) ++relaxed_collapses_;

    // Only vt and its ring can have new candidates: any other vertex keeps its
    // fan, its neighbours, their path links and its targets' quadrics.
    evaluate(c.vt);
    collect_neighbours(c.vt, ring);
    for (int w : ring) evaluate(w);

    if (options.progress && ++done % report_every == 0)
      options.progress(static_cast<double>(done) / static_cast<double>(total));
  }
  if (options.progress) options.progress(1.0);
}

std::string Simplifier::describe_leftover() const {
  for (std::size_t v = 0; v < positions_.size(); ++v) {
    if (!alive_[v] || kind_[v] == Kind::feature) continue;
    return "vertex " + std::to_string(v) +
           (kind_[v] == Kind::path ? " on a path between " + edge_name(path_prev_[v], path_next_[v])
                                   : " inside a patch");
  }
  return "none";
}

ProgressiveMesh assemble(const Simplifier& simplifier, const TriangleMesh& mesh,
                         std::vector<Triangle> base_faces, std::vector<int> base_vertices) {
  ProgressiveMesh pm;
  pm.base.positions = mesh.positions;
  pm.base.triangles = std::move(base_faces);
  pm.base_vertices = std::move(base_vertices);
  pm.splits.assign(simplifier.collapses().rbegin(), simplifier.collapses().rend());
  pm.relaxed_collapses = simplifier.relaxed_collapses();
  return pm;
}

// The progressive mesh down to whatever the simplifier left: the remaining
// faces, the remaining vertices in increasing index order.
ProgressiveMesh assemble_remaining(const Simplifier& simplifier, const TriangleMesh& mesh) {
  std::vector<Triangle> base_faces;
  for (int f : simplifier.alive_faces()) base_faces.push_back(simplifier.face(f));
  std::vector<int> base_vertices;
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    if (simplifier.alive(static_cast<int>(v))) base_vertices.push_back(static_cast<int>(v));
  return assemble(simplifier, mesh, std::move(base_faces), std::move(base_vertices));
}

}  // namespace

ProgressiveMesh simplify_constrained(const PathNetwork& network, const TriangleMesh& domain,
                                     const SimplifyOptions& options) {
  const TriangleMesh& surface = network.surface;
  Simplifier simplifier(surface);
  simplifier.constrain(network, domain);
  simplifier.run(network.features.size(), options);

  if (simplifier.alive_count() != network.features.size())
    throw std::runtime_error(
        "simplify_constrained: stuck with " +
        std::to_string(simplifier.alive_count() - network.features.size()) +
        " vertices besides the features that no legal collapse removes (e.g. " +
        simplifier.describe_leftover() + ")");

  // Base face of patch p must be domain face p, with the same orientation.
  const std::vector<int> faces = simplifier.alive_faces();
  if (faces.size() != domain.n_faces())
    throw std::runtime_error("simplify_constrained: base has " + std::to_string(faces.size()) +
                             " faces, the domain " + std::to_string(domain.n_faces()));
  std::vector<Triangle> base_faces(domain.n_faces(), Triangle{-1, -1, -1});
  for (int f : faces) {
    const int p = network.face_patch[f];
    const Triangle& d = domain.triangles[p];
    const Triangle want = {network.features[d[0]], network.features[d[1]], network.features[d[2]]};
    const Triangle& t = simplifier.face(f);
    const int k = corner_of(t, want[0]);
    const Triangle rotated = {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
    if (rotated != want || base_faces[p][0] >= 0)
      throw std::runtime_error("simplify_constrained: base face (" + std::to_string(t[0]) + ", " +
                               std::to_string(t[1]) + ", " + std::to_string(t[2]) + ") of patch " +
                               std::to_string(p) + " does not match domain face " +
                               std::to_string(p));
    base_faces[p] = want;
  }
  return assemble(simplifier, surface, std::move(base_faces), network.features);
}

ProgressiveMesh simplify_capped_to(const TriangleMesh& mesh,
                                   const std::vector<std::vector<int>>& loops,
                                   const std::vector<int>& centres, std::size_t target_vertices,
                                   const SimplifyOptions& options, std::size_t max_loop_span) {
  Simplifier simplifier(mesh);
  simplifier.hold_loops(loops, centres, max_loop_span);
  simplifier.run(target_vertices, options);

  return assemble_remaining(simplifier, mesh);
}

UncappedBase uncapped_base(const ProgressiveMesh& pm, std::size_t centres) {
  UncappedBase out{base_mesh(pm), pm.base_vertices};
  if (centres > out.vertices.size())
    throw std::invalid_argument("uncapped_base: more centres than base vertices");
  const std::size_t kept = out.vertices.size() - centres;
  std::erase_if(out.mesh.triangles, [&](const Triangle& t) {
    return std::size_t(std::max({t[0], t[1], t[2]})) >= kept;
  });
  out.mesh.positions.resize(kept);
  out.vertices.resize(kept);
  return out;
}

ProgressiveMesh simplify_to(const TriangleMesh& mesh, std::size_t target_vertices,
                            const SimplifyOptions& options) {
  Simplifier simplifier(mesh);
  simplifier.run(target_vertices, options);

  return assemble_remaining(simplifier, mesh);
}

}  // namespace ism
