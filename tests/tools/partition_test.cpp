// ism-partition as a user runs it: two surfaces (and pairs) in, the patches
// of both, the base and a report out; bad input refused with one line, a
// non-zero exit and no output file.
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "open_surfaces.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace {

namespace fs = std::filesystem;
using ism::test::quoted;
using ism::test::report_number;
using ism::test::run_tool;
using ism::test::scratch_dir;
using ism::test::slurp;

struct Files {
  fs::path dir, sphere, ellipsoid, torus, disc;
};

const Files& files() {
  static const Files f = [] {
    Files out;
    out.dir = scratch_dir("partition_tool");
    out.sphere = out.dir / "sphere.obj";
    out.ellipsoid = out.dir / "ellipsoid.obj";
    out.torus = out.dir / "torus.obj";
    out.disc = out.dir / "disc.obj";
    ism::io::write_mesh(ism::shapes::sphere(1500), out.sphere);
    ism::io::write_mesh(ism::shapes::ellipsoid(2500, {2, 1, 0.7}), out.ellipsoid);
    ism::io::write_mesh(ism::shapes::torus(2000), out.torus);
    const ism::TriangleMesh disc = ism::test::keep_faces(
        ism::shapes::sphere(1500), [](const ism::Vec3& c) { return c.z() < 0.5; });
    ism::io::write_mesh(disc, out.disc);
    return out;
  }();
  return f;
}

fs::path text_file(const std::string& name, const std::string& text) {
  return ism::test::write_text(files().dir, name, text);
}

TEST(PartitionTool, WritesPatchesBaseAndReport) {
  const Files& f = files();
  const fs::path prefix = f.dir / "patches", base = f.dir / "base.obj", report = f.dir / "r.json";
  for (const auto& p :
       {fs::path(prefix.string() + "_A.ply"), fs::path(prefix.string() + "_B.ply"), base, report})
    fs::remove(p);
  const auto pairs = text_file("pairs.txt", "# two pairs\n0 0\n100 200\n");
  const auto r = run_tool("ism-partition", quoted(f.sphere) + " " + quoted(f.ellipsoid) +
                                               " --features " + quoted(pairs) + " --dump-patches " +
                                               quoted(prefix) + " --write-base " + quoted(base) +
                                               " --report " + quoted(report));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string json = slurp(report);
  EXPECT_EQ(report_number(json, "features_given", "partition"), 2);
  EXPECT_GE(report_number(json, "features_added", "partition"), 2);  // four on genus 0
  EXPECT_NE(json.find("\"replay_exact_A\": true"), std::string::npos);
  EXPECT_NE(json.find("\"replay_exact_B\": true"), std::string::npos);
  EXPECT_NE(json.find("\"base_identical_B\": true"), std::string::npos);
  EXPECT_NE(json.find("\"networks_valid\": true"), std::string::npos);
  // The base as written: a closed genus-0 mesh with the reported faces.
  const auto check = ism::prepare_mesh(ism::io::read_polygon_soup(base)).check;
  EXPECT_EQ(check.genus, 0);
  EXPECT_TRUE(check.closed());
  EXPECT_EQ(double(check.faces), report_number(json, "faces", "base_mesh"));
  // Both dumps: the surface with its Steiner vertices, faces coloured by patch.
  for (const char* side : {"_A.ply", "_B.ply"}) {
    const auto soup = ism::io::read_polygon_soup(prefix.string() + side);
    EXPECT_GT(soup.faces.size(), 1000u);
  }
}

TEST(PartitionTool, LandmarkListsAndAutomaticFeatures) {
  const Files& f = files();
  const auto la = text_file("a.txt", "5\n17\n42\n90\n"), lb = text_file("b.txt", "1\n2\n3\n4\n");
  const auto r =
      run_tool("ism-partition", quoted(f.sphere) + " " + quoted(f.ellipsoid) + " --landmarks " +
                                    quoted(la) + " " + quoted(lb) + " -q");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const auto torus = run_tool("ism-partition", quoted(f.torus) + " " + quoted(f.torus) + " -q");
  EXPECT_EQ(torus.status, 0) << torus.err;
}

// One line on stderr, a non-zero status, and none of the outputs.
void expect_refusal(const std::string& args, const std::string& words) {
  const Files& f = files();
  const fs::path prefix = f.dir / "refused", base = f.dir / "refused.obj",
                 report = f.dir / "refused.json";
  const std::vector<fs::path> outputs = {prefix.string() + "_A.ply", prefix.string() + "_B.ply",
                                         base, report};
  for (const auto& p : outputs) fs::remove(p);
  const auto r =
      run_tool("ism-partition", args + " --dump-patches " + quoted(prefix) + " --write-base " +
                                    quoted(base) + " --report " + quoted(report));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  for (const auto& p : outputs) EXPECT_FALSE(fs::exists(p)) << p;
}

TEST(PartitionTool, RefusesBadInput) {
  const Files& f = files();
  const std::string two = quoted(f.sphere) + " " + quoted(f.ellipsoid);
  expect_refusal(quoted(f.sphere) + " " + quoted(f.torus), "genus 0");
  expect_refusal(quoted(f.sphere) + " " + quoted(f.disc), "1 boundary loop");
  expect_refusal(two + " --features " + quoted(text_file("range.txt", "1 2\n3 999999\n")),
                 "range.txt:2: vertex index 999999");
  expect_refusal(two + " --features " + quoted(text_file("twice.txt", "1 2\n3 4\n5 2\n")),
                 "twice.txt:3: vertex 2 of");
  expect_refusal(two + " --features " + quoted(text_file("empty.txt", "# none\n")),
                 "no feature pairs");
  expect_refusal(two + " --features " + quoted(f.dir / "missing.txt"), "cannot open");
  expect_refusal(quoted(f.sphere) + " " + quoted(f.dir / "missing.obj"), "missing.obj");
}

}  // namespace
