// gim-remesh as a user runs it: images that rebuild into watertight genus-0
// meshes, the report's measures, and clean refusals of unsuitable surfaces.
#include "io/io.hpp"
#include "mesh/boundary.hpp"
#include "mesh/mesh_check.hpp"
#include "sample/geometry_image_file.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include "closed_surface_checks.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <fstream>

namespace {

namespace fs = std::filesystem;
using ism::test::check_of;
using ism::test::distance_to_faces;
using ism::test::report_number;
using ism::test::run_tool;
using ism::test::scratch_dir;
using ism::test::slurp;

// The image read back from disk is a closed, genus-0, consistently oriented
// surface with nothing to repair.
void expect_watertight_image(const fs::path& exr, int n) {
  const ism::GeometryImage image = ism::read_geometry_image(exr);
  EXPECT_EQ(image.n, n);
  const ism::MeshCheck c = check_of(ism::image_to_mesh(image));
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.faces, std::size_t(2 * (n - 1) * (n - 1)));
}

TEST(GimRemesh, GeneratedBlobGivesAWatertightImageAndAReport) {
  const fs::path dir = scratch_dir("gim");
  const fs::path blob = dir / "blob.obj", exr = dir / "blob.exr", mesh = dir / "blob.ply",
                 drc = dir / "blob.drc", report = dir / "blob.json", png = dir / "blob.png",
                 meta = dir / "blob.meta";
  ASSERT_EQ(run_tool("ism-genmesh", "blob --faces 3000 -o " + blob.string()).status, 0);
  const auto r =
      run_tool("gim-remesh", blob.string() + " -o " + exr.string() + " --size 65 --mesh " +
                                 mesh.string() + " --preview " + png.string() + " --meta-mesh " +
                                 meta.string() + " --report " + report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_watertight_image(exr, 65);
  EXPECT_TRUE(fs::exists(mesh));
  EXPECT_TRUE(fs::exists(png));
  const std::string json = slurp(report);
  for (const char* key : {"\"partition\"", "\"symmetric_efficiency\"", "\"efficiency_square\"",
                          "\"flipped_triangles\"", "\"psnr_db\"", "\"peak_memory_mb\"",
                          "\"valid\": true", "\"curvature_weight\": 0.5"})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  // The map as a meta-mesh: validated from both sides, one record per crossing.
  const std::size_t section = json.find("\"meta_mesh\": {");
  ASSERT_NE(section, std::string::npos);
  EXPECT_NE(json.substr(section, json.find('}', section) - section).find("\"valid\": true"),
            std::string::npos);
  std::ifstream in(meta);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "ism-meta-mesh 1");
  std::getline(in, line);
  EXPECT_EQ(line, "mesh 0 6 8");
  std::size_t crossings = 0;
  while (std::getline(in, line)) crossings += line.rfind("x ", 0) == 0;
  EXPECT_GT(crossings, 0u);
  EXPECT_EQ(double(crossings), report_number(json, "crossings", "meta_mesh"));
  ASSERT_EQ(run_tool("gim-remesh", blob.string() + " -o " + exr.string() + " --size 33 --mesh " +
                                       drc.string() + " -q")
                .status,
            0);
  EXPECT_GT(fs::file_size(drc), 100u);
}

