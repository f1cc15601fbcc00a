// Every tool over every hostile regression file (tests/data/hostile), and the
// parameter bombs: an answer (exit 0, or 1 with one line on stderr), never a
// crash, and no output file when refused.
#include "io/io.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace {

namespace fs = std::filesystem;
using ism::test::run_tool;
using ism::test::scratch_dir;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

// Regression files that are valid closed genus-0 surfaces of 6 or more
// vertices: gim-remesh maps them in full (an octahedron takes some 7 s of
// map optimisation), which the bench (bench/hostile.sh) times; here the
// other tools read them.
bool gim_maps_it(const fs::path& file) {
  const std::string name = file.filename().string();
  return name == "obj_utf8_bom.obj" || name == "off_fused_modelnet.off";
}

TEST(HostileFiles, EveryToolAnswersEveryRegressionFile) {
  const fs::path dir = scratch_dir("hostile");
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(ism::test::hostile_dir())) {
    const fs::path input = entry.path();
    if (!ism::io::is_readable_mesh_extension(input)) continue;
    ++files;
    const std::pair<const char*, std::string> runs[] = {
        {"ism-info", ""},
        {"gim-remesh", " -o " + (dir / "out.exr").string() + " --size 9"},
        {"semireg", " --base-size 4 --levels 1 -o " + (dir / "out.obj").string()},
        {"torus-remesh", " --size 8 -o " + (dir / "out.obj").string()},
    };
    for (const auto& [tool, args] : runs) {
      if (std::string(tool) == "gim-remesh" && gim_maps_it(input)) continue;
      SCOPED_TRACE(std::string(tool) + " " + input.filename().string());
      fs::remove(dir / "out.exr");
      fs::remove(dir / "out.obj");
      const auto r = run_tool(tool, input.string() + args + " -q");
      ASSERT_TRUE(r.status == 0 || r.status == 1) << r.status << " " << r.err;
      if (r.status == 1) {
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        const bool names_file = r.err.rfind(input.string(), 0) == 0;
        const bool names_tool = r.err.rfind(std::string(tool) + ": ", 0) == 0;
        EXPECT_TRUE(names_file || names_tool) << r.err;
        EXPECT_EQ(r.err.find("std::"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out.exr"));
        EXPECT_FALSE(fs::exists(dir / "out.obj"));
      }
    }
  }
  EXPECT_GE(files, 20u);
}

TEST(HostileFiles, HostileFeatureFilesAreOneLine) {
  // gim-remesh reads --features after the surface: on the hostile octahedron.
  const fs::path octahedron = ism::test::hostile_dir() / "obj_utf8_bom.obj";
  const fs::path out = scratch_dir("hostile") / "features.exr";
  for (const auto& entry : fs::directory_iterator(ism::test::hostile_dir())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("features_", 0) != 0 || name == "features_inf_point.txt") continue;
    SCOPED_TRACE(name);
    fs::remove(out);
    const auto r = run_tool("gim-remesh", octahedron.string() + " --features " +
                                              entry.path().string() + " -o " + out.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    // The file's own defect, or (valid indices, as the grid file's) the
    // surface's answer to them.
    EXPECT_TRUE(r.err.rfind(entry.path().string(), 0) == 0 ||
                r.err.rfind(octahedron.string(), 0) == 0)
        << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(HostileFiles, ParameterBombsAreRefusedBeforeReadingTheMesh) {
  const fs::path dir = scratch_dir("hostile");
  // The mesh is never read: a missing file would be the first complaint.
  const std::string missing = (dir / "never_read.obj").string();
  fs::remove(missing);
  const std::string exr = (dir / "bomb.exr").string(), obj = (dir / "bomb.obj").string();
  struct Case {
    const char* tool;
    std::string args, starts, contains;
  };
  const Case cases[] = {
      {"gim-remesh", missing + " -o " + exr + " --size 16385", "gim-remesh: --size 16385 ",
       "or less, or raise --max-memory"},
      {"gim-remesh", missing + " -o " + exr + " --size 65537", "gim-remesh: --size must be 2^k+1",
       "got 65537"},
      {"gim-remesh", missing + " -o " + exr + " --size 2049 --max-memory 1G",
       "gim-remesh: --size 2049 ", "(limit 1.0 GB); use --size 513 or less"},
      {"gim-remesh", missing + " -o " + (dir / "bomb.txt").string(),
       "gim-remesh: ", "-o writes OpenEXR; use .exr (not .txt)"},
      {"semireg", missing + " -o " + obj + " --base-size 5000 --levels 8",
       "semireg: --base-size 5000 at --levels 8", "use --levels"},
      {"semireg", missing + " -o " + (dir / "bomb.exr").string() + " --base-size 50",
       "semireg: ", "-o writes a mesh; use .obj, .ply, .off, .stl, .drc, .glb (not .exr)"},
      {"torus-remesh", missing + " -o " + obj + " --size 4096 --max-memory 2G",
       "torus-remesh: --size 4096x4096 ", "raise --max-memory"},
      {"ism-genmesh", "sphere --faces 40000000 --max-memory 1G -o " + obj,
       "ism-genmesh: --faces 40000000 needs ~", "use fewer --faces"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.tool) + " " + c.args);
    fs::remove(exr);
    fs::remove(obj);
    const auto r = run_tool(c.tool, c.args);
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind(c.starts, 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.contains), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(exr));
    EXPECT_FALSE(fs::exists(obj));
  }
}

TEST(HostileFiles, BaseSizeAtOrAboveTheSurfaceIsRefusedBeforeWork) {
  const fs::path octahedron = ism::test::hostile_dir() / "obj_utf8_bom.obj";
  const fs::path out = scratch_dir("hostile") / "base.obj";
  fs::remove(out);
  const auto r =
      run_tool("semireg", octahedron.string() + " --base-size 100000 -o " + out.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "semireg: --base-size 100000 is not below " + octahedron.string() +
                       "'s 6 vertices; a base decimates the surface (use --base-size 5 or less)\n");
  EXPECT_FALSE(fs::exists(out));
}

TEST(HostileFiles, CorruptCountsGetTheReadersLineNotABaseSizeRefusal) {
  // The peek caps a declared count at what the file's bytes can hold; a
  // capped count is no vertex count to compare --base-size with, so semireg
  // answers as the reader does (ism-info's line), not "3 vertices".
  for (const char* name :
       {"off_2e9_vertices.off", "off_binary_truncated.off", "ply_vertex_count_bomb.ply",
        "obj_utf16_bom.obj", "stl_count_bomb.stl"}) {
    SCOPED_TRACE(name);
    const fs::path input = ism::test::hostile_dir() / name;
    const fs::path out = scratch_dir("hostile") / "corrupt.obj";
    fs::remove(out);
    const auto info = run_tool("ism-info", input.string());
    ASSERT_EQ(info.status, 1) << info.err;
    const auto r = run_tool("semireg", input.string() + " --base-size 4 -o " + out.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, info.err);
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(HostileFiles, RunningOutOfMemoryIsOneLine) {
  // An address space too small for what is asked (ulimit, below the
  // estimate's limit): std::bad_alloc deep inside ends in one line naming
  // the peak and the limit, not "std::bad_alloc".
  const fs::path dir = scratch_dir("hostile");
  const fs::path out = dir / "oom.ply", err = dir / "oom.stderr";
  fs::remove(out);
  const std::string command = "ulimit -v 300000 && " +
                              (ism::test::binary_dir() / "bin" / "ism-genmesh").string() +
                              " sphere --faces 4000000 -o " + out.string() + " 2>" + err.string();
  const int raw = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 1);
  const std::string message = ism::test::slurp(err);
  EXPECT_EQ(lines(message), 1u) << message;
  EXPECT_EQ(message.rfind("ism-genmesh: out of memory (peak ", 0), 0u) << message;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
