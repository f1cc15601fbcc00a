// .glb outputs of the command-line tools: chosen by extension, plain or
// Draco-compressed (--glb-draco), torus grids written as triangles; every
// file passes the Khronos glTF validator.
#include "gltf_validator.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;
using ism::test::report_number;
using ism::test::run_tool;
using ism::test::scratch_dir;
using ism::test::slurp;

// The glTF binary header and whether the JSON chunk requires Draco.
void expect_glb(const fs::path& file, bool draco) {
  const std::string bytes = slurp(file);
  ASSERT_GE(bytes.size(), 20u) << file;
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(bytes[4], 2) << "glTF version 2";
  EXPECT_EQ(bytes.substr(16, 4), "JSON");
  EXPECT_EQ(bytes.find("KHR_draco_mesh_compression") != std::string::npos, draco) << file;
}

TEST(GlbOutput, GimAndTorusMeshesAsGltfPassTheValidator) {
  const fs::path dir = scratch_dir("glb");
  const fs::path sphere = dir / "sphere.obj", torus = dir / "torus.obj", image = dir / "sphere.exr",
                 remesh = dir / "sphere.glb", grid = dir / "grid.glb", report = dir / "grid.json";
  ASSERT_EQ(run_tool("ism-genmesh", "sphere --faces 500 -o " + sphere.string()).status, 0);
  ASSERT_EQ(run_tool("ism-genmesh", "torus --faces 600 -o " + torus.string()).status, 0);
  const auto gim =
      run_tool("gim-remesh", sphere.string() + " -o " + image.string() + " --size 17 --mesh " +
                                 remesh.string() + " --glb-draco --draco-bits 12 -q");
  ASSERT_EQ(gim.status, 0) << gim.err;
  expect_glb(remesh, true);
  // glTF has no quads: the grid's two triangles per quad, without --triangulate.
  const auto tr = run_tool("torus-remesh", torus.string() + " -o " + grid.string() +
                                               " --size 8x6 -q --report " + report.string());
  ASSERT_EQ(tr.status, 0) << tr.err;
  expect_glb(grid, false);
  const std::string json = slurp(report);
  EXPECT_NE(json.find("\"face_kind\": \"triangles\""), std::string::npos) << json;
  EXPECT_EQ(report_number(json, "faces", "remesh"), 96);

  ISM_REQUIRE_GLTF_VALIDATOR();
  ISM_EXPECT_VALID_GLTF(std::vector<fs::path>({remesh, grid}), dir / "validator.log");
}

TEST(GlbOutput, UnsupportedTorusFormatNamesGlb) {
  const fs::path dir = scratch_dir("glb");
  const auto r = run_tool("torus-remesh",
                          (dir / "missing.obj").string() + " -o " + (dir / "grid.xyz").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(".glb, triangles"), std::string::npos) << r.err;
}

}  // namespace