// --contenders N: each variant's N best coarse networks refined whole, the
// best final map kept (the report lists each with its score).
TEST(GimRemesh, ContendersAreRefinedWholeAndTheBestIsKept) {
  const fs::path dir = scratch_dir("gim_contenders");
  const fs::path blob = dir / "blob.obj", exr = dir / "blob.exr", report = dir / "blob.json";
  ASSERT_EQ(run_tool("ism-genmesh", "blob --faces 1500 -o " + blob.string()).status, 0);
  const auto r = run_tool("gim-remesh", blob.string() + " -o " + exr.string() +
                                            " --size 33 --inverse-weight 0.5 --contenders 2 "
                                            "--report " +
                                            report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto json = nlohmann::json::parse(slurp(report));
  const auto& variants = json["map_variants"];
  ASSERT_EQ(variants.size(), 2u);
  EXPECT_EQ(variants[0]["contender"], 0);
  EXPECT_EQ(variants[1]["contender"], 1);
  EXPECT_NE(variants[0]["candidate"], variants[1]["candidate"]);
  const int kept = variants[0]["kept"].get<bool>() ? 0 : 1;
  EXPECT_TRUE(variants[kept]["kept"].get<bool>());
  EXPECT_FALSE(variants[1 - kept]["kept"].get<bool>());
  EXPECT_GE(variants[kept]["score"].get<double>(), variants[1 - kept]["score"].get<double>());
  // (The map section is measured on the meta-mesh's pieces, a variant by
  // the core that refined it: the same map, summed otherwise.)
  EXPECT_NEAR(json["map"]["efficiency_domain_to_surface"].get<double>(),
              variants[kept]["efficiency_domain_to_surface"].get<double>(), 1e-12);
  EXPECT_NE(
      run_tool("gim-remesh", blob.string() + " -o " + exr.string() + " --contenders 0 -q").status,
      0);
}

// The same tool on the symmetric map core (InterSurfaceMap: the octahedron
// as side 0, its vertices released continuously): a watertight image, the
// map validated from both sides and written as a meta-mesh, the measures
// above floors (measured at commit time: square efficiency 0.904, PSNR
// 74.3 dB, no flip; the default core 0.904, 74.4 dB). Open surfaces: below,
// on both cores.
TEST(GimRemesh, SymmetricCoreGivesAValidImageAboveItsFloors) {
  const fs::path dir = scratch_dir("gim_symmetric");
  const fs::path blob = dir / "blob.obj", exr = dir / "blob.exr", report = dir / "blob.json",
                 meta = dir / "blob.meta";
  ASSERT_EQ(run_tool("ism-genmesh", "blob --faces 3000 -o " + blob.string()).status, 0);
  const auto r = run_tool("gim-remesh", blob.string() + " -o " + exr.string() +
                                            " --size 65 --core symmetric --meta-mesh " +
                                            meta.string() + " --report " + report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_watertight_image(exr, 65);
  const auto json = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(json["map_core"], "symmetric");
  EXPECT_EQ(json["map"]["core"], "symmetric");
  EXPECT_TRUE(json["meta_mesh"]["valid"].get<bool>());
  EXPECT_GT(json["map"]["moves"].get<double>(), 0);
  // Where each variant's refinement time went: parts of it, fast charts
  // among them, within the variant's time.
  ASSERT_FALSE(json["map_variants"].empty());
  for (const auto& variant : json["map_variants"]) {
    const double refine = variant["seconds_refine"].get<double>();
    double parts = 0;
    for (const auto& [part, seconds] : variant["seconds_by_operation"].items()) {
      EXPECT_GE(seconds.get<double>(), 0) << part;
      parts += seconds.get<double>();
    }
    EXPECT_GT(variant["seconds_by_operation"]["fast_charts"].get<double>(), 0);
    EXPECT_LE(parts, refine);
    EXPECT_LE(refine, variant["seconds"].get<double>());
  }
  const double efficiency = json["image"]["efficiency_square"].get<double>(),
               psnr = json["distance"]["psnr_db"].get<double>();
  std::printf("symmetric core: square efficiency %.4f, %d flips, PSNR %.2f dB\n", efficiency,
              json["image"]["flipped_triangles"].get<int>(), psnr);
  EXPECT_GE(efficiency, 0.88);
  EXPECT_GE(psnr, 73.0);
  EXPECT_EQ(json["image"]["flipped_triangles"].get<int>(), 0);
  std::ifstream in(meta);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "ism-meta-mesh 1");
  std::size_t crossings = 0;
  while (std::getline(in, line)) crossings += line.rfind("x ", 0) == 0;
  EXPECT_GT(crossings, 0u);
  EXPECT_EQ(double(crossings), json["meta_mesh"]["crossings"].get<double>());
}

// The race between the variants on the symmetric core: with --drop-behind 0
// a variant behind the other after both of the first two levels is
// dropped (stopped there, or left out if it finished first: the blob's
// W = 1 variant often does); the map kept, and so the meta-mesh written,
// is here the one the variants refined whole keep.
TEST(GimRemesh, SymmetricCoreStopsAVariantClearlyBehindAndKeepsTheSameMap) {
  const fs::path dir = scratch_dir("gim_race");
  const fs::path blob = dir / "blob.obj";
  ASSERT_EQ(run_tool("ism-genmesh", "blob --faces 12000 -o " + blob.string()).status, 0);
  std::array<nlohmann::json, 2> json;
  std::array<std::string, 2> meta;
  for (int raced = 0; raced < 2; ++raced) {
    const std::string name = raced ? "raced" : "whole";
    const fs::path exr = dir / (name + ".exr"), report = dir / (name + ".json"),
                   meta_file = dir / (name + ".meta");
    const auto r =
        run_tool("gim-remesh", blob.string() + " -o " + exr.string() +
                                   " --size 65 --core symmetric --drop-behind " +
                                   (raced ? "0" : "-1") + " --meta-mesh " + meta_file.string() +
                                   " --report " + report.string() + " -q");
    ASSERT_EQ(r.status, 0) << r.err;
    json[raced] = nlohmann::json::parse(slurp(report));
    meta[raced] = slurp(meta_file);
  }
  const auto& whole = json[0]["map_variants"];
  const auto& raced = json[1]["map_variants"];
  ASSERT_EQ(whole.size(), 2u);
  ASSERT_EQ(raced.size(), 2u);
  // Each variant's scores after its first two levels (more while the other
  // has not reached its second), the same in both runs; dropped exactly
  // when behind the other after both.
  std::array<std::array<double, 2>, 2> level;
  for (int v = 0; v < 2; ++v) {
    ASSERT_GE(whole[v]["level_scores"].size(), 2u);
    ASSERT_GE(raced[v]["level_scores"].size(), 2u);
    EXPECT_FALSE(whole[v].contains("dropped"));
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(whole[v]["level_scores"][k], raced[v]["level_scores"][k]);
      level[v][k] = whole[v]["level_scores"][k]["score"].get<double>();
    }
  }
  int dropped = 0;
  for (int v = 0; v < 2; ++v) {
    const bool behind = level[1 - v][0] > level[v][0] && level[1 - v][1] > level[v][1];
    EXPECT_EQ(raced[v].contains("dropped"), behind) << "variant " << v;
    if (!behind) continue;
    ++dropped;
    EXPECT_FALSE(raced[v]["kept"].get<bool>());
    EXPECT_EQ(raced[v]["dropped"]["after_level"].get<int>(), 2);
    EXPECT_DOUBLE_EQ(raced[v]["dropped"]["score"].get<double>(), level[v][1]);
    EXPECT_DOUBLE_EQ(raced[v]["dropped"]["leader_score"].get<double>(), level[1 - v][1]);
    EXPECT_TRUE(whole[1 - v]["kept"].get<bool>());
  }
  ASSERT_EQ(dropped, 1) << "the blob's variants no longer separate after two levels";
  EXPECT_EQ(meta[0], meta[1]);
  EXPECT_EQ(json[0]["map"]["efficiency_domain_to_surface"],
            json[1]["map"]["efficiency_domain_to_surface"]);
}

