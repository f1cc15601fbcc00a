// Torus grids: the documented layout (domain points of parameter points, with
// the wrap, sides and diagonals decided one way), closed genus-1 quad meshes
// with every vertex of valence 4, outward orientation, and the grid measures
// on the analytic torus.
#include "sample/torus_grid.hpp"

#include "closed_surface_checks.hpp"
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>

namespace ism {
namespace {

// Distance between two parameter points on the torus (modulo 1 in each).
double torus_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  Eigen::Vector2d d = a - b;
  for (int k = 0; k < 2; ++k) d[k] -= std::round(d[k]);
  return d.norm();
}

void expect_weights(const TorusPoint& p) {
  EXPECT_GE(p.face, 0);
  EXPECT_LT(p.face, 18);
  for (int k = 0; k < 3; ++k) EXPECT_GE(p.bary[k], 0.0) << p.bary.transpose();
  EXPECT_NEAR(p.bary.sum(), 1.0, 1e-15);
}

// The analytic torus with R = 2, r = 1: s around the z axis, t around the
// tube, so that d/ds x d/dt points outward.
Vec3 analytic_torus(const TorusPoint& p) {
  const Eigen::Vector2d st = torus_parameter_point(p);
  const double theta = 2 * M_PI * st.x(), phi = 2 * M_PI * st.y();
  const double rho = 2.0 + std::cos(phi);
  return {rho * std::cos(theta), rho * std::sin(theta), std::sin(phi)};
}

PolygonSoup soup_of(const TriangleMesh& mesh) {
  PolygonSoup soup{mesh.positions, {}};
  for (const Triangle& t : mesh.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  return soup;
}

TEST(TorusGrid, FaceCornersAreTheDomainVertices) {
  // Corner k of face f, pushed through torus_parameter_point, is the domain
  // vertex domain::torus_3x3() puts there (modulo the period).
  const TriangleMesh torus = domain::torus_3x3();
  for (int f = 0; f < 18; ++f)
    for (int k = 0; k < 3; ++k) {
      TorusPoint p{f, Eigen::Vector3d::Zero()};
      p.bary[k] = 1.0;
      const Vec3& vertex = torus.positions[torus.triangles[f][k]];
      EXPECT_LT(torus_distance(torus_parameter_point(p), vertex.head<2>()), 1e-15)
          << "face " << f << " corner " << k;
    }
}

TEST(TorusGrid, ParameterPointsRoundTripWithTheWrap) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const double s = unit(random), t = unit(random);
    const TorusPoint p = torus_point(s, t);
    expect_weights(p);
    EXPECT_LT((torus_parameter_point(p) - Eigen::Vector2d(s, t)).norm(), 1e-15);
    // Whole periods change nothing (s + 1 is not always exact: compare points).
    const TorusPoint q = torus_point(s + 3.0, t - 2.0);
    expect_weights(q);
    EXPECT_LT(torus_distance(torus_parameter_point(q), {s, t}), 1e-14);
  }
  // Exactly representable shifts give the identical point.
  const TorusPoint a = torus_point(0.25, 0.625), b = torus_point(-0.75, 2.625);
  EXPECT_EQ(a.face, b.face);
  EXPECT_EQ(a.bary, b.bary);
  // A tiny negative parameter wraps to the start, not past the end.
  const TorusPoint tiny = torus_point(-1e-300, -1e-300);
  expect_weights(tiny);
  EXPECT_LT(torus_distance(torus_parameter_point(tiny), {0, 0}), 1e-15);
  EXPECT_THROW(torus_point(NAN, 0.0), std::invalid_argument);
  EXPECT_THROW(torus_point(0.0, INFINITY), std::invalid_argument);
}

