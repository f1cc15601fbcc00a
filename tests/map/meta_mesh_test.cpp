// The symmetric meta-mesh: built from maps at every stage of a refinement,
// it validates from both sides, its measures are the map's, and validate()
// finds corruptions of either side.
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "octahedral_map_fixture.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"
#include "torus_map_fixture.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

namespace ism {
namespace {

using test::OctahedralMap;

/// The meta-mesh of `map` validates from both sides and measures as the map.
void expect_same_overlay(const SurfaceMap& map) {
  const auto meta = meta_mesh(map);
  ASSERT_TRUE(meta.has_value());
  ASSERT_EQ(validate(*meta), std::nullopt);
  const MetaMesh other = swapped(*meta);
  ASSERT_EQ(validate(other), std::nullopt);
  const MapMeasures expected = map.measures();
  const auto m = measures(*meta);
  const auto s = measures(other);
  ASSERT_TRUE(m && s);
  EXPECT_NEAR(m->symmetric_efficiency, expected.symmetric_efficiency, 1e-9);
  EXPECT_NEAR(m->forward_efficiency, expected.forward_efficiency, 1e-9);
  EXPECT_NEAR(m->backward_efficiency, expected.backward_efficiency, 1e-9);
  // Read the other way round, the one-way measures exchange.
  EXPECT_NEAR(s->symmetric_efficiency, expected.symmetric_efficiency, 1e-9);
  EXPECT_NEAR(s->forward_efficiency, expected.backward_efficiency, 1e-9);
  EXPECT_NEAR(s->backward_efficiency, expected.forward_efficiency, 1e-9);
}

TEST(MetaMesh, BaseMapIsTwoCopiesOfOneMesh) {
  OctahedralMap s(shapes::sphere(500));
  const auto meta = meta_mesh(s.map);
  ASSERT_TRUE(meta.has_value());
  EXPECT_EQ(validate(*meta), std::nullopt);
  const MetaMeshSize size = meta_mesh_size(*meta);
  EXPECT_EQ(size.crossings, 0u);
  EXPECT_EQ(size.vertices_inside, 0u);
  EXPECT_EQ(size.shared_vertices, 6u);
  EXPECT_EQ(size.pieces, 8u);
}

TEST(MetaMesh, BothSidesDescribeOneOverlayThroughoutARefinement) {
  OctahedralMap s(shapes::blob(1200, 4, 0.4));
  for (int v; (v = s.map.split_next()) >= 0;) {
    for (int w : s.map.neighbours(v)) s.map.optimize_vertex(w);
    s.map.optimize_vertex(v);
    if (s.map.splits_applied() % 25 == 0) {
      SCOPED_TRACE(s.map.splits_applied());
      expect_same_overlay(s.map);
    }
  }
  refine(s.map, {.max_final_sweeps = 2});
  expect_same_overlay(s.map);
  const MetaMeshSize size = meta_mesh_size(*meta_mesh(s.map));
  std::printf("blob: %zu crossings, %zu vertices inside a face, %zu shared, %zu pieces\n",
              size.crossings, size.vertices_inside, size.shared_vertices, size.pieces);
  // 600 surface vertices inside octahedron faces or on its 6 vertices.
  EXPECT_EQ(size.vertices_inside + 2 * size.shared_vertices, s.map.n_vertices() + 6);
  EXPECT_GT(size.crossings, 100u);
  EXPECT_GT(size.pieces, s.map.n_faces());
}

TEST(MetaMesh, FlatTorusDomainWithoutCones) {
  test::TorusMap t(shapes::torus(600));
  refine(t.map, {.max_final_sweeps = 2});
  ASSERT_EQ(t.map.validate(), std::nullopt);
  expect_same_overlay(t.map);
  // No vertex of the 3×3 torus is a cone: once released, they all lie inside faces.
  const MetaMeshSize size = meta_mesh_size(*meta_mesh(t.map));
  EXPECT_GT(size.crossings, 0u);
}

TEST(MetaMesh, ValidateFindsCorruptionOfEitherSide) {
  OctahedralMap s(shapes::blob(600, 4, 0.4));
  refine(s.map, {.max_final_sweeps = 1});
  const MetaMesh good = *meta_mesh(s.map);
  ASSERT_EQ(validate(good), std::nullopt);
  // An edge of each side with crossings, and an M² vertex inside a face.
  int e0 = 0, e1 = 0, inside = 0;
  while (good.side[0].crossings[e0].size() < 2) ++e0;
  while (good.side[1].crossings[e1].empty()) ++e1;
  while (good.side[1].location[inside].face < 0) ++inside;

  MetaMesh bad = good;  // a crossing moved along one edge only
  bad.side[1].crossings[e1][0].here *= 0.999;
  ASSERT_TRUE(validate(bad).has_value());
  std::printf("moved crossing: %s\n", validate(bad)->c_str());

  bad = good;  // two crossings of an M¹ edge exchanged
  std::swap(bad.side[0].crossings[e0][0], bad.side[0].crossings[e0][1]);
  EXPECT_TRUE(validate(bad).has_value());

  bad = good;  // a crossing dropped from both sides
  {
    const MetaCrossing c = bad.side[1].crossings[e1][0];
    bad.side[1].crossings[e1].erase(bad.side[1].crossings[e1].begin());
    auto& list = bad.side[0].crossings[c.edge];
    list.erase(std::find_if(list.begin(), list.end(),
                            [&](const MetaCrossing& x) { return x.edge == e1; }));
  }
  ASSERT_TRUE(validate(bad).has_value());
  std::printf("dropped crossing: %s\n", validate(bad)->c_str());

  bad = good;  // an M² vertex placed in another face
  bad.side[1].location[inside].face = (bad.side[1].location[inside].face + 1) % 8;
  ASSERT_TRUE(validate(bad).has_value());
  std::printf("vertex in another face: %s\n", validate(bad)->c_str());

  bad = good;  // an M² vertex moved to a corner of its face: its edges fold
  bad.side[1].location[inside].bary = {1 - 2e-9, 1e-9, 1e-9};
  ASSERT_TRUE(validate(bad).has_value());
  std::printf("vertex moved: %s\n", validate(bad)->c_str());
  EXPECT_FALSE(measures(bad).has_value());

  bad = swapped(good);  // the same corruption, the sides exchanged
  bad.side[0].location[inside].bary = {1 - 2e-9, 1e-9, 1e-9};
  EXPECT_TRUE(validate(bad).has_value());
}

TEST(MetaMesh, CoarseMapFileReadsBack) {
  // At the base level M² uses 6 of the surface's vertices: the others are
  // declared without a line of their own, so the vertex count may far
  // exceed what the file's bytes describe (the reader's bound allows it).
  OctahedralMap s(shapes::sphere(40000));
  const MetaMesh meta = *meta_mesh(s.map);
  const auto path = std::filesystem::temp_directory_path() / "ism_meta_mesh_coarse.meta";
  ASSERT_TRUE(write_meta_mesh(meta, path));
  EXPECT_GT(meta.side[1].n_vertices(), std::filesystem::file_size(path) / 4);
  const MetaMesh back = read_meta_mesh(path);
  EXPECT_EQ(back.side[1].n_vertices(), meta.side[1].n_vertices());
  EXPECT_EQ(validate(back), std::nullopt);
}

TEST(MetaMesh, FileRoundTripIsExact) {
  OctahedralMap s(shapes::sphere(400));
  refine(s.map, {.max_final_sweeps = 1});
  const MetaMesh meta = *meta_mesh(s.map);
  const auto path = std::filesystem::temp_directory_path() / "ism_meta_mesh_test.meta";
  ASSERT_TRUE(write_meta_mesh(meta, path));
  {
    std::ifstream in(path);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "ism-meta-mesh 1");
    std::map<std::string, std::size_t> count;
    for (std::string line; std::getline(in, line);) ++count[line.substr(0, line.find(' '))];
    const MetaMeshSize size = meta_mesh_size(meta);
    EXPECT_EQ(count["mesh"], 2u);
    EXPECT_EQ(count["f"], 8 + s.map.n_faces());
    EXPECT_EQ(count["x"], size.crossings);
    EXPECT_EQ(count["in"], size.vertices_inside);
    EXPECT_EQ(count["on"], size.shared_vertices);
  }
  const MetaMesh back = read_meta_mesh(path);
  EXPECT_EQ(validate(back), std::nullopt);
  for (int m = 0; m < 2; ++m) {
    const MetaSide &a = meta.side[m], &b = back.side[m];
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.lengths, b.lengths);
    EXPECT_EQ(a.edges, b.edges);
    ASSERT_EQ(a.n_vertices(), b.n_vertices());
    for (std::size_t v = 0; v < a.n_vertices(); ++v) {
      EXPECT_EQ(a.location[v].vertex, b.location[v].vertex);
      EXPECT_EQ(a.location[v].face, b.location[v].face);
      EXPECT_EQ(a.location[v].bary, b.location[v].bary);
    }
    for (std::size_t e = 0; e < a.edges.size(); ++e) {
      ASSERT_EQ(a.crossings[e].size(), b.crossings[e].size());
      for (std::size_t i = 0; i < a.crossings[e].size(); ++i) {
        EXPECT_EQ(a.crossings[e][i].edge, b.crossings[e][i].edge);
        EXPECT_EQ(a.crossings[e][i].here, b.crossings[e][i].here);
        EXPECT_EQ(a.crossings[e][i].there, b.crossings[e][i].there);
      }
    }
  }
  EXPECT_EQ(measures(back)->symmetric_efficiency, measures(meta)->symmetric_efficiency);