// Every closed genus-0 shared model, one test each (they take 5-60 s).
// Floors at 129² (measured at commit time, a little below): PSNR of the
// remesh, square-domain efficiency of the image, most flipped triangles.
struct Floor {
  const char* name;
  double psnr = 0, efficiency = 0;
  int flips = -1;
  // The largest models run one variant of the map (the one they keep with
  // the default two), which halves their time in CI.
  const char* options = "";
};

void PrintTo(const Floor& floor, std::ostream* os) {
  *os << floor.name;
}

class GimRemeshSharedModel : public ::testing::TestWithParam<Floor> {};

TEST_P(GimRemeshSharedModel, ValidWatertightAndAboveItsFloors) {
  ISM_REQUIRE_SHARED_MODELS();
  const Floor& m = GetParam();
  const fs::path dir = scratch_dir("gim");
  const fs::path exr = dir / (std::string(m.name) + ".exr"),
                 report = dir / (std::string(m.name) + ".json");
  const auto r =
      run_tool("gim-remesh",
               (ism::test::shared_models_dir() / (std::string(m.name) + ".obj")).string() + " -o " +
                   exr.string() + " --size 129 -q --report " + report.string() + " " + m.options);
  ASSERT_EQ(r.status, 0) << r.err;
  expect_watertight_image(exr, 129);
  const std::string json = slurp(report);
  EXPECT_NE(json.find("\"valid\": true"), std::string::npos);
  const double psnr = report_number(json, "psnr_db"),
               efficiency = report_number(json, "efficiency_square"),
               flips = report_number(json, "flipped_triangles");
  std::printf("%-12s square efficiency %.4f, %4.0f flips, PSNR %.2f dB\n", m.name, efficiency,
              flips, psnr);
  EXPECT_GE(psnr, m.psnr);
  EXPECT_GE(efficiency, m.efficiency);
  if (m.flips >= 0) {
    EXPECT_LE(flips, m.flips);
  }
}

