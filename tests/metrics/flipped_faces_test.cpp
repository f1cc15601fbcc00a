// The fold test of remeshes (FoldTest, flipped_faces): which faces are
// folded, and how deeply.
#include "metrics/metrics.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace ism {
namespace {

// A flat 3 x 3 grid of unit squares in the plane z = 0, each split along
// its a-c diagonal; vertex (i, j) is j * 4 + i.
TriangleMesh flat_grid() {
  TriangleMesh mesh;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) mesh.positions.push_back(Vec3(i, j, 0));
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = j * 4 + i, b = a + 1, c = a + 5, d = a + 4;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  return mesh;
}

TEST(FoldTest, DepthIsPositiveExactlyOnFoldedFaces) {
  TriangleMesh mesh = flat_grid();
  FoldTest flat(mesh);
  std::vector<std::size_t> scratch;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    EXPECT_FALSE(flat.folded(f, scratch));
    EXPECT_EQ(flat.fold_depth(f, scratch), 0.0);
  }
  EXPECT_EQ(flipped_faces(mesh), 0u);

  // The centre vertex (1, 1) pulled past (2, 2): the faces around it turn
  // over (some of them), the others stay.
  mesh.positions[5] = Vec3(2.5, 2.5, 0);
  FoldTest test(mesh);
  std::size_t folded = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const double depth = test.fold_depth(f, scratch);
    EXPECT_EQ(depth > 0, test.folded(f, scratch)) << f;
    EXPECT_GE(depth, 0.0);
    EXPECT_LE(depth, 1.0 + 1e-15);
    folded += depth > 0;
  }
  EXPECT_GT(folded, 0u);
  EXPECT_EQ(flipped_faces(mesh), folded);
  // A flat face turned right over lies against its neighbours: depth 1.
  bool right_over = false;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    right_over |= test.fold_depth(f, scratch) > 1 - 1e-12;
  EXPECT_TRUE(right_over);

  // A zero-area face is never folded.
  TriangleMesh degenerate = flat_grid();
  degenerate.positions[5] = degenerate.positions[0];
  FoldTest zero(degenerate);
  for (std::size_t f = 0; f < degenerate.n_faces(); ++f)
    if (face_normal_scaled(degenerate, f).norm() == 0) EXPECT_EQ(zero.fold_depth(f, scratch), 0.0);
}

}  // namespace
}  // namespace ism
