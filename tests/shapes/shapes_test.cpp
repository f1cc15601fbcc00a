// Tests of the shape generators. Topology and geometry are recomputed here
// from the raw arrays, independently of the library's own mesh checks.
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

namespace ism {
namespace {

// ---------------------------------------------------------------------------
// Local topology and geometry helpers.

struct Topology {
  int vertices = 0, edges = 0, faces = 0;
  int bad_edges = 0;          // edges without exactly two incident faces
  int misoriented_edges = 0;  // two faces crossing an edge in the same direction
  int nonmanifold_vertices = 0;
  int unreferenced_vertices = 0;
  int components = 0;
  int euler() const { return vertices - edges + faces; }
  int genus() const { return (2 * components - euler()) / 2; }
};

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

Topology topology(const TriangleMesh& mesh) {
  Topology topo;
  const int nv = static_cast<int>(mesh.n_vertices());
  topo.vertices = nv;
  topo.faces = static_cast<int>(mesh.n_faces());

  // Undirected edge -> the directions (+1 low to high, -1 high to low) of its faces.
  std::map<std::pair<int, int>, std::vector<int>> edges;
  for (const Triangle& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back(a < b ? 1 : -1);
    }
  topo.edges = static_cast<int>(edges.size());
  for (const auto& [edge, dirs] : edges) {
    if (dirs.size() != 2)
      ++topo.bad_edges;
    else if (dirs[0] + dirs[1] != 0)
      ++topo.misoriented_edges;
  }

  // Around a manifold vertex v the faces (v, a, b) chain a -> b into one cycle.
  std::vector<std::map<int, int>> fan(nv);
  std::vector<int> fan_faces(nv, 0);
  std::vector<bool> repeated(nv, false);
  for (const Triangle& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      const int v = t[c];
      ++fan_faces[v];
      if (!fan[v].emplace(t[(c + 1) % 3], t[(c + 2) % 3]).second) repeated[v] = true;
    }
  for (int v = 0; v < nv; ++v) {
    if (fan_faces[v] == 0) {
      ++topo.unreferenced_vertices;
      continue;
    }
    int steps = 0;
    const int start = fan[v].begin()->first;
    int a = start;
    do {
      auto it = fan[v].find(a);
      if (it == fan[v].end()) break;  // open fan
      a = it->second;
      ++steps;
    } while (a != start && steps <= fan_faces[v]);
    if (repeated[v] || a != start || steps != fan_faces[v]) ++topo.nonmanifold_vertices;
  }

  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (const Triangle& t : mesh.triangles)
    for (int c = 1; c < 3; ++c) parent[find_root(parent, t[c])] = find_root(parent, t[0]);
  for (int v = 0; v < nv; ++v)
    if (fan_faces[v] > 0 && find_root(parent, v) == v) ++topo.components;
  return topo;
}

Vec3 normal(const TriangleMesh& m, const Triangle& t) {
  return (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
}

Vec3 centroid(const TriangleMesh& m, const Triangle& t) {
  return (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
}

double diagonal(const TriangleMesh& m) {
  Vec3 lo = m.positions[0], hi = lo;
  for (const Vec3& p : m.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

double volume(const TriangleMesh& m) {
  double six = 0.0;
  for (const Triangle& t : m.triangles)
    six += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]]));
  return six / 6.0;
}

double area(const TriangleMesh& m) {
  double sum = 0.0;
  for (const Triangle& t : m.triangles) sum += 0.5 * normal(m, t).norm();
  return sum;
}

// Faces with a repeated index or (relative to the mesh size) zero area.
int degenerate_faces(const TriangleMesh& m) {
  const double eps = 1e-12 * diagonal(m) * diagonal(m);
  int count = 0;
  for (const Triangle& t : m.triangles)
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || 0.5 * normal(m, t).norm() <= eps) ++count;
  return count;
}

int duplicate_faces(const TriangleMesh& m) {
  std::set<Triangle> seen;
  int count = 0;
  for (Triangle t : m.triangles) {
    std::sort(t.begin(), t.end());
    if (!seen.insert(t).second) ++count;
  }
  return count;
}

// Pairs of positions closer than 1e-9 of the bounding box diagonal (sweep in x).
int duplicate_positions(const TriangleMesh& m) {
  const double tol = 1e-9 * diagonal(m);
  std::vector<Vec3> p = m.positions;
  std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
  int count = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size() && p[j].x() - p[i].x() <= tol; ++j)
      if ((p[j] - p[i]).norm() <= tol) ++count;
  return count;
}

double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