TEST(TorusGrid, SidesDiagonalsAndVerticesAreDecidedOneWay) {
  // Grid points are placed from integers: on a 9 x 9 grid every third point
  // is a domain vertex, held with weight exactly 1 by the face of the cell
  // above and to the right of it.
  const TriangleMesh torus = domain::torus_3x3();
  for (int row = 0; row < 9; row += 3)
    for (int col = 0; col < 9; col += 3) {
      const TorusPoint p = torus_grid_point(9, 9, col, row);
      const int cell = 3 * (row / 3) + col / 3;
      EXPECT_EQ(p.face, 2 * cell);
      EXPECT_EQ(p.bary, Eigen::Vector3d(1, 0, 0));
      EXPECT_EQ(torus.triangles[p.face][0], cell);
    }
  // A vertical cell side belongs to the cell on its right, a horizontal one
  // to the cell above; the diagonal to the even face.
  const TorusPoint side = torus_grid_point(9, 6, 3, 1);  // (1/3, 1/6)
  EXPECT_EQ(side.face, 3);                               // cell (0, 1), y > x = 0
  EXPECT_EQ(side.bary, Eigen::Vector3d(0.5, 0.0, 0.5));
  const TorusPoint bottom = torus_grid_point(6, 9, 1, 3);  // (1/6, 1/3)
  EXPECT_EQ(bottom.face, 6);                               // cell (1, 0), x > y = 0
  EXPECT_EQ(bottom.bary, Eigen::Vector3d(0.5, 0.5, 0.0));
  const TorusPoint diagonal = torus_grid_point(6, 6, 1, 1);  // (1/6, 1/6)
  EXPECT_EQ(diagonal.face, 0);
  EXPECT_EQ(diagonal.bary, Eigen::Vector3d(0.5, 0.0, 0.5));
  EXPECT_EQ(torus_point(0.5, 0.5).face, 8);  // cell (1, 1), on its diagonal
}

TEST(TorusGrid, GridPointsAreTheDocumentedParameterPoints) {
  for (const auto& [u, v] : {std::pair{3, 3}, {7, 5}, {12, 9}, {64, 48}})
    for (int row = 0; row < v; ++row)
      for (int col = 0; col < u; ++col) {
        const TorusPoint p = torus_grid_point(u, v, col, row);
        expect_weights(p);
        EXPECT_LT(
            (torus_parameter_point(p) - Eigen::Vector2d(double(col) / u, double(row) / v)).norm(),
            1e-15);
      }
}

TEST(TorusGrid, SizesAreChecked) {
  EXPECT_TRUE(is_torus_grid_size(3, 3));
  EXPECT_TRUE(is_torus_grid_size(8192, 8192));
  for (const auto& [u, v] : {std::pair{2, 5}, {5, 2}, {0, 0}, {-4, 4}, {8193, 8192}})
    EXPECT_FALSE(is_torus_grid_size(u, v)) << u << "x" << v;
  EXPECT_THROW(sample_torus_grid(2, 5, analytic_torus), std::invalid_argument);
  TorusGrid bad;
  bad.columns = 4;
  bad.rows = 4;
  bad.points.resize(15);
  EXPECT_THROW(torus_grid_mesh(bad), std::invalid_argument);
  EXPECT_THROW(torus_grid_efficiency(bad), std::invalid_argument);
}

TEST(TorusGrid, QuadMeshIsClosedGenusOneWithValenceFourEverywhere) {
  for (const auto& [u, v] : {std::pair{3, 3}, {4, 7}, {12, 5}, {32, 32}}) {
    SCOPED_TRACE(std::to_string(u) + "x" + std::to_string(v));
    const QuadMesh mesh = torus_grid_mesh(sample_torus_grid(u, v, analytic_torus));
    ASSERT_EQ(mesh.n_vertices(), std::size_t(u * v));
    ASSERT_EQ(mesh.n_faces(), std::size_t(u * v));
    // Every directed edge once and its reverse once: closed, consistently
    // oriented, manifold along edges.
    std::set<std::pair<int, int>> directed;
    std::map<int, std::set<int>> neighbours;
    for (const Quad& q : mesh.quads)
      for (int k = 0; k < 4; ++k) {
        const int a = q[k], b = q[(k + 1) % 4];
        EXPECT_TRUE(directed.emplace(a, b).second) << a << "->" << b;
        neighbours[a].insert(b);
        neighbours[b].insert(a);
      }
    for (const auto& [a, b] : directed) EXPECT_TRUE(directed.count({b, a})) << a << "-" << b;
    for (int x = 0; x < u * v; ++x) EXPECT_EQ(neighbours[x].size(), 4u) << "vertex " << x;
    const long edges = long(directed.size()) / 2;
    EXPECT_EQ(long(mesh.n_vertices()) - edges + long(mesh.n_faces()), 0);

    // Triangulated: 2UV triangles, V - E + F = 0, nothing to repair, outward.
    const TriangleMesh triangles = torus_grid_triangles(sample_torus_grid(u, v, analytic_torus));
    ASSERT_EQ(triangles.n_faces(), 2 * mesh.n_faces());
    const MeshCheck c = prepare_mesh(soup_of(triangles)).check;
    test::expect_clean_closed_surface(c, 1);
    EXPECT_GT(signed_volume(triangles), 0.0);
  }
}

