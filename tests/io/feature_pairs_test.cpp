// Pairs files and landmark lists: every accepted form, and one clear error
// naming the file and line for each kind of bad line.
#include "io/features.hpp"
#include "io/io.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>

namespace ism {
namespace {

namespace fs = std::filesystem;

fs::path write(const std::string& name, const std::string& text) {
  const fs::path dir = test::binary_dir() / "test-scratch" / "feature_pairs";
  fs::create_directories(dir);
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

// A row of n vertices at x = 0, 1, ..., n-1 (faces do not matter here).
TriangleMesh row(int n, double y = 0) {
  TriangleMesh m;
  for (int k = 0; k < n; ++k) m.positions.push_back({double(k), y, 0});
  return m;
}

std::string error_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const io::FileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(FeaturePairs, IndexAndPointLines) {
  const TriangleMesh a = row(10), b = row(20, 5);
  const auto path = write("mixed.pairs.txt",
                          "# comment\n\n3 7\r\n  0 19   # trailing comment\n"
                          "4.9 0.1 0  12.2 5 0\n");
  const io::FeaturePairs p = io::read_feature_pairs(path, a, b);
  ASSERT_EQ(p.pairs.size(), 3u);
  EXPECT_EQ(p.pairs[0], (std::array<int, 2>{3, 7}));
  EXPECT_EQ(p.pairs[1], (std::array<int, 2>{0, 19}));
  EXPECT_EQ(p.pairs[2], (std::array<int, 2>{5, 12}));  // snapped to the nearest vertices
  EXPECT_EQ(p.lines, (std::vector<int>{3, 4, 5}));
}

TEST(FeaturePairs, PointsSnapToTheNearestVertex) {
  // Points near and far from a sphere (some outside its bounding box): the
  // snapped vertex is as near as the nearest one found by brute force.
  const TriangleMesh a = shapes::sphere(3000), b = shapes::ellipsoid(2000, {3, 1, 0.5});
  std::ostringstream text;
  text.precision(17);
  std::vector<Vec3> pa, pb;
  std::uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53) * 8 - 4;
  };
  for (int k = 0; k < 300; ++k) {
    pa.push_back({uniform(), uniform(), uniform()});
    pb.push_back({uniform(), uniform(), uniform()});
    text << pa.back().transpose() << ' ' << pb.back().transpose() << '\n';
  }
  // Vertices may repeat among 300 random points: read them one line at a time.
  const std::string all = text.str();
  std::istringstream lines(all);
  std::string line;
  for (int k = 0; std::getline(lines, line); ++k) {
    const io::FeaturePairs p = io::read_feature_pairs(write("point.txt", line + "\n"), a, b);
    ASSERT_EQ(p.pairs.size(), 1u);
    for (int s = 0; s < 2; ++s) {
      const TriangleMesh& m = s ? b : a;
      const Vec3& q = s ? pb[k] : pa[k];
      double best = HUGE_VAL;
      for (const Vec3& v : m.positions) best = std::min(best, (v - q).squaredNorm());
      EXPECT_NEAR((m.positions[p.pairs[0][s]] - q).squaredNorm(), best, 1e-9) << "point " << k;
    }
  }
}

TEST(FeaturePairs, EmptyFileHasNoPairs) {
  const TriangleMesh a = row(3), b = row(3);
  EXPECT_TRUE(io::read_feature_pairs(write("empty.txt", "# nothing\n\n"), a, b).pairs.empty());
}

TEST(FeaturePairs, BadLinesNameFileAndLine) {
  const TriangleMesh a = row(10), b = row(20);
  const std::array<std::string, 2> names{"cat.obj", "horse.obj"};
  auto error = [&](const std::string& name, const std::string& text) {
    const auto path = write(name, text);
    return error_of([&] { io::read_feature_pairs(path, a, b, names); });
  };
  EXPECT_EQ(error("range.txt", "1 2\n10 3\n"),
            (test::binary_dir() / "test-scratch/feature_pairs/range.txt").string() +
                ":2: vertex index 10 of cat.obj out of range (cat.obj has 10 vertices)");
  EXPECT_NE(error("range_b.txt", "1 20\n").find(":1: vertex index 20 of horse.obj"),
            std::string::npos);
  EXPECT_NE(error("negative.txt", "-1 2\n").find(":1: vertex index -1 of cat.obj out of range"),
            std::string::npos);
  EXPECT_NE(error("huge.txt", "1e300 2\n").find(":1: vertex index 1e+300"), std::string::npos);
  EXPECT_NE(error("twice_a.txt", "1 2\n3 4\n1 5\n")
                .find(":3: vertex 1 of cat.obj is already paired on line 1"),
            std::string::npos);
  EXPECT_NE(error("twice_b.txt", "1 2\n3 2\n").find(":2: vertex 2 of horse.obj is already paired"),
            std::string::npos);
  EXPECT_NE(error("count.txt", "1 2 3\n").find(":1: expected 'IA IB'"), std::string::npos);
  EXPECT_NE(error("word.txt", "1 two\n").find(":1: 'two' is not a finite number"),
            std::string::npos);
  EXPECT_NE(error("nan.txt", "nan 2\n").find(":1: 'nan' is not a finite number"),
            std::string::npos);
  EXPECT_NE(error("inf.txt", "0 0 0 inf 0 0\n").find("is not a finite number"), std::string::npos);
  EXPECT_NE(error("fraction.txt", "1.5 2\n").find(":1: 1.5 is not a vertex index"),
            std::string::npos);
  EXPECT_NE(error("long.txt", "1 2\n" + std::string(5000, ' ') + "3 4\n")
                .find(":2: line longer than 4096 characters"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              io::read_feature_pairs("/nonexistent/p.txt", a, b);
            }).find("/nonexistent/p.txt: cannot open the file"),
            std::string::npos);
  // Every message is one line.
  EXPECT_EQ(error("twice_c.txt", "1 2\n1 3\n").find('\n'), std::string::npos);
}