// dragon is known to be poor: PSNR and efficiency without floors. With the
// pixels of folded triangles re-sampled, every model but dragon (1) measured
// 0 folds (at their grid points: bunny_small 40, gargoyle 30, nefertiti 30,
// bunny 60 were the caps).
INSTANTIATE_TEST_SUITE_P(
    EveryClosedGenusZero, GimRemeshSharedModel,
    ::testing::Values(Floor{"bunny_small", 71.3, 0.75, 2}, Floor{"spot", 74.7, 0.69, 2},
                      Floor{"gargoyle", 68.7, 0.70, 2}, Floor{"max_planck", 77.5, 0.88, 2},
                      Floor{"igea", 72.6, 0.90, 2}, Floor{"nefertiti", 71.7, 0.70, 2},
                      Floor{"fandisk", 73.5, 0.84, 2}, Floor{"sphere", 85.8, 0.88, 0},
                      Floor{"cube", 72.4, 0.85, 2},
                      Floor{"bunny", 70.3, 0.75, 2, "--inverse-weight 0.1"},
                      Floor{"dragon", 0, 0, 5, "--inverse-weight 0.1"}),
    [](const auto& info) { return std::string(info.param.name); });

// The pixels of folded triangles re-sampled nearby (the default) against
// every pixel at its grid point (--grid-points): the same map, fewer folds;
// only the re-sampled pixels differ, and the normal map follows them.
TEST(GimRemesh, FoldedPixelsAreReSampledAndTheNormalsFollow) {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path dir = scratch_dir("gim");
  const std::string input = (ism::test::shared_models_dir() / "bunny_small.obj").string();
  auto run = [&](const std::string& tag, const std::string& extra) {
    const auto r = run_tool("gim-remesh", input + " --size 129 -q --inverse-weight 0.1 -o " +
                                              (dir / (tag + ".exr")).string() + " --normals " +
                                              (dir / (tag + "_n.exr")).string() + " --report " +
                                              (dir / (tag + ".json")).string() + " " + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(slurp(dir / (tag + ".json")));
  };
  const auto moved = run("resampled", ""), fixed = run("grid_points", "--grid-points");
  EXPECT_EQ(moved["map"]["efficiency_domain_to_surface"],
            fixed["map"]["efficiency_domain_to_surface"]);
  const int at_grid = fixed["image"]["flipped_triangles"].get<int>();
  EXPECT_GT(at_grid, 0);
  EXPECT_EQ(fixed["image"]["flipped_triangles_at_grid_points"], at_grid);
  EXPECT_EQ(fixed["image"]["resampled_vertices"], 0);
  EXPECT_EQ(moved["image"]["flipped_triangles_at_grid_points"], at_grid);
  EXPECT_LT(moved["image"]["flipped_triangles"].get<int>(), at_grid);
  const std::size_t resampled = moved["image"]["resampled_vertices"].get<std::size_t>();
  EXPECT_GT(resampled, 0u);
  const ism::GeometryImage a = ism::read_geometry_image(dir / "resampled.exr"),
                           b = ism::read_geometry_image(dir / "grid_points.exr"),
                           na = ism::read_geometry_image(dir / "resampled_n.exr"),
                           nb = ism::read_geometry_image(dir / "grid_points_n.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  std::size_t differ = 0, normals_differ = 0;
  for (std::size_t p = 0; p < a.pixels.size(); ++p) {
    const bool same = a.pixels[p] == b.pixels[p];
    differ += !same;
    normals_differ += na.pixels[p] != nb.pixels[p];
    if (same) EXPECT_EQ(na.pixels[p], nb.pixels[p]) << p;  // a normal moves with its pixel only
  }
  EXPECT_GE(differ, resampled);
  EXPECT_LE(differ, 4 * resampled);  // mirrored pixels: 2 on a side, 4 at -z
  EXPECT_GT(normals_differ, 0u);
  expect_watertight_image(dir / "resampled.exr", 129);
}

TEST(GimRemesh, UnsuitableSurfacesAreRefusedWithoutOutput) {
  ISM_REQUIRE_SHARED_MODELS();
  const fs::path out = scratch_dir("gim") / "refused.exr";
  const auto models = ism::test::shared_models_dir();
  const std::pair<fs::path, std::string> cases[] = {
      {models / "torus.obj", "genus 1, gim-remesh needs genus 0"},
      {models / "bad" / "two_tori_linked.obj", "2 connected components"},
  };
  for (const auto& [input, message] : cases) {
    SCOPED_TRACE(input.string());
    fs::remove(out);
    const auto r = run_tool("gim-remesh", input.string() + " -o " + out.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind(input.string() + ": ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  const auto bad_size = run_tool(
      "gim-remesh", (models / "sphere.obj").string() + " -o " + out.string() + " --size 100");
  EXPECT_EQ(bad_size.status, 1);
  EXPECT_NE(bad_size.err.find("2^k+1"), std::string::npos);
  EXPECT_FALSE(fs::exists(out));
}

// An open genus-0 surface: its holes are capped and mapped with it; the
// image's alpha says which pixels fall on the surface (alpha 1: on an input
// face) and which on a cap (alpha 0: on a fan face); the remesh is open
// with the input's loops; the report measures the input surface alone. On
// either map core.
struct OpenCase {
  const char* name;
  const char* core;
};

void PrintTo(const OpenCase& c, std::ostream* os) {
  *os << c.name << " " << c.core;
}

class GimRemeshOpenModel : public ::testing::TestWithParam<OpenCase> {};

TEST_P(GimRemeshOpenModel, CapsAreMaskedByAlphaAndDroppedFromTheRemesh) {
  ISM_REQUIRE_SHARED_MODELS();
  const std::string name = GetParam().name, core = GetParam().core;
  const fs::path dir = scratch_dir("gim_open_" + core);
  const fs::path input = ism::test::shared_models_dir() / (name + ".obj");
  const fs::path exr = dir / (name + ".exr"), mesh = dir / (name + "_remesh.obj"),
                 mask = dir / (name + "_mask.png"), report = dir / (name + ".json");
  const int n = 65;
  const auto r =
      run_tool("gim-remesh", input.string() + " -o " + exr.string() +
                                 " --size 65 --inverse-weight 0.1 --final-sweeps 2" + " --core " +
                                 core + " --mesh " + mesh.string() + " --mask " + mask.string() +
                                 " --report " + report.string() + " -q");
  ASSERT_EQ(r.status, 0) << r.err;

  const ism::PolygonSoup soup = ism::io::read_polygon_soup(input);
  ism::TriangleMesh surface{soup.positions, {}};
  for (const auto& f : soup.faces) surface.triangles.push_back({f[0], f[1], f[2]});
  const ism::CappedMesh capped = ism::cap_boundary_loops(surface, ism::boundary_loops(surface));
  ASSERT_FALSE(capped.loops.empty());
  const double diagonal = ism::bounding_box_diagonal(surface);

  const ism::GeometryImage image = ism::read_geometry_image(exr);
  ASSERT_EQ(image.n, n);
  ASSERT_EQ(image.alpha.size(), image.pixels.size()) << "no alpha channel";
  std::size_t on_cap = 0;
  for (std::size_t p = 0; p < image.pixels.size(); ++p) {
    const float a = image.alpha[p];
    ASSERT_TRUE(a == 0.0f || a == 1.0f) << a;
    // Alpha 1: the sample lies on a face of the input; alpha 0: on a cap.
    const double d = a == 1.0f
                         ? distance_to_faces(image.pixels[p], capped.mesh, 0, capped.input_faces)
                         : distance_to_faces(image.pixels[p], capped.mesh, capped.input_faces,
                                             capped.mesh.n_faces());
    EXPECT_LT(d, 1e-6 * diagonal) << "pixel " << p << " alpha " << a;
    on_cap += a == 0.0f;
  }
  EXPECT_GT(on_cap, 0u);
  EXPECT_LT(on_cap, image.pixels.size() / 2);
  // Mirrored border pixels are one point: the same alpha.
  for (int j = 0; j < n; ++j) {
    EXPECT_EQ(image.alpha[image.index(0, j)], image.alpha[image.index(0, n - 1 - j)]);
    EXPECT_EQ(image.alpha[image.index(j, 0)], image.alpha[image.index(n - 1 - j, 0)]);
  }

  // The remesh: a valid surface, open with the input's number of loops.
  const ism::PolygonSoup remesh_soup = ism::io::read_polygon_soup(mesh);
  ism::TriangleMesh remesh{remesh_soup.positions, {}};
  for (const auto& f : remesh_soup.faces) remesh.triangles.push_back({f[0], f[1], f[2]});
  const ism::MeshCheck c = check_of(remesh);
  EXPECT_TRUE(c.valid_surface()) << (c.defects().empty() ? "" : c.defects().front());
  EXPECT_EQ(c.boundary_loops, capped.loops.size());
  EXPECT_EQ(c.genus, 0);
  const ism::TriangleMesh expected = ism::image_to_surface_mesh(image);
  EXPECT_EQ(remesh.n_vertices(), expected.n_vertices());
  EXPECT_EQ(remesh.triangles, expected.triangles);

  const std::string png = slurp(mask);
  EXPECT_EQ(png.substr(1, 3), "PNG");

  const auto json = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(json["map_core"], core == "symmetric" ? "symmetric" : "surface_map");
  EXPECT_EQ(json["boundary"]["loops"], capped.loops.size());
  EXPECT_EQ(json["boundary"]["remesh_loops"], capped.loops.size());
  const double fraction = json["boundary"]["cap_area_fraction"];
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 0.5);
  EXPECT_EQ(json["map"]["valid"], true);
  EXPECT_GT(json["distance"]["psnr_db"].get<double>(), 50.0);
  EXPECT_GT(json["map"]["efficiency_domain_to_surface"].get<double>(), 0.3);
}

// venus: one loop (the neck), 1199 faces; head_3holes: three (neck, eyes).
INSTANTIATE_TEST_SUITE_P(OpenGenusZero, GimRemeshOpenModel,
                         ::testing::Values(OpenCase{"venus", "surface-map"},
                                           OpenCase{"head_3holes", "surface-map"},
                                           OpenCase{"venus", "symmetric"},
                                           OpenCase{"head_3holes", "symmetric"}),
                         [](const auto& info) {
                           std::string name = std::string(info.param.name) + "_" + info.param.core;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
