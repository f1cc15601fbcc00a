// The command-line tools as a user runs them: exit status, one-line errors,
// JSON keys, no output file on failure.
#include "io/io.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <set>

namespace {

namespace fs = std::filesystem;

using Result = ism::test::ToolResult;
using ism::test::slurp;

fs::path scratch_dir() {
  return ism::test::scratch_dir("tools");
}

Result run(const std::string& tool, const std::string& args) {
  return ism::test::run_tool(tool, args);
}

std::size_t lines(const std::string& s) {
  return std::count(s.begin(), s.end(), '\n');
}

TEST(IsmInfo, ValidModelsExitZeroWithTheirGenus) {
  ISM_REQUIRE_SHARED_MODELS();
  const std::pair<const char*, const char*> cases[] = {
      {"bunny_small.obj", "\"genus\": 0"},
      {"bunny_open.obj", "\"boundary_loops\": 5"},
      {"torus.obj", "\"genus\": 1"},
      {"fertility.obj", "\"genus\": 4"},
  };
  for (const auto& [file, expected] : cases) {
    SCOPED_TRACE(file);
    const Result r = run("ism-info", (ism::test::shared_models_dir() / file).string() + " --json");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"manifold\": true"), std::string::npos);
  }
}

TEST(IsmInfo, EveryBadModelGetsAnAnswerAndNoCrash) {
  ISM_REQUIRE_SHARED_MODELS();
  const std::pair<const char*, int> cases[] = {
      {"cow_pinched.obj", 1},       {"dragon_vrip_res4.obj", 1}, {"trex_skull_scan.obj", 1},
      {"two_tori_linked.obj", 1},   {"mobius.obj", 1},           {"teapot_patch_soup.obj", 1},
      {"bunny_inward.obj", 0},      {"blobby_shuffled.obj", 0},  {"torus_quads.obj", 0},
      {"sphere_uv_unwelded.obj", 0}};
  for (const auto& [file, status] : cases) {
    SCOPED_TRACE(file);
    const fs::path path = ism::test::shared_models_dir() / "bad" / file;
    const Result r = run("ism-info", path.string());
    EXPECT_EQ(r.status, status) << r.err;
    if (status != 0) {
      EXPECT_EQ(lines(r.err), 1u) << r.err;
      EXPECT_EQ(r.err.rfind(path.string() + ": ", 0), 0u) << r.err;
    } else {
      EXPECT_NE(r.out.find("repaired: "), std::string::npos) << r.out;
    }
  }
}

TEST(IsmInfo, UnreadableFileIsOneLine) {
  const Result r = run("ism-info", "/nonexistent/mesh.obj");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "/nonexistent/mesh.obj: no such file\n");
}

TEST(Tools, WrongTopologyIsRefusedWithoutOutput) {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path output = scratch_dir() / "never.exr";
  fs::remove(output);
  const fs::path input = ism::test::shared_models_dir() / "torus.obj";
  const Result r = run("gim-remesh", input.string() + " -o " + output.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, input.string() + ": genus 1, gim-remesh needs genus 0\n");
  EXPECT_FALSE(fs::exists(output));
}

TEST(IsmInfo, EachBoundaryLoopIsListedWithItsVerticesAndLength) {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path input = ism::test::shared_models_dir() / "head_3holes.obj";
  const Result r = run("ism-info", input.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto info = nlohmann::json::parse(r.out);
  ASSERT_EQ(info["boundary_loops"], 3);
  ASSERT_EQ(info["loops"].size(), 3u);
  // Against the loops walked here from the file's faces: the boundary
  // half-edges (no twin) chained, each loop's vertices and summed length.
  const ism::PolygonSoup soup = ism::io::read_polygon_soup(input);
  std::map<int, int> next;
  std::set<std::pair<int, int>> directed;
  for (const auto& f : soup.faces)
    for (std::size_t k = 0; k < f.size(); ++k) directed.insert({f[k], f[(k + 1) % f.size()]});
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) next[b] = a;
  std::vector<std::pair<std::size_t, double>> expected, listed;
  std::set<int> seen;
  for (const auto& [start, unused] : next) {
    if (seen.count(start)) continue;
    std::size_t count = 0;
    double length = 0;
    int v = start;
    do {
      seen.insert(v);
      ++count;
      length += (soup.positions[next[v]] - soup.positions[v]).norm();
      v = next[v];
    } while (v != start);
    expected.push_back({count, length});
  }
  for (const auto& loop : info["loops"])
    listed.push_back({loop["vertices"].get<std::size_t>(), loop["length"].get<double>()});
  std::sort(expected.begin(), expected.end());
  std::sort(listed.begin(), listed.end());
  ASSERT_EQ(listed.size(), expected.size());
  for (std::size_t l = 0; l < listed.size(); ++l) {
    EXPECT_EQ(listed[l].first, expected[l].first);
    EXPECT_NEAR(listed[l].second, expected[l].second, 1e-9 * expected[l].second);
  }
  const Result text = run("ism-info", input.string());
  EXPECT_NE(text.out.find("boundary loop 2: "), std::string::npos) << text.out;
}

TEST(Tools, GeneratedMeshIsAValidSurfaceAndReportIsWritten) {
  const fs::path mesh = scratch_dir() / "generated_torus.obj",
                 report = scratch_dir() / "report.json";
  fs::remove(report);
  Result r = run("ism-genmesh", "torus --faces 2000 -o " + mesh.string());
  ASSERT_EQ(r.status, 0) << r.err;
  r = run("ism-info", mesh.string() + " --report " + report.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("genus 1"), std::string::npos) << r.out;
  const std::string json = slurp(report);
  EXPECT_NE(json.find("\"peak_memory_mb\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"total\""), std::string::npos) << json;
}

TEST(Tools, OutputOverTheInputIsRefused) {
  const fs::path mesh = scratch_dir() / "keep.obj";
  ASSERT_EQ(run("ism-genmesh", "sphere --faces 500 -o " + mesh.string()).status, 0);
  const std::string before = slurp(mesh);
  // An output of a writable kind (a mesh) named as the input.
  const fs::path image = scratch_dir() / "keep.exr";
  fs::remove(image);
  const Result r =
      run("gim-remesh", mesh.string() + " -o " + image.string() + " --mesh " + mesh.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("refusing to overwrite an input file"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(mesh), before);
  EXPECT_FALSE(fs::exists(image));
  // A report named as the input: refused (as not JSON), the input untouched.
  const Result report = run("ism-info", mesh.string() + " --report " + mesh.string());
  EXPECT_EQ(report.status, 1);
  EXPECT_EQ(slurp(mesh), before);
}

TEST(Tools, VersionAndHelp) {
  for (const char* tool : {"ism-info", "ism-genmesh", "gim-remesh", "semireg", "torus-remesh"}) {
    SCOPED_TRACE(tool);
    EXPECT_EQ(run(tool, "--version").status, 0);
    const Result help = run(tool, "--help");
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.out.find("--report"), std::string::npos);
  }
}

}  // namespace
