// Path network and constrained progressive mesh together, as issue 3 asks:
// every closed genus-0 shared model with the octahedron and with decimated
// base meshes of about 20, 50 and 100 vertices; base = domain, exact replay.
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace ism {
namespace {

std::set<std::array<int, 3>> rotated_faces(const TriangleMesh& m) {
  std::set<std::array<int, 3>> out;
  for (Triangle t : m.triangles) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

// The base is the domain (vertex i <-> domain vertex i, same orientation),
// every patch a disc, and replaying all splits rebuilds the surface exactly.
void expect_network_and_pm(const TriangleMesh& surface, const TriangleMesh& domain,
                           const PathNetwork& network) {
  EXPECT_EQ(validate_network(network, domain), std::nullopt);
  const ProgressiveMesh pm = simplify_constrained(network, domain);
  EXPECT_EQ(rotated_faces(base_mesh(pm)), rotated_faces(domain));
  for (std::size_t i = 0; i < domain.n_vertices(); ++i)
    EXPECT_EQ(pm.base_vertices[i], network.features[i]);
  const TriangleMesh full = replay(pm);
  EXPECT_EQ(rotated_faces(full), rotated_faces(network.surface));
  EXPECT_EQ(full.positions, network.surface.positions);
  (void)surface;
}

TriangleMesh read_shared(const std::string& file) {
  return prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / file)).mesh;
}

const char* const kGenusZero[] = {
    "bunny_small.obj", "spot.obj",   "gargoyle.obj", "max_planck.obj", "igea.obj",  "nefertiti.obj",
    "fandisk.obj",     "sphere.obj", "cube.obj",     "bunny.obj",      "dragon.obj"};

TEST(NetworkAndPm, OctahedronOnGeneratedSurfaces) {
  const TriangleMesh octahedron = domain::octahedron();
  for (const TriangleMesh& s :
       {shapes::sphere(3000), shapes::blob(5000, 7, 0.5), shapes::ellipsoid(4000, {3, 1, 0.5})})
    expect_network_and_pm(s, octahedron, trace_octahedral_network(s));
}

TEST(NetworkAndPm, OctahedronOnEveryClosedGenusZeroModel) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh octahedron = domain::octahedron();
  for (const char* file : kGenusZero) {
    SCOPED_TRACE(file);
    const TriangleMesh s = read_shared(file);
    expect_network_and_pm(s, octahedron, trace_octahedral_network(s));
  }
}

TEST(NetworkAndPm, DecimatedBaseMeshes) {
  ISM_REQUIRE_SHARED_MODELS();
  for (const char* file : kGenusZero) {
    const TriangleMesh s = read_shared(file);
    for (std::size_t size : {20u, 50u, 100u}) {
      SCOPED_TRACE(std::string(file) + " base " + std::to_string(size));
      const ProgressiveMesh decimated = simplify_to(s, size);
      const TriangleMesh base = base_mesh(decimated);
      EXPECT_EQ(base.n_vertices(), size);
      expect_network_and_pm(s, base, trace_path_network(s, base, decimated.base_vertices));
    }
  }
}

}  // namespace
}  // namespace ism

namespace ism {
namespace {

TEST(NetworkAndPm, TorusOnGeneratedAndGenusOneModels) {
  const TriangleMesh torus = domain::torus_3x3();
  for (const TriangleMesh& s : {shapes::torus(4000, 2, 1), shapes::torus(6000, 3, 0.5)})
    expect_network_and_pm(s, torus, trace_torus_network(s));
  if (!test::have_shared_models()) GTEST_SKIP() << "shared models not found";
  for (const char* file :
       {"torus.obj", "teapot.obj", "rocker_arm.obj", "mug.obj", "cup.obj", "bob.obj", "knot.obj"}) {
    SCOPED_TRACE(file);
    const TriangleMesh s = read_shared(file);
    expect_network_and_pm(s, torus, trace_torus_network(s));
  }
  // The shared feature file of torus.obj, as given.
  const TriangleMesh s = read_shared("torus.obj");
  const auto file = test::shared_models_dir() / "torus_features_3x3.txt";
  const auto features = io::resolve_features(io::read_feature_file(file), s, 3, file.string());
  expect_network_and_pm(s, torus, trace_path_network(s, torus, features));
}

}  // namespace
}  // namespace ism
