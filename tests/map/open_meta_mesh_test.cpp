// Open maps in the meta-mesh: two different triangulations of the unit
// square overlaid in the plane (each side's boundary vertices on the other's
// boundary edges) validate from both sides, measure the identity as
// stretch-free, map points to themselves, survive a file round trip, and
// every corruption of their boundary records is found.
#include "inter_surface_map_access.hpp"
#include "io/io.hpp"
#include "map/inter_surface_map.hpp"
#include "map/map.hpp"
#include "map/meta_cut.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace ism {
namespace {

/// A triangulation of the unit square in the plane.
struct PlanarMesh {
  std::vector<Vec2> p;
  std::vector<Triangle> faces;
};

/// An n × n grid of the unit square, each cell split by a random diagonal:
/// the corners fixed, the other boundary vertices moved along their side and
/// the interior ones in both directions, by up to `jitter` of a cell.
PlanarMesh jittered_square(int n, double jitter, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-jitter / n, jitter / n);
  PlanarMesh m;
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      Vec2 q(double(i) / n, double(j) / n);
      const bool side_x = i == 0 || i == n, side_y = j == 0 || j == n;
      if (!side_x) q.x() += u(rng);
      if (!side_y) q.y() += u(rng);
      m.p.push_back(q);
    }
  std::bernoulli_distribution flip(0.5);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (flip(rng)) {
        m.faces.push_back({a, b, c});
        m.faces.push_back({a, c, d});
      } else {
        m.faces.push_back({a, b, d});
        m.faces.push_back({b, c, d});
      }
    }
  return m;
}

/// The lengths of a face from positions (2D or 3D).
template <class P>
FaceLengths lengths_of(const std::vector<P>& x, const Triangle& t) {
  return {(x[t[1]] - x[t[0]]).norm(), (x[t[2]] - x[t[1]]).norm(), (x[t[0]] - x[t[2]]).norm()};
}

/// The identity of the plane as a meta-mesh between two triangulations of
/// the same square (in general position inside it): locations and crossings
/// found by brute force. Side m's metric is that of `metric[m]` when given
/// (another planar drawing of the same faces), else its own.
MetaMesh planar_overlay(const std::array<const PlanarMesh*, 2>& mesh,
                        const std::array<const std::vector<Vec2>*, 2>& metric = {nullptr,
                                                                                 nullptr}) {
  MetaMesh meta;
  for (int m = 0; m < 2; ++m) {
    MetaSide& side = meta.side[m];
    side.faces = mesh[m]->faces;
    for (const Triangle& t : side.faces)
      side.lengths.push_back(lengths_of(metric[m] ? *metric[m] : mesh[m]->p, t));
    if (!build_edges(side, true)) throw std::logic_error("not a manifold");
    side.location.assign(mesh[m]->p.size(), {});
    side.crossings.assign(side.edges.size(), {});
  }
  const MetaIndex index = build_index(meta);
  for (int m = 0; m < 2; ++m) {
    const PlanarMesh &X = *mesh[m], &Y = *mesh[1 - m];
    const MetaSide& other = meta.side[1 - m];
    for (std::size_t v = 0; v < X.p.size(); ++v) {
      MetaLocation& loc = meta.side[m].location[v];
      for (std::size_t w = 0; w < Y.p.size() && loc.vertex < 0; ++w)
        if ((X.p[v] - Y.p[w]).norm() < 1e-12) loc.vertex = int(w);
      if (loc.vertex >= 0) continue;
      for (std::size_t f = 0; f < Y.faces.size(); ++f) {
        const Triangle& t = Y.faces[f];
        const std::array<Vec2, 3> c{Y.p[t[0]], Y.p[t[1]], Y.p[t[2]]};
        const double a = orient(c[0], c[1], c[2]);
        const Eigen::Vector3d b(orient(X.p[v], c[1], c[2]) / a, orient(c[0], X.p[v], c[2]) / a,
                                orient(c[0], c[1], X.p[v]) / a);
        if (b.minCoeff() < -1e-13) continue;
        int zero = -1;
        for (int k = 0; k < 3; ++k)
          if (std::abs(b[k]) < 1e-13) zero = k;
        if (zero < 0) {
          loc.face = int(f);
          loc.bary = b;
        } else {  // on the edge opposite corner `zero`: a boundary edge
          const int k = (zero + 1) % 3, k1 = (zero + 2) % 3;
          const int e = other.face_edges[f][k];
          if (!index[1 - m].is_boundary(e)) throw std::logic_error("not in general position");
          const double along = b[k1] / (b[k] + b[k1]);  // from corner k
          set_edge_location(loc, other, int(f), e, t[k] == other.edges[e][0] ? along : 1 - along);
        }
        break;
      }
      if (loc.face < 0) throw std::logic_error("a vertex outside the other mesh");
    }
  }
  // Crossings of interior edges.
  const MetaSide &s0 = meta.side[0], &s1 = meta.side[1];
  for (std::size_t e = 0; e < s0.edges.size(); ++e) {
    if (index[0].is_boundary(int(e))) continue;
    const Vec2 &a = mesh[0]->p[s0.edges[e][0]], &b = mesh[0]->p[s0.edges[e][1]];
    for (std::size_t g = 0; g < s1.edges.size(); ++g) {
      if (index[1].is_boundary(int(g))) continue;
      const Vec2 &c = mesh[1]->p[s1.edges[g][0]], &d = mesh[1]->p[s1.edges[g][1]];
      const double da = orient(c, d, a), db = orient(c, d, b), dc = orient(a, b, c),
                   dd = orient(a, b, d);
      if (!(da * db < 0 && dc * dd < 0)) continue;
      const double here = da / (da - db), there = dc / (dc - dd);
      if (here < 1e-9 || here > 1 - 1e-9 || there < 1e-9 || there > 1 - 1e-9)
        throw std::logic_error("not in general position");
      meta.side[0].crossings[e].push_back({int(g), here, there});
      meta.side[1].crossings[g].push_back({int(e), there, here});
    }
  }
  for (MetaSide& side : meta.side)
    for (auto& list : side.crossings)
      std::sort(list.begin(), list.end(),
                [](const MetaCrossing& x, const MetaCrossing& y) { return x.here < y.here; });
  return meta;
}

