// The path network on generated and shared surfaces: it must succeed, cut the
// surface into one disc per domain face with the domain's orientation, and
// refuse bad feature sets with a clear message.
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

namespace ism {
namespace {

TriangleMesh read_shared(const std::string& file) {
  return prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file)).mesh;
}

void expect_octahedral_network(const TriangleMesh& surface) {
  const PathNetwork net = trace_octahedral_network(surface);
  const TriangleMesh octahedron = domain::octahedron();
  EXPECT_EQ(validate_network(net, octahedron), std::nullopt);
  EXPECT_EQ(net.paths.size(), 12u);
  std::set<int> patches(net.face_patch.begin(), net.face_patch.end());
  EXPECT_EQ(patches.size(), 8u);
  EXPECT_EQ(net.surface.n_faces(), surface.n_faces() + 2 * net.steiner_vertices());
  // The input's vertices keep their indices and positions.
  for (std::size_t v = 0; v < surface.n_vertices(); ++v)
    ASSERT_EQ(net.surface.positions[v], surface.positions[v]);
}

TEST(OctahedralNetwork, GeneratedSpheresAndBlobs) {
  expect_octahedral_network(shapes::sphere(2000));
  expect_octahedral_network(shapes::ellipsoid(5000, {2.0, 1.0, 0.5}));
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE(seed);
    expect_octahedral_network(shapes::blob(4000, seed, 0.5));
  }
}

TEST(OctahedralNetwork, EveryClosedGenusZeroSharedModel) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const char* file :
       {"bunny_small.obj", "spot.obj", "gargoyle.obj", "max_planck.obj", "igea.obj",
        "nefertiti.obj", "fandisk.obj", "sphere.obj", "cube.obj", "bunny.obj", "dragon.obj"}) {
    SCOPED_TRACE(file);
    expect_octahedral_network(read_shared(file));
  }
}

// A grid and its transpose have opposite orientations: exactly one of them
// agrees with the surface's, and only that one can be traced in the harmonic
// map's homotopy class (torus.obj's file lists its grid mirrored).
TEST(TorusNetwork, SharedFeatureFilesGiveEighteenDiscs) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const char* name : {"torus", "teapot", "rocker_arm"}) {
    SCOPED_TRACE(name);
    const TriangleMesh surface = read_shared(std::string(name) + ".obj");
    const auto file = test::shared_models_dir() / (std::string(name) + "_features_3x3.txt");
    const auto features =
        io::resolve_features(io::read_feature_file(file), surface, 3, file.string());
    std::vector<int> transposed(9);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) transposed[3 * col + row] = features[3 * row + col];
    int traced = 0;
    for (const auto& grid : {features, transposed}) {
      try {
        const PathNetwork net = trace_torus_network(surface, grid);
        ++traced;
        EXPECT_EQ(validate_network(net, domain::torus_3x3()), std::nullopt);
        EXPECT_EQ(std::set<int>(net.face_patch.begin(), net.face_patch.end()).size(), 18u);
        EXPECT_EQ(net.features, grid);
      } catch (const PartitionError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot be realised"), std::string::npos) << e.what();
      }
    }
    EXPECT_EQ(traced, 1);
  }
}

std::string error_of(const TriangleMesh& surface, const TriangleMesh& domain, std::vector<int> f) {
  try {
    trace_path_network(surface, domain, f);
  } catch (const PartitionError& e) {
    return e.what();
  }
  return "";
}

TEST(PathNetwork, BadFeatureSetsAreRefusedClearly) {
  const TriangleMesh sphere = shapes::sphere(500);
  const TriangleMesh octahedron = domain::octahedron();
  EXPECT_EQ(error_of(sphere, octahedron, {0, 1, 2, 3, 4}),
            "5 features given, the domain has 6 vertices");
  EXPECT_EQ(error_of(sphere, octahedron, {0, 1, 2, 3, 4, 100000}),
            "feature 5: vertex index 100000 out of range (the surface has " +
                std::to_string(sphere.n_vertices()) + " vertices)");
  EXPECT_NE(error_of(sphere, octahedron, {0, 1, 2, 3, 4, 4}).find("same vertex 4"),
            std::string::npos);
  EXPECT_EQ(error_of(sphere, domain::torus_3x3(), {0, 1, 2, 3, 4, 5, 6, 7, 8}),
            "the surface has genus 0, the domain genus 1");
}

TEST(PathNetwork, FeatureFileErrorsNameTheLine) {
  const auto dir = test::binary_dir() / "test-scratch";
  std::filesystem::create_directories(dir);
  const auto file = dir / "bad_features.txt";
  std::ofstream(file) << "# comment\n1\n2 x\n";
  try {
    io::read_feature_file(file);
    FAIL() << "no error";
  } catch (const io::FileError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ":3: 'x' is not a number");
  }
}

}  // namespace
}  // namespace ism

namespace ism {
namespace {

// The swirl heuristics change the order of the paths, never the validity.
TEST(PathNetwork, SwirlHeuristicsGiveValidNetworks) {
  const TriangleMesh octahedron = domain::octahedron();
  for (const TriangleMesh& surface : {shapes::blob(3000, 5, 0.4), shapes::sphere(1280)}) {
    const std::vector<int> features = trace_octahedral_network(surface).features;
    const PathNetwork net =
        trace_path_network(surface, octahedron, features, {.swirl_heuristics = true});
    EXPECT_EQ(validate_network(net, octahedron), std::nullopt);
    EXPECT_EQ(net.features, features);
  }
}

}  // namespace
}  // namespace ism