// Segment pq properly crosses triangle abc: its ends strictly on both sides
// of the plane and the line strictly inside the triangle. Volumes below eps
// count as zero, so (nearly) coplanar contact is not reported.
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                     double eps) {
  const double dp = orient(a, b, c, p), dq = orient(a, b, c, q);
  if (!((dp > eps && dq < -eps) || (dp < -eps && dq > eps))) return false;
  const double s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
  return (s1 > eps && s2 > eps && s3 > eps) || (s1 < -eps && s2 < -eps && s3 < -eps);
}

// Pairs of faces without a common vertex that intersect (brute force with a
// bounding-box filter; meant for meshes of a few thousand faces).
int intersecting_face_pairs(const TriangleMesh& m) {
  const std::size_t nf = m.n_faces();
  std::vector<Eigen::AlignedBox3d> box(nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int c : m.triangles[f]) box[f].extend(m.positions[c]);
  const double eps = 1e-12 * std::pow(diagonal(m), 3);
  int count = 0;
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t g = f + 1; g < nf; ++g) {
      if (!box[f].intersects(box[g])) continue;
      const Triangle& s = m.triangles[f];
      const Triangle& t = m.triangles[g];
      bool shared = false;
      for (int a : s)
        for (int b : t) shared = shared || a == b;
      if (shared) continue;
      bool hit = false;
      for (int i = 0; i < 3 && !hit; ++i) {
        const auto& P = m.positions;
        hit = segment_crosses(P[s[i]], P[s[(i + 1) % 3]], P[t[0]], P[t[1]], P[t[2]], eps) ||
              segment_crosses(P[t[i]], P[t[(i + 1) % 3]], P[s[0]], P[s[1]], P[s[2]], eps);
      }
      if (hit) ++count;
    }
  return count;
}

// Every property all generated shapes share.
void expect_closed_surface(const TriangleMesh& mesh, int genus) {
  ASSERT_FALSE(mesh.positions.empty());
  ASSERT_FALSE(mesh.triangles.empty());
  for (const Triangle& t : mesh.triangles)
    for (int v : t) ASSERT_TRUE(v >= 0 && v < static_cast<int>(mesh.n_vertices()));
  const Topology topo = topology(mesh);
  EXPECT_EQ(topo.bad_edges, 0) << "not closed or not edge-manifold";
  EXPECT_EQ(topo.misoriented_edges, 0) << "not consistently oriented";
  EXPECT_EQ(topo.nonmanifold_vertices, 0);
  EXPECT_EQ(topo.unreferenced_vertices, 0);
  EXPECT_EQ(topo.components, 1);
  EXPECT_EQ(2 * topo.edges, 3 * topo.faces);
  EXPECT_EQ(topo.genus(), genus) << "Euler characteristic " << topo.euler();
  EXPECT_GT(volume(mesh), 0.0) << "not oriented outward";
  EXPECT_EQ(degenerate_faces(mesh), 0);
  EXPECT_EQ(duplicate_faces(mesh), 0);
  EXPECT_EQ(duplicate_positions(mesh), 0);
}

void expect_face_count_near(const TriangleMesh& mesh, int target) {
  EXPECT_NEAR(static_cast<double>(mesh.n_faces()), target, 0.15 * target);
}

const int kTargets[] = {1000, 5000, 20000};

// ---------------------------------------------------------------------------
// The helpers themselves must see the defects they look for.

TEST(Helpers, DetectDefects) {
  const TriangleMesh sphere = shapes::sphere(320);
  const int nv = static_cast<int>(sphere.n_vertices());
  {  // Two overlapping spheres: two components that intersect.
    TriangleMesh two = sphere;
    for (const Vec3& p : sphere.positions) two.positions.push_back(p + Vec3(0.5, 0.1, 0.2));
    for (Triangle t : sphere.triangles) two.triangles.push_back({t[0] + nv, t[1] + nv, t[2] + nv});
    EXPECT_EQ(topology(two).components, 2);
    EXPECT_GT(intersecting_face_pairs(two), 0);
  }
  {  // A flipped face.
    TriangleMesh flipped = sphere;
    std::swap(flipped.triangles[7][1], flipped.triangles[7][2]);
    EXPECT_EQ(topology(flipped).misoriented_edges, 3);
  }
  {  // A hole: three open edges.
    TriangleMesh open = sphere;
    open.triangles.pop_back();
    EXPECT_EQ(topology(open).bad_edges, 3);
  }
  {  // Two spheres glued at one vertex (topologically): a pinched vertex.
    TriangleMesh pinched = sphere;
    pinched.positions.insert(pinched.positions.end(), sphere.positions.begin(),
                             sphere.positions.end());
    for (Triangle t : sphere.triangles) {
      for (int& v : t) v = v == 0 ? 0 : v + nv;
      pinched.triangles.push_back(t);
    }
    const Topology topo = topology(pinched);
    EXPECT_EQ(topo.nonmanifold_vertices, 1);
    EXPECT_EQ(topo.unreferenced_vertices, 1);
    EXPECT_EQ(topo.bad_edges, 0);
  }
  {  // A repeated position and a repeated face.
    TriangleMesh repeated = sphere;
    repeated.positions.push_back(sphere.positions[5]);
    repeated.triangles.push_back(sphere.triangles[3]);
    EXPECT_EQ(duplicate_positions(repeated), 1);
    EXPECT_EQ(duplicate_faces(repeated), 1);
  }
}