/// Boundary vertices of a planar square mesh that are not its corners.
std::size_t side_points(const PlanarMesh& m) {
  std::size_t n = 0;
  for (const Vec2& q : m.p) {
    const bool on_x = q.x() == 0 || q.x() == 1, on_y = q.y() == 0 || q.y() == 1;
    n += on_x != on_y;
  }
  return n;
}

Vec2 point_of(const PlanarMesh& m, int f, const Eigen::Vector3d& b) {
  const Triangle& t = m.faces[f];
  return b[0] * m.p[t[0]] + b[1] * m.p[t[1]] + b[2] * m.p[t[2]];
}

TEST(OpenMetaMesh, TwoTriangulationsOfASquareOverlaidAreTheIdentity) {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    const int na = 2 + int(seed % 4), nb = 3 + int(seed % 5) + int(seed % 2);
    const PlanarMesh A = jittered_square(na, 0.3, rng), B = jittered_square(nb, 0.3, rng);
    const MetaMesh meta = planar_overlay({&A, &B});
    ASSERT_EQ(validate(meta), std::nullopt);
    ASSERT_EQ(validate(swapped(meta)), std::nullopt);
    const auto m = measures(meta);
    ASSERT_TRUE(m.has_value());
    EXPECT_NEAR(m->symmetric_efficiency, 1.0, 1e-12);
    EXPECT_NEAR(m->forward_efficiency, 1.0, 1e-12);
    EXPECT_NEAR(m->backward_efficiency, 1.0, 1e-12);
    const MetaMeshSize size = meta_mesh_size(meta);
    EXPECT_EQ(size.on_boundary_edges, side_points(A) + side_points(B));
    EXPECT_EQ(size.shared_vertices, 4u);  // the corners
    EXPECT_GT(size.crossings, 0u);
    // The pieces tile the square from both sides.
    const auto pieces = meta_pieces(meta);
    ASSERT_TRUE(pieces.has_value());
    double area[2] = {0, 0};
    for (const MetaPiece& p : *pieces) area[0] += p.area[0], area[1] += p.area[1];
    EXPECT_NEAR(area[0], 1.0, 1e-12);
    EXPECT_NEAR(area[1], 1.0, 1e-12);
    // Points map to themselves both ways, near the boundary too.
    const MetaMeshSampler sampler(meta);
    std::uniform_real_distribution<double> r(0, 1);
    for (int m_side = 0; m_side < 2; ++m_side) {
      const PlanarMesh& X = m_side == 0 ? A : B;
      const PlanarMesh& Y = m_side == 0 ? B : A;
      for (std::size_t f = 0; f < X.faces.size(); ++f)
        for (int i = 0; i < 4; ++i) {
          double u = r(rng), v = r(rng);
          if (u + v > 1) u = 1 - u, v = 1 - v;
          if (i == 0) v = 1e-15;  // next to an edge (a boundary edge for some faces)
          const Eigen::Vector3d b(1 - u - v, u, v);
          const auto image = sampler.map_point(m_side, int(f), b);
          ASSERT_TRUE(image.has_value());
          EXPECT_LT((point_of(Y, image->face, image->bary) - point_of(X, int(f), b)).norm(), 1e-12);
        }
    }
  }
}

