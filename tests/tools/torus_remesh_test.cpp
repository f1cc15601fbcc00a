// torus-remesh as a user runs it: closed genus-1 grids in which every vertex
// has valence 4, read back from the written files; the report's measures;
// the periodic image; and clean refusals of unsuitable inputs.
#include "closed_surface_checks.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "sample/geometry_image_file.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>

namespace {

namespace fs = std::filesystem;
using ism::test::report_number;
using ism::test::run_tool;
using ism::test::scratch_dir;
using ism::test::slurp;

// The written grid: U·V faces (quads, or two triangles each), U·V
// vertices of valence 4, a closed genus-1 surface with nothing to repair,
// oriented outward.
void expect_valence_four_torus(const fs::path& file, int columns, int rows, bool quads = true) {
  const ism::PolygonSoup soup = ism::io::read_polygon_soup(file);
  const std::size_t cells = std::size_t(columns) * rows;
  ASSERT_EQ(soup.positions.size(), cells);
  ASSERT_EQ(soup.faces.size(), quads ? cells : 2 * cells);
  std::map<int, std::set<int>> neighbours;
  ism::PolygonSoup triangles{soup.positions, {}};
  for (const auto& f : soup.faces) {
    ASSERT_EQ(f.size(), quads ? 4u : 3u);
    for (std::size_t k = 0; k < f.size(); ++k) {
      neighbours[f[k]].insert(f[(k + 1) % f.size()]);
      neighbours[f[(k + 1) % f.size()]].insert(f[k]);
    }
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      triangles.faces.push_back({f[0], f[k], f[k + 1]});
  }
  // In the triangulated file the diagonals add two neighbours: the grid
  // edges alone are those of the quads, so count valence on quads only.
  if (quads) {
    for (std::size_t v = 0; v < cells; ++v)
      EXPECT_EQ(neighbours[int(v)].size(), 4u) << "vertex " << v;
  }
  const ism::MeshCheck c = ism::prepare_mesh(triangles).check;
  ism::test::expect_clean_closed_surface(c, 1);
}

TEST(TorusRemesh, GeneratedTorusGivesAValenceFourGridAndAReport) {
  const fs::path dir = scratch_dir("torus");
  const fs::path torus = dir / "torus.obj", out = dir / "torus_grid.obj",
                 image = dir / "torus_grid.exr", report = dir / "torus.json",
                 patches = dir / "torus_patches.ply", drc = dir / "torus_grid.drc",
                 triangles = dir / "torus_grid_tri.ply";
  ASSERT_EQ(run_tool("ism-genmesh", "torus --faces 4000 --R 2 --r 1 -o " + torus.string()).status,
            0);
  fs::remove(out);
  const auto r =
      run_tool("torus-remesh", torus.string() + " -o " + out.string() + " --size 48x32 --image " +
                                   image.string() + " --dump-patches " + patches.string() +
                                   " --report " + report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_TRUE(fs::exists(patches));
  expect_valence_four_torus(out, 48, 32);

  const std::string json = slurp(report);
  for (const char* key :
       {"\"partition\"", "\"map\"", "\"valid\": true", "\"symmetric_efficiency\"",
        "\"efficiency_domain_to_surface\"", "\"grid\"", "\"columns\": 48", "\"rows\": 32",
        "\"efficiency\"", "\"flipped_triangles\": 0", "\"remesh\"", "\"vertices\": 1536",
        "\"faces\": 1536", "\"psnr_db\"", "\"peak_memory_mb\"", "\"seconds\"",
        "\"source\": \"automatic\"", "\"global_reembeddings\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  EXPECT_GT(report_number(json, "global_reembeddings_applied"), 0);
  // The plain angle parametrisation of the unit square scores 0.615 (8/13).
  const double efficiency = report_number(json, "efficiency_domain_to_surface", "map");
  std::printf("generated torus R=2 r=1: one-way efficiency %.4f, grid %.4f, PSNR %.1f dB\n",
              efficiency, report_number(json, "efficiency", "grid"),
              report_number(json, "psnr_db"));
  EXPECT_GE(efficiency, 0.615);

  // The image holds the same points: V rows of U pixels, vertex order.
  const ism::TorusGrid grid = ism::read_torus_image(image);
  EXPECT_EQ(grid.columns, 48);
  EXPECT_EQ(grid.rows, 32);
  const ism::PolygonSoup mesh = ism::io::read_polygon_soup(out);
  ASSERT_EQ(grid.points.size(), mesh.positions.size());
  for (std::size_t v = 0; v < grid.points.size(); ++v)
    EXPECT_LT((grid.points[v] - mesh.positions[v]).norm(), 1e-5) << v;

  // Triangulated, as PLY and as Draco.
  const auto t = run_tool(
      "torus-remesh", torus.string() + " -o " + triangles.string() + " --size 12 --triangulate -q");
  ASSERT_EQ(t.status, 0) << t.err;
  expect_valence_four_torus(triangles, 12, 12, false);
  const auto d = run_tool("torus-remesh",
                          torus.string() + " -o " + drc.string() + " --size 16 --triangulate -q");
  ASSERT_EQ(d.status, 0) << d.err;
  EXPECT_GT(fs::file_size(drc), 100u);

  // Without the global re-embeddings: a valid grid, none in the report.
  const auto n = run_tool("torus-remesh", torus.string() + " -o " + triangles.string() +
                                              " --size 12 --no-global-reembedding --report " +
                                              report.string() + " -q");
  ASSERT_EQ(n.status, 0) << n.err;
  EXPECT_EQ(slurp(report).find("global_reembeddings"), std::string::npos);
}

// The symmetric core (--core symmetric): the coarse map taken over at 3000
// surface vertices, refined on, re-embedded on the flat torus before the
// final sweeps; a valence-4 grid, the map valid from both sides, as good as
// the default core's.
TEST(TorusRemesh, SymmetricCoreOnAGeneratedTorus) {
  const fs::path dir = scratch_dir("torus_symmetric");
  const fs::path torus = dir / "torus.obj", out = dir / "grid.obj", report = dir / "grid.json";
  ASSERT_EQ(run_tool("ism-genmesh", "torus --faces 8000 --R 2 --r 1 -o " + torus.string()).status,
            0);
  const auto r = run_tool("torus-remesh", torus.string() + " -o " + out.string() +
                                              " --size 48x32 --core symmetric --report " +
                                              report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_valence_four_torus(out, 48, 32);
  const auto json = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(json["map_core"], "symmetric");
  EXPECT_EQ(json["map"]["core"], "symmetric");
  EXPECT_TRUE(json["meta_mesh"]["valid"].get<bool>());
  // Refined on the symmetric core: its splits optimised, then its final sweeps.
  EXPECT_GT(json["map"]["optimizations"].get<double>(), json["map"]["faces"].get<double>() / 2);
  EXPECT_EQ(json["map"]["global_steps"], 1);
  EXPECT_EQ(json["map"]["global_steps_applied"], 1);
  EXPECT_EQ(json["grid"]["flipped_triangles"], 0);
  const double efficiency = json["map"]["efficiency_domain_to_surface"].get<double>();
  std::printf("symmetric core, generated torus 8000 faces: one-way efficiency %.4f, PSNR %.2f dB\n",
              efficiency, json["distance"]["psnr_db"].get<double>());
  // Measured 0.6375 (the default core 0.637); the angle parametrisation 0.615.
  EXPECT_GE(efficiency, 0.63);
}

// A closed genus-1 shared model with automatic features or the given ones,
// at 128x128; `flip_free`: no flipped grid triangle expected; the one-way
// efficiency at least `min_efficiency`.
void remesh_shared_model(const std::string& model, bool given_features, bool flip_free,
                         double min_efficiency = 0, const std::string& extra = "") {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path models = ism::test::shared_models_dir();
  const std::string tag =
      model + (given_features ? "_given" : "_auto") + (extra.empty() ? "" : "_x");
  const fs::path out = scratch_dir("torus") / (tag + ".obj"),
                 report = scratch_dir("torus") / (tag + ".json");
  std::string args = (models / (model + ".obj")).string() + " -o " + out.string() +
                     " --size 128 --report " + report.string() + " -q " + extra;
  if (given_features) args += " --features " + (models / (model + "_features_3x3.txt")).string();
  const auto r = run_tool("torus-remesh", args);
  ASSERT_EQ(r.status, 0) << r.err;
  expect_valence_four_torus(out, 128, 128);
  const std::string json = slurp(report);
  EXPECT_NE(json.find("\"valid\": true"), std::string::npos);
  const double flipped = report_number(json, "flipped_triangles");
  std::printf("%s: one-way efficiency %.3f, grid efficiency %.3f, %g flipped triangles\n",
              tag.c_str(), report_number(json, "efficiency_domain_to_surface", "map"),
              report_number(json, "efficiency", "grid"), flipped);
  if (flip_free) {
    EXPECT_EQ(flipped, 0);
  }
  // Re-sampling folded triangles' points nearby never adds a fold.
  EXPECT_LE(flipped, report_number(json, "flipped_triangles_at_grid_points", "grid"));
  EXPECT_GE(report_number(json, "efficiency_domain_to_surface", "map"), min_efficiency);
}

// One test per run, so that ctest spreads them over the cores.
TEST(TorusRemesh, SharedTorusAutomatic) {
  remesh_shared_model("torus", false, true);
}
TEST(TorusRemesh, SharedRockerArmAutomatic) {
  remesh_shared_model("rocker_arm", false, true, 0.60);  // paper 0.582
}
TEST(TorusRemesh, SharedBobAutomatic) {
  remesh_shared_model("bob", false, true);
}
TEST(TorusRemesh, SharedKnotAutomatic) {
  remesh_shared_model("knot", false, true);
}
TEST(TorusRemesh, SharedTorusGivenFeatures) {
  remesh_shared_model("torus", true, true);
}
TEST(TorusRemesh, SharedRockerArmGivenFeatures) {
  remesh_shared_model("rocker_arm", true, true, 0.60);
}
// teapot and mug fold grid triangles at their grid points where skinny
// images of the grid cells cross the sharp bends at the handles' roots;
// re-sampled nearby, their best maps are fold-free (teapot 9 -> 0, mug
// 10 -> 0) and kept over the anisotropy fallback variants (which had cost
// teapot 0.458 -> 0.444, mug 0.517 -> 0.489). The efficiencies need the
// global re-embeddings: vertex-at-a-time alone gave teapot 0.353, mug
// 0.142, cup 0.407.
TEST(TorusRemesh, SharedTeapotAutomatic) {
  remesh_shared_model("teapot", false, true, 0.455);  // measured 0.458; paper 0.458
}
TEST(TorusRemesh, SharedMugAutomatic) {
  remesh_shared_model("mug", false, true, 0.51);  // measured 0.517
}
TEST(TorusRemesh, SharedCupAutomatic) {
  remesh_shared_model("cup", false, true, 0.53);  // measured 0.538
}
TEST(TorusRemesh, SharedTeapotGivenFeatures) {
  remesh_shared_model("teapot", true, true, 0.455);  // measured 0.457
}
// --grid-points: every vertex at its grid point, so the mug's map keeps its
// folds (and by default the fallback variants would compete again).
TEST(TorusRemesh, SharedMugAtGridPoints) {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path models = ism::test::shared_models_dir();
  const fs::path dir = scratch_dir("torus");
  const std::string common =
      (models / "mug.obj").string() + " --size 128 -q --anisotropy-weight 0 --inverse-weight 0.1";
  const auto moved = run_tool("torus-remesh", common + " -o " + (dir / "mug_m.obj").string() +
                                                  " --report " + (dir / "mug_m.json").string());
  const auto fixed =
      run_tool("torus-remesh", common + " --grid-points -o " + (dir / "mug_g.obj").string() +
                                   " --report " + (dir / "mug_g.json").string());
  ASSERT_EQ(moved.status, 0) << moved.err;
  ASSERT_EQ(fixed.status, 0) << fixed.err;
  const std::string m = slurp(dir / "mug_m.json"), g = slurp(dir / "mug_g.json");
  // The same map (one variant, no fallback with the penalty off), sampled both ways.
  EXPECT_EQ(report_number(m, "efficiency_domain_to_surface", "map"),
            report_number(g, "efficiency_domain_to_surface", "map"));
  const double at_grid = report_number(g, "flipped_triangles", "grid");
  EXPECT_GT(at_grid, 0);
  EXPECT_EQ(report_number(g, "resampled_vertices", "grid"), 0);
  EXPECT_EQ(report_number(m, "flipped_triangles_at_grid_points", "grid"), at_grid);
  EXPECT_GT(report_number(m, "resampled_vertices", "grid"), 0);
  EXPECT_LT(report_number(m, "flipped_triangles", "grid"), at_grid);
  // Both are valence-4 torus grids.
  expect_valence_four_torus(dir / "mug_m.obj", 128, 128);
  expect_valence_four_torus(dir / "mug_g.obj", 128, 128);
}

// One error line naming the file (or the tool), exit status 1, no output.
void expect_refused(const std::string& args, const fs::path& out, const std::string& message) {
  SCOPED_TRACE(args);
  fs::remove(out);
  const auto r = run_tool("torus-remesh", args + " -o " + out.string() + " -q");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  std::printf("refused: %s", r.err.c_str());
  EXPECT_FALSE(fs::exists(out));
}

void write_lines(const fs::path& file, const std::vector<std::string>& lines) {
  std::ofstream f(file);
  for (const auto& line : lines) f << line << '\n';
}

TEST(TorusRemesh, UnsuitableInputsAreRefusedWithoutOutput) {
  const fs::path dir = scratch_dir("torus");
  const fs::path torus = dir / "refuse_torus.obj", sphere = dir / "refuse_sphere.obj",
                 genus2 = dir / "refuse_genus2.obj", open = dir / "refuse_open.obj",
                 out = dir / "refused.obj", drc = dir / "refused.drc",
                 features = dir / "refuse_features.txt";
  ASSERT_EQ(run_tool("ism-genmesh", "torus --faces 1000 -o " + torus.string()).status, 0);
  ASSERT_EQ(run_tool("ism-genmesh", "sphere --faces 500 -o " + sphere.string()).status, 0);
  ASSERT_EQ(run_tool("ism-genmesh", "double-torus --faces 1000 -o " + genus2.string()).status, 0);
  {
    const ism::PolygonSoup soup = ism::io::read_polygon_soup(torus);
    ism::TriangleMesh holed{soup.positions, {}};
    for (std::size_t f = 1; f < soup.faces.size(); ++f)
      holed.triangles.push_back({soup.faces[f][0], soup.faces[f][1], soup.faces[f][2]});
    ism::io::write_mesh(holed, open);
  }
  expect_refused(sphere.string(), out, sphere.string() + ": genus 0, torus-remesh needs genus 1");
  expect_refused(genus2.string(), out, genus2.string() + ": genus 2, torus-remesh needs genus 1");
  expect_refused(open.string(), out,
                 open.string() +
                     ": 1 boundary loop, torus-remesh needs a closed surface; fill "
                     "its holes first (e.g. MeshLab's Close Holes)");

  write_lines(features, {"# eight", "0", "1", "2", "3", "4", "5", "6", "7"});
  expect_refused(torus.string() + " --features " + features.string(), out,
                 features.string() + ": 8 features, torus-remesh needs 9");
  write_lines(features, {"0", "1", "2", "3", "100000", "5", "6", "7", "8"});
  expect_refused(torus.string() + " --features " + features.string(), out,
                 features.string() + ": feature 4: vertex index 100000 out of range");
  write_lines(features, {"0", "1", "2", "3", "4", "5", "6", "7", "-3"});
  expect_refused(torus.string() + " --features " + features.string(), out,
                 "vertex index -3 out of range");
  write_lines(features, {"0", "1", "2", "3", "4", "5", "6", "7", "7"});
  expect_refused(torus.string() + " --features " + features.string(), out, "same vertex 7");
  expect_refused(torus.string() + " --features " + (dir / "missing.txt").string(), out,
                 "cannot open the feature file");

  for (const char* size : {"2", "64x2", "0", "abc", "12x", "x12", "-5"})
    expect_refused(torus.string() + " --size " + size, out,
                   "torus-remesh: --size must be N or UxV with N, U, V >= 3");
  expect_refused(torus.string(), drc,
                 "Draco stores triangles only; add --triangulate, or write the quads as .obj");
  expect_refused(torus.string() + " --image " + (dir / "refused.png").string(), out,
                 "--image writes OpenEXR, name it .exr");
  EXPECT_FALSE(fs::exists(dir / "refused.png"));

  ISM_REQUIRE_SHARED_MODELS();
  // A permutation of torus_features_3x3.txt that neither as given nor
  // transposed can be traced on torus.obj.
  const fs::path model = ism::test::shared_models_dir() / "torus.obj";
  write_lines(features, {"1536", "3072", "1552", "1568", "3088", "32", "3104", "16", "0"});
  expect_refused(model.string() + " --features " + features.string(), out,
                 model.string() + ": cannot trace the path between features");
  expect_refused(model.string() + " --features " + features.string(), out,
                 "the features' order cannot be realised on the surface (features from " +
                     features.string() + ")");
}

}  // namespace
