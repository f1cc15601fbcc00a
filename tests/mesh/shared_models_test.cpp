// Reader and checks on every file of ../shared/models: the genus and boundary
// loops must match the table of its README; and every file of
// ../shared/models/bad gets its defect or its repair, never a crash.
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <set>

namespace ism {
namespace {

struct Expected {
  const char* file;
  std::size_t vertices, faces;
  int genus;
  std::size_t boundary_loops;
};

// From ../shared/models/README.md.
const Expected kModels[] = {
    {"bunny.obj", 34817, 69630, 0, 0},      {"bunny_small.obj", 3301, 6598, 0, 0},
    {"spot.obj", 11533, 23062, 0, 0},       {"gargoyle.obj", 10002, 20000, 0, 0},
    {"dragon.obj", 32175, 64346, 0, 0},     {"max_planck.obj", 10000, 19996, 0, 0},
    {"igea.obj", 25001, 49998, 0, 0},       {"nefertiti.obj", 20001, 39998, 0, 0},
    {"fandisk.obj", 6475, 12946, 0, 0},     {"sphere.obj", 2562, 5120, 0, 0},
    {"cube.obj", 1538, 3072, 0, 0},         {"bunny_open.obj", 34834, 69451, 0, 5},
    {"face.obj", 25905, 51712, 0, 1},       {"camelhead.obj", 11381, 22704, 0, 1},
    {"venus.obj", 628, 1199, 0, 1},         {"venus_loop2.obj", 9703, 19184, 0, 1},
    {"head_3holes.obj", 1487, 2918, 0, 3},  {"mannequin_devil.obj", 12977, 25888, 0, 1},
    {"rocker_arm.obj", 10044, 20088, 1, 0}, {"torus.obj", 4608, 9216, 1, 0},
    {"teapot.obj", 14983, 29966, 1, 0},     {"mug.obj", 5084, 10168, 1, 0},
    {"cup.obj", 2000, 4000, 1, 0},          {"bob.obj", 5344, 10688, 1, 0},
    {"knot.obj", 3200, 6400, 1, 0},         {"eight.obj", 315, 634, 2, 0},
    {"eight_loop2.obj", 5070, 10144, 2, 0}, {"feline.obj", 20531, 41066, 2, 0},
    {"double_torus.obj", 2521, 5046, 2, 0}, {"hanger.obj", 4026, 8056, 2, 0},
    {"3holes.obj", 3596, 7200, 3, 0},       {"mechpart.obj", 7612, 15232, 3, 0},
    {"fertility.obj", 4494, 9000, 4, 0},
};

PreparedMesh read_shared(const std::string& relative) {
  return prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / relative));
}

TEST(SharedModels, EveryModelHasTheDocumentedTopology) {
  ISM_REQUIRE_SHARED_MODELS();
  std::set<std::string> listed;
  for (const Expected& e : kModels) {
    SCOPED_TRACE(e.file);
    listed.insert(e.file);
    const PreparedMesh p = read_shared(e.file);
    const MeshCheck& c = p.check;
    EXPECT_TRUE(c.valid_surface());
    EXPECT_EQ(c.vertices, e.vertices);
    EXPECT_EQ(c.faces, e.faces);
    EXPECT_EQ(c.genus, e.genus);
    EXPECT_EQ(c.boundary_loops, e.boundary_loops);
    EXPECT_EQ(c.components, 1u);
    EXPECT_TRUE(c.repairs().empty()) << c.repairs().front();
    if (c.closed()) {
      EXPECT_GT(signed_volume(p.mesh), 0.0);
    }
  }
  // A model added to ../shared must be added to the table above.
  for (const auto& entry : std::filesystem::directory_iterator(test::shared_models_dir()))
    if (entry.path().extension() == ".obj") {
      EXPECT_TRUE(listed.count(entry.path().filename().string())) << entry.path();
    }
}

TEST(SharedModels, BadModelsAreRejectedWithTheirDefect) {
  ISM_REQUIRE_SHARED_MODELS();
  struct Case {
    const char* file;
    const char* defect;  // a word the first defect must contain
  };
  const Case rejected[] = {
      {"cow_pinched.obj", "non-manifold vertex"},
      {"dragon_vrip_res4.obj", "non-manifold edge"},
      {"trex_skull_scan.obj", "non-manifold vertices"},
      {"two_tori_linked.obj", "2 connected components"},
      {"mobius.obj", "non-orientable"},
      {"teapot_patch_soup.obj", ""},
  };
  for (const Case& bad : rejected) {
    SCOPED_TRACE(bad.file);
    const MeshCheck c = read_shared(std::string("bad/") + bad.file).check;
    EXPECT_FALSE(c.valid_surface());
    const auto unmet = unmet_requirement(c, {.tool = "ism-info"});
    ASSERT_TRUE(unmet);
    EXPECT_NE(unmet->find(bad.defect), std::string::npos) << *unmet;
  }
}

TEST(SharedModels, RepairableModelsAreRepaired) {
  ISM_REQUIRE_SHARED_MODELS();
  {
    const PreparedMesh p = read_shared("bad/bunny_inward.obj");
    EXPECT_TRUE(p.check.valid_surface());
    EXPECT_TRUE(p.check.flipped_inward);
    EXPECT_GT(signed_volume(p.mesh), 0.0);
  }
  {
    const PreparedMesh p = read_shared("bad/blobby_shuffled.obj");
    EXPECT_TRUE(p.check.valid_surface());
    EXPECT_GT(p.check.reoriented_faces, 0u);
    EXPECT_EQ(p.check.genus, 0);
    EXPECT_GT(signed_volume(p.mesh), 0.0);
    // Checking the repaired mesh again finds nothing left to repair.
    PolygonSoup repaired{p.mesh.positions, {}};
    for (const Triangle& t : p.mesh.triangles) repaired.faces.push_back({t[0], t[1], t[2]});
    EXPECT_TRUE(prepare_mesh(repaired).check.repairs().empty());
  }
  {
    const MeshCheck c = read_shared("bad/torus_quads.obj").check;
    EXPECT_TRUE(c.valid_surface());
    EXPECT_EQ(c.triangulated_polygons, 25u);
    EXPECT_EQ(c.faces, 50u);
    EXPECT_EQ(c.genus, 1);
  }
  {
    const MeshCheck c = read_shared("bad/sphere_uv_unwelded.obj").check;
    EXPECT_TRUE(c.valid_surface());
    // The seam differs by rounding (1e-17) only: welded shut, poles joined.
    EXPECT_EQ(c.welded_vertices, 79u);
    EXPECT_EQ(c.dropped_faces, 64u);
    EXPECT_TRUE(c.closed());
    EXPECT_EQ(c.genus, 0);
  }
}

}  // namespace
}  // namespace ism