TEST(TorusGrid, QuadsFollowTheLayout) {
  const int u = 5, v = 4;
  const TorusGrid grid = sample_torus_grid(u, v, analytic_torus);
  const QuadMesh mesh = torus_grid_mesh(grid);
  // Quad j*U + i: (j, i), (j, i+1), (j+1, i+1), (j+1, i), modulo the size.
  EXPECT_EQ(mesh.quads[0], (Quad{0, 1, 6, 5}));
  EXPECT_EQ(mesh.quads[4], (Quad{4, 0, 5, 9}));            // last column wraps
  EXPECT_EQ(mesh.quads[3 * u + 4], (Quad{19, 15, 0, 4}));  // last row and column
  for (std::size_t x = 0; x < grid.points.size(); ++x)
    EXPECT_EQ(std::memcmp(mesh.positions[x].data(), grid.points[x].data(), sizeof(Vec3)), 0);
  EXPECT_EQ(grid.index(2, 3), std::size_t(2 * u + 3));
}

TEST(TorusGrid, SamplingIsCompleteAndDoesNotDependOnTheSchedule) {
  std::atomic<int> calls{0};
  auto counted = [&](const TorusPoint& p) {
    ++calls;
    return analytic_torus(p);
  };
  const TorusGrid a = sample_torus_grid(40, 30, counted);
  EXPECT_EQ(calls.load(), 40 * 30);
  const TorusGrid b = sample_torus_grid(40, 30, analytic_torus);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(Vec3)), 0);
}

TEST(TorusGrid, AnalyticTorusMeasures) {
  // The angle parametrisation of R = 2, r = 1 has one-way efficiency 8/13 =
  // 0.615 (issue 7); the grid approaches it, without a flipped triangle.
  const TorusGrid grid = sample_torus_grid(256, 256, analytic_torus);
  EXPECT_NEAR(torus_grid_efficiency(grid), 8.0 / 13.0, 2e-3);
  EXPECT_EQ(torus_grid_flipped_triangles(grid), 0u);
  // Fold the sampling: one point of the outer equator moved past its next
  // neighbour along s (to column 6.6 of 16) reverses the cells between them,
  // whichever diagonal splits them.
  TorusGrid folded = sample_torus_grid(16, 16, analytic_torus);
  EXPECT_EQ(torus_grid_flipped_triangles(folded), 0u);
  const double theta = 2 * M_PI * 6.6 / 16;
  folded.at(0, 5) = Vec3(3 * std::cos(theta), 3 * std::sin(theta), 0);
  EXPECT_GT(torus_grid_flipped_triangles(folded), 0u);
}

// The 16 × 16 grid of the analytic torus with point (row 0, column 5)
// moved past its next neighbour along s (to column 6.6): folded.
TorusGrid folded_grid() {
  TorusGrid grid = sample_torus_grid(16, 16, analytic_torus);
  const double theta = 2 * M_PI * 6.6 / 16;
  grid.at(0, 5) = Vec3(3 * std::cos(theta), 3 * std::sin(theta), 0);
  return grid;
}