TEST(LandmarkPairs, ByLineOrder) {
  const TriangleMesh a = row(10), b = row(20, 1);
  const auto la = write("a.landmarks", "# ids\n2\n5\n7\n");
  const auto lb = write("b.landmarks", "11\n0\n19\n");
  const io::FeaturePairs p = io::read_landmark_pairs(la, a, lb, b);
  EXPECT_EQ(p.pairs, (std::vector<std::array<int, 2>>{{2, 11}, {5, 0}, {7, 19}}));
  // Points, snapped.
  const auto pa = write("a.points", "2.2 0 0\n8.9 0 0\n");
  const auto pb = write("b.points", "3 1 0\n14.4 1 0\n");
  EXPECT_EQ(io::read_landmark_pairs(pa, a, pb, b).pairs,
            (std::vector<std::array<int, 2>>{{2, 3}, {9, 14}}));
}

TEST(LandmarkPairs, ByIdSkipsUnmatched) {
  const TriangleMesh a = row(10), b = row(20, 1);
  const auto la = write("a.vts", "1 2 0 0\n3 5 0 0\n4 9 0 0\n");
  const auto lb = write("b.vts", "4 15 1 0\n1 7 1 0\n2 0 1 0\n");
  const io::FeaturePairs p = io::read_landmark_pairs(la, a, lb, b);
  EXPECT_EQ(p.pairs, (std::vector<std::array<int, 2>>{{2, 7}, {9, 15}}));
  EXPECT_EQ(p.unmatched, 2u);  // id 3 on A, id 2 on B
}

TEST(LandmarkPairs, Refusals) {
  const TriangleMesh a = row(10), b = row(20, 1);
  auto error = [&](const std::string& ta, const std::string& tb) {
    const auto la = write("bad_a.txt", ta), lb = write("bad_b.txt", tb);
    return error_of([&] { io::read_landmark_pairs(la, a, lb, b); });
  };
  EXPECT_NE(error("1\n2\n", "3\n").find("need the same length"), std::string::npos);
  EXPECT_NE(error("1\n2 0 0\n", "3\n4\n").find(":2: 3 numbers where the lines before have 1"),
            std::string::npos);
  EXPECT_NE(error("1 0 0 0\n1 1 0 0\n", "1 0 1 0\n").find(":2: landmark id 1 already given"),
            std::string::npos);
  EXPECT_NE(error("1 0 0 0\n", "3\n").find("one list pairs by id"), std::string::npos);
  EXPECT_NE(error("11\n", "3\n").find(":1: vertex index 11 of A out of range"), std::string::npos);
  EXPECT_NE(error("1\n1\n", "3\n4\n").find("vertex 1 of A is already paired"), std::string::npos);
}

}  // namespace
}  // namespace ism
