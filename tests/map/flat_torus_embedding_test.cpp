// Flat-torus layouts of the map: read from a valid map they describe it
// exactly (installing them gives the same map back), a distorted layout
// installs as a valid map, and a layout that would break the map or raise
// the energy above the bound is refused without a trace.
#include "domain/domain.hpp"
#include "map/map.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "shapes/shapes.hpp"

#include "torus_map_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace ism {
namespace {

using test::TorusMap;

// The vector of every half-edge (u, w) in the layout, from the face it bounds.
std::map<std::pair<int, int>, Vec2> edge_vectors(const SurfaceMap& map,
                                                 const FlatTorusLayout& layout) {
  std::map<std::pair<int, int>, Vec2> out;
  const auto& faces = map.faces();
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k)
      out[{faces[t][k], faces[t][(k + 1) % 3]}] =
          layout.corner(faces, int(t), (k + 1) % 3) - layout.corner(faces, int(t), k);
  return out;
}

// Distance between two points of the unit torus.
double torus_distance(const Vec2& a, const Vec2& b) {
  Vec2 d = a - b;
  d -= d.array().round().matrix();
  return d.norm();
}

// A diffeomorphism of R²/Z² (two periodic shears), applied to every vertex:
// the shifts stay valid because it commutes with whole periods.
FlatTorusLayout sheared(const FlatTorusLayout& layout, double amount) {
  FlatTorusLayout out = layout;
  for (Vec2& p : out.position) {
    p.x() += amount * std::sin(2 * M_PI * p.y());
    p.y() += amount * std::sin(2 * M_PI * p.x());
  }
  return out;
}

TEST(FlatTorusEmbedding, OnlyTheUnitSquareTorusHasSquareLayouts) {
  const TriangleMesh grid = domain::torus_3x3();
  const auto square = unit_square_layouts(DomainGeometry(grid, torus_3x3_lengths(grid)));
  ASSERT_TRUE(square.has_value());
  double area = 0;
  for (const auto& l : *square) area += 0.5 * orient(l[0], l[1], l[2]);
  EXPECT_NEAR(area, 1.0, 1e-12);
  // Equilateral faces on the same connectivity are no unit square, and the
  // octahedron has cones.
  EXPECT_FALSE(unit_square_layouts(DomainGeometry(grid, equilateral_lengths(grid))));
  const TriangleMesh octahedron = domain::octahedron();
  EXPECT_FALSE(unit_square_layouts(
      DomainGeometry(octahedron, octahedron_lengths(octahedron, DomainMetric::right_isosceles))));
}

TEST(FlatTorusEmbedding, LayoutDescribesTheMapAndInstallsItBack) {
  TorusMap s(shapes::torus(1500, 2, 1));
  SurfaceMap& map = s.map;
  refine(map);
  ASSERT_EQ(map.validate(), std::nullopt);
  ASSERT_TRUE(map.is_free_flat_torus());
  const std::optional<FlatTorusLayout> layout = map.flat_layout();
  ASSERT_TRUE(layout.has_value());

  // Every face counter-clockwise, covering the unit square once; its
  // energy is the map's.
  test::expect_layout_tiles_the_torus(map.faces(), *layout);
  const double energy = map.energy();
  EXPECT_NEAR(map.layout_energy(*layout), energy, 1e-9 * energy);

  // The lattice offsets are those of the M² edges: both faces of an edge
  // give the same vector (opposite signs), and the offsets are whole periods.
  const auto vectors = edge_vectors(map, *layout);
  for (const auto& [edge, d] : vectors) {
    const auto twin = vectors.find({edge.second, edge.first});
    ASSERT_NE(twin, vectors.end());
    EXPECT_LT((d + twin->second).norm(), 1e-9) << edge.first << "-" << edge.second;
    const Vec2 offset = d - (layout->position[edge.second] - layout->position[edge.first]);
    EXPECT_LT((offset - offset.array().round().matrix()).norm(), 1e-12);
  }
  // Some edges do cross the square's sides: the offsets carry information.
  std::size_t wrapped = 0;
  for (const auto& t : layout->shift)
    for (const auto& k : t) wrapped += k != t[0];
  EXPECT_GT(wrapped, 0u);

  // Installed, the layout gives the same map: valid, same energy, and read
  // back the same vertex points and edge vectors.
  ASSERT_TRUE(map.set_flat_layout(*layout));
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_NEAR(map.energy(), energy, 1e-7 * energy);
  const std::optional<FlatTorusLayout> again = map.flat_layout();
  ASSERT_TRUE(again.has_value());
  for (std::size_t v = 0; v < layout->position.size(); ++v) {
    if (!map.is_active(int(v))) continue;
    EXPECT_LT(torus_distance(again->position[v], layout->position[v]), 1e-8) << "vertex " << v;
  }
  const auto vectors_again = edge_vectors(map, *again);
  for (const auto& [edge, d] : vectors)
    EXPECT_LT((vectors_again.at(edge) - d).norm(), 1e-8) << edge.first << "-" << edge.second;
}

TEST(FlatTorusEmbedding, DistortedLayoutInstallsAndBadOnesAreRefused) {
  TorusMap s(shapes::torus(1500, 2, 1));
  SurfaceMap& map = s.map;
  refine(map);
  const FlatTorusLayout layout = *map.flat_layout();
  const double optimised = map.energy();

  // A smooth distortion of the torus: still a bijection, higher energy.
  const FlatTorusLayout distorted = sheared(layout, 0.15);
  ASSERT_TRUE(map.set_flat_layout(distorted));
  EXPECT_EQ(map.validate(), std::nullopt);
  const double distorted_energy = map.energy();
  EXPECT_NEAR(distorted_energy, map.layout_energy(distorted), 1e-7 * distorted_energy);
  EXPECT_GT(distorted_energy, 1.2 * optimised);

  // Above the energy bound: refused, the distorted map stays as it was.
  EXPECT_FALSE(map.set_flat_layout(layout, 0.5 * optimised));
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_EQ(map.energy(), distorted_energy);

  // A face turned over (two corners swapped): refused, nothing changed.
  FlatTorusLayout folded = layout;
  const auto& faces = map.faces();
  std::size_t t = 0;
  while (layout.shift[t][0] != layout.shift[t][1]) ++t;
  std::swap(folded.position[faces[t][0]], folded.position[faces[t][1]]);
  ASSERT_LT(orient(folded.corner(faces, int(t), 0), folded.corner(faces, int(t), 1),
                   folded.corner(faces, int(t), 2)),
            0);
  EXPECT_FALSE(map.set_flat_layout(folded));
  EXPECT_EQ(map.energy(), distorted_energy);

  // Below the bound: accepted.
  EXPECT_TRUE(map.set_flat_layout(layout, distorted_energy));
  EXPECT_NEAR(map.energy(), optimised, 1e-7 * optimised);
}

TEST(FlatTorusEmbedding, NoLayoutWithPinnedFeatures) {
  TorusMap s(shapes::torus(600, 2, 1), {.release_features = false});
  EXPECT_FALSE(s.map.is_free_flat_torus());
  EXPECT_FALSE(s.map.flat_layout().has_value());
}

}  // namespace
}  // namespace ism