TEST(TorusGrid, UnfoldReSamplesFoldedPointsAtNearbyParameterPoints) {
  const TorusGrid clean = sample_torus_grid(16, 16, analytic_torus);
  TorusGrid grid = folded_grid();
  const std::size_t folds = torus_grid_flipped_triangles(grid);
  ASSERT_GT(folds, 0u);
  const UnfoldReport r = unfold_torus_grid(grid, analytic_torus);
  EXPECT_EQ(r.folds_before, folds);
  EXPECT_EQ(r.folds_after, 0u);
  EXPECT_EQ(torus_grid_flipped_triangles(grid), 0u);
  ASSERT_EQ(grid.points.size(), clean.points.size());
  // Every point that is not its grid point's sample is exactly the sample of
  // a point a quarter, half or three quarters of the way to a grid
  // neighbour (the wrong point among them: it had to move).
  std::size_t moved = 0;
  for (int row = 0; row < 16; ++row)
    for (int col = 0; col < 16; ++col) {
      const Vec3& p = grid.at(row, col);
      if (p == clean.at(row, col)) continue;
      ++moved;
      bool candidate = false;
      for (double step : {0.25, 0.5, 0.75})
        for (int dc = -1; dc <= 1; ++dc)
          for (int dr = -1; dr <= 1; ++dr)
            candidate |=
                (dc != 0 || dr != 0) && p == analytic_torus(torus_point((col + step * dc) / 16.0,
                                                                        (row + step * dr) / 16.0));
      EXPECT_TRUE(candidate) << row << " " << col;
    }
  EXPECT_GE(moved, 1u);
  EXPECT_EQ(r.moved_vertices, moved);
  EXPECT_NE(grid.at(0, 5), folded_grid().at(0, 5));

  // A grid without folds is left as it is.
  TorusGrid same = clean;
  const UnfoldReport none = unfold_torus_grid(same, analytic_torus);
  EXPECT_EQ(none.folds_before, 0u);
  EXPECT_EQ(none.folds_after, 0u);
  EXPECT_EQ(none.moved_vertices, 0u);
  EXPECT_EQ(
      std::memcmp(same.points.data(), clean.points.data(), clean.points.size() * sizeof(Vec3)), 0);

  // Where no nearby point can be sampled (the map throws), nothing moves.
  TorusGrid stuck = folded_grid();
  const UnfoldReport kept = unfold_torus_grid(
      stuck, [](const TorusPoint&) -> Vec3 { throw std::runtime_error("outside the map"); });
  EXPECT_EQ(kept.folds_after, folds);
  EXPECT_EQ(kept.moved_vertices, 0u);
}

// The torus R = 2, r = 1 sampled 6 × 4, column 1 shifted by one row along
// the tube: the quads are mirror-symmetric trapezoids (a tie, split along
// a–c) except beside column 1, where b–d is the shorter diagonal of some.
TorusGrid sheared_grid() {
  const int u = 6, v = 4;
  TorusGrid grid = sample_torus_grid(u, v, analytic_torus);
  for (int row = 0; row < v; ++row)
    grid.at(row, 1) = analytic_torus(torus_grid_point(u, v, 1, (row + v - 1) % v));
  return grid;
}

TEST(TorusGrid, QuadsAreSplitAlongTheirShorterDiagonal) {
  const TorusGrid grid = sheared_grid();
  const TriangleMesh triangles = torus_grid_triangles(grid);
  const QuadMesh quads = torus_grid_mesh(grid);
  ASSERT_EQ(triangles.n_faces(), 2 * quads.n_faces());
  int along_bd = 0;
  for (std::size_t q = 0; q < quads.n_faces(); ++q) {
    const Quad& c = quads.quads[q];
    const auto& p = grid.points;
    const bool ac = (p[c[2]] - p[c[0]]).squaredNorm() <= (p[c[3]] - p[c[1]]).squaredNorm();
    if (ac) {
      EXPECT_EQ(triangles.triangles[2 * q], (Triangle{c[0], c[1], c[2]})) << q;
      EXPECT_EQ(triangles.triangles[2 * q + 1], (Triangle{c[0], c[2], c[3]})) << q;
    } else {
      ++along_bd;
      EXPECT_EQ(triangles.triangles[2 * q], (Triangle{c[0], c[1], c[3]})) << q;
      EXPECT_EQ(triangles.triangles[2 * q + 1], (Triangle{c[1], c[2], c[3]})) << q;
    }
  }
  EXPECT_GT(along_bd, 0);
  EXPECT_LT(along_bd, grid.columns * grid.rows);
}