TEST(OpenMetaMesh, ADeformedMetricValidatesAndMeasuresBelowOne) {
  std::mt19937 rng(7);
  const PlanarMesh A = jittered_square(4, 0.3, rng), B = jittered_square(6, 0.3, rng);
  // B's faces measured on a smooth deformation of the square (its faces stay
  // positive): the map is then the deformation, piecewise linear.
  std::vector<Vec2> bent;
  for (const Vec2& q : B.p)
    bent.push_back({q.x() + 0.1 * std::sin(3 * q.y()), q.y() * (1 + 0.3 * q.x())});
  const MetaMesh meta = planar_overlay({&A, &B}, {nullptr, &bent});
  ASSERT_EQ(validate(meta), std::nullopt);
  const auto m = measures(meta);
  ASSERT_TRUE(m.has_value());
  EXPECT_LT(m->symmetric_efficiency, 0.999);
  EXPECT_GT(m->symmetric_efficiency, 0.8);
  const auto s = measures(swapped(meta));
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->forward_efficiency, m->backward_efficiency, 1e-12);
}

TEST(OpenMetaMesh, FilesOfOpenMapsReadBackExactly) {
  std::mt19937 rng(3);
  const PlanarMesh A = jittered_square(3, 0.3, rng), B = jittered_square(5, 0.3, rng);
  const MetaMesh meta = planar_overlay({&A, &B});
  const auto path = std::filesystem::temp_directory_path() / "ism_open_meta_mesh.txt";
  ASSERT_TRUE(write_meta_mesh(meta, path));
  {
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first, "ism-meta-mesh 3");
  }
  const MetaMesh back = read_meta_mesh(path);
  ASSERT_EQ(validate(back), std::nullopt);
  for (int m = 0; m < 2; ++m)
    for (std::size_t v = 0; v < meta.side[m].n_vertices(); ++v) {
      const MetaLocation &a = meta.side[m].location[v], &b = back.side[m].location[v];
      EXPECT_EQ(a.vertex, b.vertex);
      EXPECT_EQ(a.edge >= 0, b.edge >= 0);
      if (a.edge >= 0) {
        EXPECT_EQ(meta.side[1 - m].edges[a.edge], back.side[1 - m].edges[b.edge]);
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.face, b.face);
        EXPECT_EQ(a.bary, b.bary);
      }
    }
  EXPECT_EQ(measures(back)->symmetric_efficiency, measures(meta)->symmetric_efficiency);
  // A version 2 file may not hold boundary-edge locations.
  std::stringstream text;
  {
    std::ifstream in(path);
    text << in.rdbuf();
  }
  std::string s = text.str();
  s.replace(0, std::string("ism-meta-mesh 3").size(), "ism-meta-mesh 2");
  {
    std::ofstream out(path);
    out << s;
  }
  try {
    read_meta_mesh(path);
    ADD_FAILURE() << "a version 2 file with a b record was read";
  } catch (const io::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("need 'ism-meta-mesh 3'"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(OpenMetaMesh, CorruptBoundaryRecordsAreFound) {
  std::mt19937 rng(5);
  const PlanarMesh A = jittered_square(3, 0.3, rng), B = jittered_square(4, 0.3, rng);
  const MetaMesh good = planar_overlay({&A, &B});
  ASSERT_EQ(validate(good), std::nullopt);
  // A vertex of B on a boundary edge of A, and an interior vertex of B.
  int on_edge = -1, inside = -1;
  for (std::size_t v = 0; v < good.side[1].n_vertices(); ++v) {
    const MetaLocation& loc = good.side[1].location[v];
    if (loc.on_edge() && on_edge < 0) on_edge = int(v);
    if (!loc.on_edge() && loc.face >= 0 && inside < 0) inside = int(v);
  }
  ASSERT_GE(on_edge, 0);
  ASSERT_GE(inside, 0);
  auto expect_error = [](const MetaMesh& meta, const std::string& what) {
    const auto error = validate(meta);
    ASSERT_TRUE(error.has_value()) << what;
    EXPECT_NE(error->find(what), std::string::npos) << *error;
  };
  {  // The boundary vertex said to lie inside its face.
    MetaMesh bad = good;
    MetaLocation& loc = bad.side[1].location[on_edge];
    loc.edge = -1;
    loc.bary = Eigen::Vector3d(0.2, 0.3, 0.5);
    expect_error(bad, "a boundary vertex inside a face of the other mesh");
  }
  {  // Slid a little along its edge: another map, as valid (each side's
     // records place the meta-vertices in its own faces).
    MetaMesh moved = good;
    MetaLocation& loc = moved.side[1].location[on_edge];
    set_edge_location(loc, moved.side[0], loc.face, loc.edge,
                      loc.t < 0.5 ? loc.t + 1e-3 : loc.t - 1e-3);
    EXPECT_EQ(validate(moved), std::nullopt);
  }
  {  // Moved onto a boundary edge of another face: its edges' records no
     // longer close.
    MetaMesh bad = good;
    MetaLocation& loc = bad.side[1].location[on_edge];
    const MetaIndex index = build_index(bad);
    int face = -1, edge = -1;
    for (std::size_t f = 0; f < bad.side[0].faces.size() && edge < 0; ++f) {
      if (int(f) == loc.face) continue;
      for (int e : bad.side[0].face_edges[f])
        if (index[0].is_boundary(e) && e != loc.edge) face = int(f), edge = e;
    }
    ASSERT_GE(edge, 0);
    set_edge_location(loc, bad.side[0], face, edge, 0.5);
    EXPECT_TRUE(validate(bad).has_value());
  }
  {  // Its parameter and barycentric coordinates disagree.
    MetaMesh bad = good;
    bad.side[1].location[on_edge].t = 0.5 * bad.side[1].location[on_edge].t + 0.25;
    expect_error(bad, "off its boundary edge");
  }
  {  // An interior vertex put on a boundary edge.
    MetaMesh bad = good;
    const MetaLocation& ref = good.side[1].location[on_edge];
    set_edge_location(bad.side[1].location[inside], bad.side[0], ref.face, ref.edge, 0.5);
    expect_error(bad, "an interior vertex on the other mesh's boundary");
  }
  {  // A location on an interior edge.
    MetaMesh bad = good;
    const MetaIndex index = build_index(bad);
    int f = good.side[1].location[inside].face, e = -1;
    for (int x : bad.side[0].face_edges[f])
      if (!index[0].is_boundary(x)) e = x;
    ASSERT_GE(e, 0);
    set_edge_location(bad.side[1].location[on_edge], bad.side[0], f, e, 0.5);
    expect_error(bad, "not a boundary edge");
  }
  {  // A break point on a boundary edge.
    MetaMesh bad = good;
    const MetaIndex index = build_index(bad);
    for (std::size_t e = 0; e < bad.side[0].edges.size(); ++e)
      if (index[0].is_boundary(int(e))) {
        bad.side[0].crossings[e].push_back(MetaCrossing{-1, 0.5, 0, 0, Eigen::Vector3d(1, 0, 0)});
        break;
      }
    expect_error(bad, "a boundary edge with break points");
  }
  {  // A corner of one square on a vertex of the other that is not a corner.
    MetaMesh bad = good;
    // Vertex 0 of A (a corner, on B's vertex 0) exchanged with an interior
    // vertex of B: B's interior vertex said to be on A's corner.
    const int corner_b = good.side[0].location[0].vertex;
    ASSERT_GE(corner_b, 0);
    bad.side[0].location[0].vertex = inside;
    bad.side[1].location[inside] = MetaLocation{};
    bad.side[1].location[inside].vertex = 0;
    bad.side[1].location[corner_b] = good.side[1].location[inside];
    expect_error(bad, "a boundary vertex on an interior vertex of the other mesh");
  }
}

/// Side m of a planar overlay as an abstract domain of the map core, its
/// metric the meta-mesh's (extra: unused vertex slots to split into).
MapSideInput open_side(const MetaMesh& meta, int m, std::size_t extra = 0) {
  TriangleMesh mesh;
  mesh.triangles = meta.side[m].faces;
  mesh.positions.assign(meta.side[m].n_vertices(), Vec3::Zero());
  MapSideInput in = side_from_domain(mesh, meta.side[m].lengths);
  in.n_vertices += extra;
  return in;
}

/// Whether the map core's views of its meta-mesh are those built anew
/// (lists in any order where their order is not kept).
bool index_current(const InterSurfaceMap& map) {
  const MetaIndex fresh = build_index(map.meta());
  const MetaIndex& kept = InterSurfaceMapTestAccess::index(map);
  auto sorted = [](std::vector<std::vector<int>> lists) {
    for (auto& l : lists) std::sort(l.begin(), l.end());
    return lists;
  };
  for (int s = 0; s < 2; ++s) {
    const MetaSideIndex &a = kept[s], &b = fresh[s];
    if (a.edge_faces != b.edge_faces || a.on_edge != b.on_edge || a.edge_of != b.edge_of ||
        sorted(a.vertex_edges) != sorted(b.vertex_edges) ||
        sorted(a.vertex_faces) != sorted(b.vertex_faces) ||
        sorted(a.residents) != sorted(b.residents) || sorted(a.lodgers) != sorted(b.lodgers))
      return false;
  }
  return true;
}

TEST(OpenMetaMesh, TheMapCoreOptimisesAnOpenMapUpToItsBoundary) {
  std::mt19937 rng(9);
  const PlanarMesh A = jittered_square(6, 0.3, rng), B = jittered_square(8, 0.3, rng);
  std::vector<Vec2> bent;
  for (const Vec2& q : B.p)
    bent.push_back({q.x() + 0.1 * std::sin(3 * q.y()), q.y() * (1 + 0.3 * q.x())});
  const MetaMesh meta = planar_overlay({&A, &B}, {nullptr, &bent});
  ASSERT_EQ(validate(meta), std::nullopt);
  InterSurfaceMap map(meta, open_side(meta, 0), open_side(meta, 1), {0, 0});
  ASSERT_EQ(map.validate(), std::nullopt);
  const double start = map.energy();
  double energy = start;
  std::size_t moves = 0, moved_near_boundary = 0, moved_over_lodgers = 0, slid = 0;
  const MetaIndex index = build_index(meta);
  // Whether v's ring has a boundary edge, and one with vertices of the
  // other side on it (fixed anchors of its chart's boundary).
  auto near_boundary = [&](int s, int v, bool lodgers) {
    for (int f : index[s].vertex_faces[v])
      for (int e : meta.side[s].face_edges[f])
        if (index[s].is_boundary(e) && (!lodgers || !index[s].on_edge[e].empty())) return true;
    return false;
  };
  for (int sweep = 0; sweep < 3; ++sweep)
    for (int s = 0; s < 2; ++s)
      for (std::size_t v = 0; v < meta.side[s].n_vertices(); ++v) {
        const double gain = map.optimize_vertex(s, int(v));
        const double after = map.energy();
        // Every accepted move lowers the energy by exactly its gain.
        EXPECT_NEAR(energy - after, gain, 1e-12 * energy);
        if (gain > 0) {
          ++moves;
          slid += meta.side[s].location[v].on_edge();
          moved_near_boundary += near_boundary(s, int(v), false);
          moved_over_lodgers += near_boundary(s, int(v), true);
          ASSERT_EQ(map.validate(), std::nullopt)
              << "after moving vertex " << v << " of side " << s;
        }
        energy = after;
      }
  std::printf(
      "open square map: energy %.6f -> %.6f in %zu moves (%zu next to the boundary, %zu over "
      "the other side's vertices on it, %zu boundary vertices slid)\n",
      start, energy, moves, moved_near_boundary, moved_over_lodgers, slid);
  EXPECT_GT(moves, 20u);
  EXPECT_LT(energy, start * (1 - 1e-4));
  // Vertices whose rings reach the boundary move too, also where the other
  // side's vertices on a boundary edge are anchors of the chart.
  EXPECT_GT(moved_near_boundary, 10u);
  EXPECT_GT(moved_over_lodgers, 5u);
  // Boundary vertices slide along the other side's boundary edge they lie
  // on; the corners, on each other, stay.
  EXPECT_GT(slid, 5u);
  for (int s = 0; s < 2; ++s)
    for (std::size_t v = 0; v < meta.side[s].n_vertices(); ++v) {
      const MetaLocation &was = meta.side[s].location[v], &is = map.meta().side[s].location[v];
      if (was.on_edge()) {
        EXPECT_EQ(is.edge, was.edge);
      } else if (was.vertex >= 0) {
        EXPECT_EQ(is.vertex, was.vertex);
      }
    }
  ASSERT_EQ(validate(swapped(map.meta())), std::nullopt);
  EXPECT_TRUE(index_current(map));
  const auto m = measures(map.meta());
  ASSERT_TRUE(m.has_value());
  EXPECT_GT(m->symmetric_efficiency, measures(meta)->symmetric_efficiency);
}

TEST(OpenMetaMesh, TheTrivialMapOfTwoOpenBasesIsValidAndASplitAtTheBoundaryIsRefused) {
  std::mt19937 rng(4);
  const PlanarMesh A = jittered_square(3, 0.3, rng);
  std::vector<Vec2> bent;
  for (const Vec2& q : A.p) bent.push_back({q.x() * (1 + 0.5 * q.y()), q.y()});
  // Two copies of one open base with different metrics.
  MetaMesh meta = planar_overlay({&A, &A}, {nullptr, &bent});
  ASSERT_EQ(validate(meta), std::nullopt);
  InterSurfaceMap trivial(open_side(meta, 0), open_side(meta, 1));
  ASSERT_EQ(trivial.validate(), std::nullopt);
  EXPECT_EQ(meta_mesh_size(trivial.meta()).pieces, A.faces.size());
  EXPECT_NEAR(trivial.energy(), 2 / measures(meta)->symmetric_efficiency, 1e-12);
  // A split of boundary vertex 1 (on the square's bottom side) into an
  // unused vertex slot: refused, the map as it was.
  meta.side[1].location.push_back({});
  MapSideInput b = open_side(meta, 1, 0);
  b.splits.push_back({int(A.p.size()), 1, 0, 2, Vec3::Zero()});
  InterSurfaceMap map(meta, open_side(meta, 0), b, {0, 0});
  const double before = map.energy();
  try {
    map.split_next(1);
    ADD_FAILURE() << "a split at the boundary was applied";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a split at the boundary"), std::string::npos) << e.what();
  }
  EXPECT_EQ(map.energy(), before);
  EXPECT_EQ(map.splits_applied(1), 0u);
  EXPECT_EQ(map.validate(), std::nullopt);
}

TEST(OpenMetaMesh, BoundaryVerticesSlideBackToTheIdentity) {
  // B's metric is its own drawing with its boundary vertices moved along
  // their sides (by up to 2 % of the side): the map that is an isometry
  // puts them there, which only sliding along A's boundary reaches.
  std::mt19937 rng(5);
  const PlanarMesh A = jittered_square(6, 0.3, rng), B = jittered_square(5, 0.3, rng);
  std::uniform_real_distribution<double> shift(-0.02, 0.02);
  std::vector<Vec2> drawn = B.p;
  for (Vec2& q : drawn) {
    const bool on_x = q.x() == 0 || q.x() == 1, on_y = q.y() == 0 || q.y() == 1;
    if (on_x && !on_y) q.y() += shift(rng);
    if (on_y && !on_x) q.x() += shift(rng);
  }
  const MetaMesh meta = planar_overlay({&A, &B}, {nullptr, &drawn});
  ASSERT_EQ(validate(meta), std::nullopt);
  const double start = measures(meta)->symmetric_efficiency;
  InterSurfaceMap map(meta, open_side(meta, 0), open_side(meta, 1), {0, 0});
  std::size_t slid = 0;
  for (int sweep = 0; sweep < 12; ++sweep)
    for (int s = 0; s < 2; ++s)
      for (std::size_t v = 0; v < meta.side[s].n_vertices(); ++v) {
        const bool boundary = map.meta().side[s].location[v].on_edge();
        slid += boundary && map.optimize_vertex(s, int(v)) > 0;
        if (!boundary) map.optimize_vertex(s, int(v));
      }
  ASSERT_EQ(map.validate(), std::nullopt);
  const double end = measures(map.meta())->symmetric_efficiency;
  // Where B's boundary vertices went along their sides, against where
  // its metric puts them.
  double worst = 0, before = 0;
  for (std::size_t v = 0; v < B.p.size(); ++v) {
    const MetaLocation& loc = map.meta().side[1].location[v];
    if (!loc.on_edge()) continue;
    const Vec2 at = point_of(A, loc.face, loc.bary);
    worst = std::max(worst, (at - drawn[v]).norm());
    before = std::max(before, (B.p[v] - drawn[v]).norm());
  }
  std::printf(
      "boundary slid back: efficiency %.6f -> %.6f, %zu slides; B's boundary vertices %.2e -> "
      "%.2e from where its metric puts them\n",
      start, end, slid, before, worst);
  EXPECT_LT(1 - end, 0.25 * (1 - start));
  EXPECT_LT(worst, 0.25 * before);
}

TEST(OpenMetaMesh, AnInteriorVertexWhoseRingReachesTheBoundarySplitsAndMoves) {
  std::mt19937 rng(21);
  const PlanarMesh A = jittered_square(5, 0.3, rng), B = jittered_square(7, 0.3, rng);
  std::vector<Vec2> bent;
  for (const Vec2& q : A.p) bent.push_back({q.x() * (1 + 0.4 * q.y()), q.y() + 0.1 * q.x()});
  MetaMesh meta = planar_overlay({&A, &B}, {&bent, nullptr});
  ASSERT_EQ(validate(meta), std::nullopt);
  const MetaIndex index = build_index(meta);
  // An interior vertex of B with a boundary edge holding vertices of A in
  // its ring: its ring in order, counter-clockwise, from vl.
  const MetaSide& SB = meta.side[1];
  int vt = -1;
  std::vector<int> ring;
  std::size_t boundary_at = 0;
  for (std::size_t v = 0; v < B.p.size() && vt < 0; ++v) {
    const Vec2& q = B.p[v];
    if (q.x() == 0 || q.x() == 1 || q.y() == 0 || q.y() == 1) continue;
    const auto& around = index[1].vertex_faces[v];
    ring.clear();
    int f = around.front();
    for (std::size_t k = 0; k < around.size(); ++k) {
      const Triangle& tri = SB.faces[f];
      const int c = tri[0] == int(v) ? 0 : tri[1] == int(v) ? 1 : 2;
      ring.push_back(tri[(c + 1) % 3]);
      const int e = SB.face_edges[f][(c + 1) % 3];
      if (index[1].is_boundary(e) && !index[1].on_edge[e].empty()) vt = int(v), boundary_at = k;
      for (int g : around) {
        const Triangle& h = SB.faces[g];
        const int d = h[0] == int(v) ? 0 : h[1] == int(v) ? 1 : 2;
        if (h[(d + 1) % 3] == tri[(c + 2) % 3]) f = g;
      }
    }
  }
  ASSERT_GE(vt, 0);
  // vl before the boundary edge, vr two ring positions after it: vs takes
  // the faces between them, the boundary edge's among them.
  const std::size_t r = ring.size();
  const int vl = ring[(boundary_at + r - 1) % r], vr = ring[(boundary_at + 2) % r];
  const Vec2 wedge = 0.5 * (B.p[ring[boundary_at]] + B.p[ring[(boundary_at + 1) % r]]);
  const Vec2 at = B.p[vt] + 0.3 * (wedge - B.p[vt]);
  const int vs = int(B.p.size());
  MapSideInput b;
  b.base_faces = B.faces;
  for (std::size_t v = 0; v < B.p.size(); ++v) {
    b.base_vertices.push_back(int(v));
    b.positions.push_back({B.p[v].x(), B.p[v].y(), 0});
  }
  b.positions.push_back({at.x(), at.y(), 0});
  b.n_vertices = b.positions.size();
  b.splits.push_back({vs, vt, vl, vr, b.positions.back()});
  meta.side[1].location.push_back({});
  InterSurfaceMap map(meta, open_side(meta, 0), b, {0, 0});
  ASSERT_EQ(map.validate(), std::nullopt);
  ASSERT_EQ(map.split_next(1), vs);
  EXPECT_EQ(map.splits_applied(1), 1u);
  ASSERT_EQ(map.validate(), std::nullopt);
  ASSERT_EQ(validate(swapped(map.meta())), std::nullopt);
  // The new vertex and the split one move, over the other side's vertices
  // on the boundary edge now in vs's ring; each move gains what it says.
  double energy = map.energy();
  ASSERT_TRUE(energy < HUGE_VAL);
  std::size_t moves = 0;
  for (int sweep = 0; sweep < 4; ++sweep)
    for (int v : {vs, vt, vl, vr}) {
      const double gain = map.optimize_vertex(1, v);
      EXPECT_NEAR(energy - map.energy(), gain, 1e-12 * energy);
      energy = map.energy();
      moves += gain > 0;
      ASSERT_EQ(map.validate(), std::nullopt) << "after moving " << v;
    }
  std::printf("split next to the boundary: %zu moves, energy %.6f\n", moves, energy);
  EXPECT_GT(moves, 0u);
  // A split of a boundary vertex is still refused.
}

/// A side of a planar overlay as an embedded surface (z = 0) with one
/// split to replay: the metric its positions', vs at `at`.
MapSideInput embedded_side(const PlanarMesh& m, const VertexSplit& split, const Vec2& at) {
  MapSideInput in;
  in.base_faces = m.faces;
  for (std::size_t v = 0; v < m.p.size(); ++v) {
    in.base_vertices.push_back(int(v));
    in.positions.push_back({m.p[v].x(), m.p[v].y(), 0});
  }
  in.positions.push_back({at.x(), at.y(), 0});
  in.n_vertices = in.positions.size();
  in.splits.push_back(split);
  in.splits.back().position = in.positions.back();
  return in;
}

TEST(OpenMetaMesh, BoundaryVerticesSplitInPlaceAndSlideToTheIdentity) {
  // Two triangulations of the square, each in its own metric: the identity
  // is the map of efficiency 1. B's boundary vertex vt splits (a boundary
  // split, one wing -1) with vs 30 % of the way to a boundary neighbour:
  // placed in place next to vt, vs then slides towards where it belongs.
  // The kinds: the fan from vl to the boundary moves (vr = -1), the fan
  // from the boundary to vr (vl = -1), a fan inside (vs an inner vertex).
  // And a boundary split of a corner of B, which sits on a corner of A.
  enum Kind { ccw, cw, inside, at_corner };
  for (const Kind kind : {ccw, cw, inside, at_corner}) {
    const char* name = kind == ccw      ? "ccw"
                       : kind == cw     ? "cw"
                       : kind == inside ? "inside"
                                        : "corner";
    std::mt19937 rng(31 + kind);
    const PlanarMesh A = jittered_square(5, 0.3, rng), B = jittered_square(4, 0.3, rng);
    MetaMesh meta = planar_overlay({&A, &B});
    ASSERT_EQ(validate(meta), std::nullopt);
    const MetaIndex index = build_index(meta);
    const MetaSide& SB = meta.side[1];
    // A boundary vertex of B on a boundary edge of A, with two faces or
    // more, and no vertex of A between it and where vs goes.
    int vt = -1, wing = -1, other_wing = -1;
    Vec2 at;
    for (std::size_t v = 0; v < B.p.size() && vt < 0; ++v) {
      const bool on_corner = SB.location[v].vertex >= 0;
      if (!(kind == at_corner ? on_corner : SB.location[v].on_edge()) ||
          index[1].vertex_faces[v].size() < (kind == inside ? 3u : 2u))
        continue;
      // The fan counter-clockwise: the face whose (v, next) edge is on the
      // boundary first.
      std::vector<int> ring;
      const auto& around = index[1].vertex_faces[v];
      auto corner = [&](int f) {
        const Triangle& t = SB.faces[f];
        return t[0] == int(v) ? 0 : t[1] == int(v) ? 1 : 2;
      };
      int f = -1;
      for (int g : around) {
        bool preceded = false;
        for (int h : around)
          preceded |= SB.faces[h][(corner(h) + 2) % 3] == SB.faces[g][(corner(g) + 1) % 3];
        if (!preceded) f = g;
      }
      while (f >= 0) {
        ring.push_back(SB.faces[f][(corner(f) + 1) % 3]);
        const int last = SB.faces[f][(corner(f) + 2) % 3];
        f = -1;
        for (int h : around)
          if (SB.faces[h][(corner(h) + 1) % 3] == last) f = h;
        if (f < 0) ring.push_back(last);
      }
      const Vec2 far = kind == ccw || kind == at_corner ? B.p[ring.back()]
                       : kind == cw                     ? B.p[ring.front()]
                                                        : 0.5 * (B.p[ring[1]] + B.p[ring[2]]);
      const Vec2 target = B.p[v] + 0.3 * (far - B.p[v]);
      bool clear = true;
      for (const Vec2& q : A.p) {
        const Vec2 d = target - B.p[v];
        const double u = (q - B.p[v]).dot(d) / d.squaredNorm();
        if (std::abs(orient(B.p[v], target, q)) < 1e-14 && u > 1e-9 && u < 1 + 1e-9) clear = false;
      }
      if (!clear) continue;
      vt = int(v), at = target;
      wing = kind == ccw || kind == at_corner ? ring[ring.size() - 2] : ring[1];
      other_wing = ring[2];
    }
    ASSERT_GE(vt, 0);
    const int vs = int(B.p.size());
    const VertexSplit split = kind == ccw || kind == at_corner
                                  ? VertexSplit{vs, vt, wing, -1, Vec3::Zero()}
                              : kind == cw ? VertexSplit{vs, vt, -1, wing, Vec3::Zero()}
                                           : VertexSplit{vs, vt, wing, other_wing, Vec3::Zero()};
    meta.side[1].location.push_back({});
    const MapSideInput a = open_side(meta, 0);
    InterSurfaceMap map(meta, a, embedded_side(B, split, at), {0, 0});
    ASSERT_EQ(map.validate(), std::nullopt);
    ASSERT_TRUE(index_current(map));
    // The split made and undone leaves the map exactly as it was.
    const double energy_before = map.energy();
    const MetaMesh unsplit = map.meta();
    ASSERT_EQ(InterSurfaceMapTestAccess::split_and_undo(map, 1), -1);
    ASSERT_EQ(map.energy(), energy_before);
    for (int s = 0; s < 2; ++s) {
      const MetaSide &was = unsplit.side[s], &is = map.meta().side[s];
      EXPECT_EQ(is.faces, was.faces);
      EXPECT_EQ(is.edges, was.edges);
      ASSERT_EQ(is.location.size(), was.location.size());
      for (std::size_t v = 0; v < is.location.size(); ++v) {
        EXPECT_EQ(is.location[v].edge, was.location[v].edge);
        EXPECT_EQ(is.location[v].t, was.location[v].t);
        EXPECT_EQ(is.location[v].face, was.location[v].face);
        EXPECT_EQ(is.location[v].bary, was.location[v].bary);
      }
    }
    ASSERT_EQ(map.splits_applied(1), 0u);
    ASSERT_TRUE(index_current(map));
    ASSERT_EQ(map.split_next(1), vs) << name;
    ASSERT_EQ(map.validate(), std::nullopt);
    ASSERT_TRUE(index_current(map));
    ASSERT_EQ(validate(swapped(map.meta())), std::nullopt);
    // vs on the boundary, or inside a face of A for a fan inside.
    ASSERT_EQ(map.meta().side[1].location[vs].on_edge(), kind != inside);
    const double split_efficiency = measures(map.meta())->symmetric_efficiency;
    const Vec2 placed =
        point_of(A, map.meta().side[1].location[vs].face, map.meta().side[1].location[vs].bary);
    double energy = map.energy();
    for (int sweep = 0; sweep < 10; ++sweep)
      for (int s = 0; s < 2; ++s)
        for (std::size_t v = 0; v < map.meta().side[s].n_vertices(); ++v) {
          const double gain = map.optimize_vertex(s, int(v));
          EXPECT_NEAR(energy - map.energy(), gain, 1e-12 * energy);
          energy = map.energy();
        }
    ASSERT_EQ(map.validate(), std::nullopt);
    ASSERT_TRUE(index_current(map));
    const MetaLocation& loc = map.meta().side[1].location[vs];
    ASSERT_EQ(loc.on_edge(), kind != inside);
    const Vec2 slid = point_of(A, loc.face, loc.bary);
    const double end = measures(map.meta())->symmetric_efficiency;
    std::printf(
        "boundary split (%s): efficiency %.6f after the split in place, %.6f after 10 sweeps; vs "
        "%.2e -> %.2e from where it belongs\n",
        name, split_efficiency, end, (placed - at).norm(), (slid - at).norm());
    EXPECT_GT(end, split_efficiency);
    EXPECT_LT((slid - at).norm(), 0.2 * (placed - at).norm());
  }
  // A boundary vertex's split with both wings is still refused (the
  // trivial-map test above).
}

}  // namespace
}  // namespace ism