// ---------------------------------------------------------------------------
// Sphere and ellipsoid.

TEST(Sphere, ExactCountsAndTopology) {
  // target -> frequency n = round(sqrt(target / 20)): F = 20 n^2, V = 10 n^2 + 2.
  struct Case {
    int target, faces, vertices;
  };
  for (const Case c : {Case{0, 20, 12}, Case{80, 80, 42}, Case{1000, 980, 492},
                       Case{5000, 5120, 2562}, Case{20000, 20480, 10242}}) {
    SCOPED_TRACE(c.target);
    const TriangleMesh mesh = shapes::sphere(c.target);
    EXPECT_EQ(mesh.n_faces(), static_cast<std::size_t>(c.faces));
    EXPECT_EQ(mesh.n_vertices(), static_cast<std::size_t>(c.vertices));
    expect_closed_surface(mesh, 0);
  }
}

TEST(Sphere, VerticesOnSphereAndFacesOutward) {
  for (double radius : {1.0, 2.5}) {
    const TriangleMesh mesh = shapes::sphere(5000, radius);
    for (const Vec3& p : mesh.positions) ASSERT_NEAR(p.norm(), radius, 1e-12);
    for (const Triangle& t : mesh.triangles) ASSERT_GT(normal(mesh, t).dot(centroid(mesh, t)), 0);
    const double exact = 4.0 / 3.0 * M_PI * radius * radius * radius;
    EXPECT_NEAR(volume(mesh), exact, 0.01 * exact);
    EXPECT_NEAR(area(mesh), 4.0 * M_PI * radius * radius, 0.01 * 4.0 * M_PI * radius * radius);
  }
}

TEST(Sphere, Deterministic) {
  const TriangleMesh a = shapes::sphere(3000), b = shapes::sphere(3000);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(Ellipsoid, VerticesOnEllipsoid) {
  const Vec3 axes(3.0, 2.0, 0.5);
  for (int target : kTargets) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::ellipsoid(target, axes);
    expect_closed_surface(mesh, 0);
    expect_face_count_near(mesh, target);
    EXPECT_EQ(mesh.n_faces(), shapes::sphere(target).n_faces());
    for (const Vec3& p : mesh.positions)
      ASSERT_NEAR(p.cwiseQuotient(axes).squaredNorm(), 1.0, 1e-12);
  }
  const TriangleMesh mesh = shapes::ellipsoid(20000, axes);
  const double exact = 4.0 / 3.0 * M_PI * axes.prod();
  EXPECT_NEAR(volume(mesh), exact, 0.01 * exact);
}

// ---------------------------------------------------------------------------
// Blob.

TEST(Blob, ClosedGenusZeroStarShaped) {
  for (int target : kTargets) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::blob(target);
    expect_closed_surface(mesh, 0);
    expect_face_count_near(mesh, target);
    EXPECT_EQ(mesh.n_faces(), shapes::sphere(target).n_faces());
  }
}

TEST(Blob, StarShapedForManySeeds) {
  for (std::uint64_t seed = 0; seed < 30; ++seed) {
    SCOPED_TRACE(seed);
    const TriangleMesh mesh = shapes::blob(2000, seed, 0.6);
    for (const Vec3& p : mesh.positions) ASSERT_GT(p.norm(), 0.3);
    for (const Triangle& t : mesh.triangles) ASSERT_GT(normal(mesh, t).dot(centroid(mesh, t)), 0);
  }
}

TEST(Blob, IsBumpy) {
  const TriangleMesh mesh = shapes::blob(5000);
  double lo = 1e9, hi = 0;
  for (const Vec3& p : mesh.positions) lo = std::min(lo, p.norm()), hi = std::max(hi, p.norm());
  EXPECT_GT(hi - lo, 0.1);
}

TEST(Blob, EmbeddedAtLowResolution) {
  EXPECT_EQ(intersecting_face_pairs(shapes::blob(1000, 3, 0.6)), 0);
}

TEST(Blob, DeterministicPerSeed) {
  const TriangleMesh a = shapes::blob(2000, 42), b = shapes::blob(2000, 42);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  const TriangleMesh c = shapes::blob(2000, 43);
  ASSERT_EQ(a.n_vertices(), c.n_vertices());
  double max_diff = 0.0;
  for (std::size_t v = 0; v < a.n_vertices(); ++v)
    max_diff = std::max(max_diff, (a.positions[v] - c.positions[v]).norm());
  EXPECT_GT(max_diff, 1e-3);
}