  // A damaged file: one line naming the file and the line.
  {
    std::ofstream out(path, std::ios::app);
    out << "x 0 1 2\n";
  }
  try {
    read_meta_mesh(path);
    ADD_FAILURE() << "read a damaged file";
  } catch (const io::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("bad crossing"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(MetaMeshSampler, IsTheMapAffineOnEachFaceBothWays) {
  OctahedralMap s(shapes::blob(2000, 7, 0.4));
  refine(s.map, {.max_final_sweeps = 2});
  const MetaMesh meta = *meta_mesh(s.map);
  const MetaMeshSampler sampler(meta);
  const auto& octahedron = s.octahedron;
  auto domain = [&](int face, const Eigen::Vector3d& b) {
    const Triangle& t = octahedron.triangles[face];
    const auto& p = octahedron.positions;
    return Vec3(b[0] * p[t[0]] + b[1] * p[t[1]] + b[2] * p[t[2]]);
  };
  // The checker, from SurfaceMap's own records: an M² face whose corners
  // all lie in one M¹ face f is mapped affinely into f, its corner k to
  // the corner's location. Column k: corner k's barycentric coordinates in f.
  auto within_one_face = [&](int t, Eigen::Matrix3d& corners) {
    int f = -1;
    for (int k = 0; k < 3; ++k) {
      const DomainLocation& loc = s.map.location(s.map.faces()[t][k]);
      if (loc.face < 0 || (f >= 0 && loc.face != f)) return -1;
      f = loc.face;
      corners.col(k) = loc.bary;
    }
    return f;
  };
  std::uint64_t state = 99;
  auto uniform = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  double worst_forward = 0, worst_back = 0, worst_round_trip = 0;
  std::size_t checked_forward = 0, checked_back = 0;
  for (int i = 0; i < 20000; ++i) {
    double a = uniform(), b = uniform();
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Eigen::Vector3d bary(1 - a - b, a, b);
    // M¹ -> M², and back.
    const int f = i % 8;
    const auto got = sampler.map_point(0, f, bary);
    ASSERT_TRUE(got);
    Eigen::Matrix3d corners;
    if (within_one_face(got->face, corners) == f) {
      ++checked_forward;
      worst_forward = std::max(worst_forward, (corners * got->bary - bary).norm());
    }
    const auto back = sampler.map_point(1, got->face, got->bary);
    ASSERT_TRUE(back);
    worst_round_trip =
        std::max(worst_round_trip, (domain(back->face, back->bary) - domain(f, bary)).norm());
    // M² -> M¹.
    const int t = int((i * 7919) % s.map.n_faces());
    const auto image = sampler.map_point(1, t, bary);
    ASSERT_TRUE(image);
    const int g = within_one_face(t, corners);
    if (g >= 0) {
      ++checked_back;
      worst_back = std::max(worst_back,
                            (domain(image->face, image->bary) - domain(g, corners * bary)).norm());
    }
  }
  std::printf(
      "largest differences: M¹ -> M² %.3g (%zu points), M² -> M¹ %.3g (%zu points), "
      "round trip %.3g\n",
      worst_forward, checked_forward, worst_back, checked_back, worst_round_trip);
  EXPECT_GT(checked_forward, 10000u);
  EXPECT_GT(checked_back, 10000u);
  EXPECT_LT(worst_forward, 1e-9);
  EXPECT_LT(worst_back, 1e-9);
  EXPECT_LT(worst_round_trip, 1e-9);
  // Outside a face, or no such face: nothing.
  EXPECT_FALSE(sampler.map_point(0, 0, Eigen::Vector3d(1.5, -0.25, -0.25)));
  EXPECT_FALSE(sampler.map_point(0, 8, Eigen::Vector3d(1, 0, 0)));
}

}  // namespace
}  // namespace ism