TEST(TorusGrid, EfficiencyIsTheOneWayStretchOfTheGridTriangles) {
  // The flat triangles have legs 1/U along s and 1/V along t, the wrap
  // included, split as the grid quads are; the measure is one_way_stretch
  // over them and their images. The sheared grid has both splits.
  const TorusGrid grid = sheared_grid();
  const int u = grid.columns, v = grid.rows;
  const TriangleMesh triangles = torus_grid_triangles(grid);
  const QuadMesh quads = torus_grid_mesh(grid);
  const double diagonal = std::hypot(1.0 / u, 1.0 / v);
  const TriangleLengths lower{1.0 / v, diagonal, 1.0 / u};  // (0,0), (1/U,0), (1/U,1/V)
  const TriangleLengths upper{1.0 / u, 1.0 / v, diagonal};  // (0,0), (1/U,1/V), (0,1/V)
  const TriangleLengths left{diagonal, 1.0 / v, 1.0 / u};   // (0,0), (1/U,0), (0,1/V)
  const TriangleLengths right{1.0 / u, diagonal, 1.0 / v};  // (1/U,0), (1/U,1/V), (0,1/V)
  std::vector<StretchPiece> pieces;
  for (std::size_t f = 0; f < triangles.n_faces(); ++f) {
    const Triangle& t = triangles.triangles[f];
    const Vec3 &a = triangles.positions[t[0]], &b = triangles.positions[t[1]],
               &c = triangles.positions[t[2]];
    const bool ac = triangles.triangles[f & ~std::size_t(1)][2] == quads.quads[f / 2][2];
    const TriangleLengths& flat = ac ? (f % 2 == 0 ? lower : upper) : (f % 2 == 0 ? left : right);
    pieces.push_back({flat, {(b - c).norm(), (c - a).norm(), (a - b).norm()}});
  }
  EXPECT_NEAR(torus_grid_efficiency(grid), one_way_stretch(pieces).efficiency, 1e-12);
  // Scaling the surface changes nothing.
  TorusGrid scaled = grid;
  for (Vec3& p : scaled.points) p *= 7.5;
  EXPECT_NEAR(torus_grid_efficiency(scaled), torus_grid_efficiency(grid), 1e-12);
}

TEST(TorusGrid, QuadFilesKeepTheQuads) {
  const QuadMesh mesh = torus_grid_mesh(sample_torus_grid(6, 5, analytic_torus));
  const auto dir = test::binary_dir() / "test-scratch";
  std::filesystem::create_directories(dir);
  for (const char* ext : {".obj", ".ply", ".off"}) {
    SCOPED_TRACE(ext);
    const auto file = dir / (std::string("torus_grid") + ext);
    io::write_quad_mesh(mesh, file);
    const PolygonSoup soup = io::read_polygon_soup(file);
    ASSERT_EQ(soup.positions.size(), mesh.n_vertices());
    ASSERT_EQ(soup.faces.size(), mesh.n_faces());
    for (std::size_t q = 0; q < mesh.n_faces(); ++q)
      EXPECT_EQ(soup.faces[q], std::vector<int>(mesh.quads[q].begin(), mesh.quads[q].end()));
    for (std::size_t x = 0; x < mesh.n_vertices(); ++x)
      EXPECT_LT((soup.positions[x] - mesh.positions[x]).norm(), 1e-6);
  }
  for (const char* ext : {".stl", ".drc"})
    EXPECT_THROW(io::write_quad_mesh(mesh, dir / (std::string("torus_grid") + ext)), io::FileError);
}

}  // namespace
}  // namespace ism