TEST(Blob, MatchesRecordedRadii) {
  // Pins the generator (mt19937_64 plus our own conversion to doubles), so an
  // accidental change of the draw order shows up here.
  const TriangleMesh mesh = shapes::blob(80, 1);
  EXPECT_NEAR(mesh.positions[0].norm(), 1.030155963247284, 1e-9);
  EXPECT_NEAR(mesh.positions[5].norm(), 1.188856017187874, 1e-9);
  EXPECT_NEAR(mesh.positions[11].norm(), 1.007049477535846, 1e-9);
}

// ---------------------------------------------------------------------------
// Torus.

TEST(Torus, ClosedGenusOne) {
  for (int target : kTargets) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::torus(target);
    expect_closed_surface(mesh, 1);
    expect_face_count_near(mesh, target);
  }
  expect_closed_surface(shapes::torus(0), 1);  // the minimal 3 x 3 grid
}

TEST(Torus, VerticesOnTorusAndArea) {
  for (auto [R, r] : {std::pair{2.0, 1.0}, std::pair{3.0, 0.5}}) {
    SCOPED_TRACE(R);
    const TriangleMesh mesh = shapes::torus(20000, R, r);
    expect_closed_surface(mesh, 1);
    expect_face_count_near(mesh, 20000);
    for (const Vec3& p : mesh.positions) {
      const double d = std::hypot(p.x(), p.y()) - R;
      ASSERT_NEAR(d * d + p.z() * p.z(), r * r, 1e-9);
    }
    const double exact_area = 4.0 * M_PI * M_PI * R * r;
    EXPECT_NEAR(area(mesh), exact_area, 0.01 * exact_area);
    const double exact_volume = 2.0 * M_PI * M_PI * R * r * r;
    EXPECT_NEAR(volume(mesh), exact_volume, 0.01 * exact_volume);
  }
}

TEST(Torus, DocumentedVertexLayout) {
  const TriangleMesh mesh = shapes::torus(1000);
  // Vertex 0 is on the outer equator at angle 0; vertex 1 is one step around the tube.
  EXPECT_NEAR((mesh.positions[0] - Vec3(3.0, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(mesh.positions[1].y(), 0.0, 1e-12);
  EXPECT_GT(mesh.positions[1].z(), 0.0);
}

TEST(Torus, EmbeddedAtLowResolution) {
  EXPECT_EQ(intersecting_face_pairs(shapes::torus(1500)), 0);
}

// ---------------------------------------------------------------------------
// Double torus.

TEST(DoubleTorus, ClosedGenusTwo) {
  for (int target : {100, 1000, 5000, 20000}) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::double_torus(target);
    expect_closed_surface(mesh, 2);
    if (target >= 1000) expect_face_count_near(mesh, target);
  }
}

TEST(DoubleTorus, EmbeddedAndRounded) {
  // target -> largest dihedral angle allowed between adjacent faces.
  for (auto [target, max_angle] : {std::pair{1000, 60.0}, std::pair{5000, 40.0}}) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::double_torus(target);
    EXPECT_EQ(intersecting_face_pairs(mesh), 0);
    // The voxel boundary has 90 degree creases; the smoothed one should not.
    double min_cos = 1.0;
    std::map<std::pair<int, int>, Vec3> first_normal;
    for (const Triangle& t : mesh.triangles)
      for (int c = 0; c < 3; ++c) {
        const int a = t[c], b = t[(c + 1) % 3];
        const Vec3 n = normal(mesh, t).normalized();
        auto [it, inserted] = first_normal.try_emplace({std::min(a, b), std::max(a, b)}, n);
        if (!inserted) min_cos = std::min(min_cos, it->second.dot(n));
      }
    EXPECT_GT(min_cos, std::cos(max_angle * M_PI / 180))
        << "creases of " << max_angle << " degrees";
  }
}

TEST(DoubleTorus, ShapeIndependentOfResolution) {
  auto extent = [](const TriangleMesh& m) -> Vec3 {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : m.positions) box.extend(p);
    return box.sizes();
  };
  const TriangleMesh reference = shapes::double_torus(20000);
  for (int target : {2000, 5000, 50000}) {
    SCOPED_TRACE(target);
    const TriangleMesh mesh = shapes::double_torus(target);
    EXPECT_LT((extent(mesh) - extent(reference)).norm(), 0.05);
    EXPECT_NEAR(volume(mesh), volume(reference), 0.03 * volume(reference));
  }
}

}  // namespace
}  // namespace ism
