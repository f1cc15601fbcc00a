// ism-map as a user runs it: two surfaces (and pairs) in; the overlay pair,
// the correspondences both ways, the meta-mesh and a report out. The outputs
// are read back and checked here independently of the map code: the overlay
// pair has one connectivity, lies on both surfaces, covers each exactly once
// without a flipped triangle (a bijection); every correspondence row names a
// face of the target and weights summing to 1. Bad input: one line, a
// non-zero exit, no output file.
#include "gltf_validator.hpp"
#include "io/io.hpp"
#include "map/meta_mesh.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"
#include "open_surfaces.hpp"
#include "pipeline/map_surfaces.hpp"
#include "report/json.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"
#include "tools_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace {

namespace fs = std::filesystem;
using ism::TriangleMesh;
using ism::Vec3;
using ism::test::quoted;
using ism::test::report_number;
using ism::test::run_tool;
using ism::test::scratch_dir;
using ism::test::slurp;

struct Files {
  fs::path dir, sphere, blob, torus, disc;
};

const Files& files() {
  static const Files f = [] {
    Files out;
    out.dir = scratch_dir("map_tool");
    out.sphere = out.dir / "sphere.obj";
    out.blob = out.dir / "blob.obj";
    out.torus = out.dir / "torus.obj";
    out.disc = out.dir / "disc.obj";
    ism::io::write_mesh(ism::shapes::sphere(500), out.sphere);
    ism::io::write_mesh(ism::shapes::blob(700, 3), out.blob);
    ism::io::write_mesh(ism::shapes::torus(600), out.torus);
    const TriangleMesh disc =
        ism::test::keep_faces(ism::shapes::sphere(500), [](const Vec3& c) { return c.z() < 0.5; });
    ism::io::write_mesh(disc, out.disc);
    return out;
  }();
  return f;
}

fs::path text_file(const std::string& name, const std::string& text) {
  return ism::test::write_text(files().dir, name, text);
}

// An OBJ of `v` and `f` lines as the file holds it, every coordinate at
// double precision (the library's readers round coordinates to single
// precision, as the tools read their inputs).
TriangleMesh read_raw(const fs::path& p) {
  TriangleMesh m = ism::io::read_triangles_exact(p);
  EXPECT_FALSE(m.triangles.empty()) << p;
  return m;
}

// The surface as the tools read it (coordinates at single precision).
TriangleMesh read_input(const fs::path& p) {
  const ism::PolygonSoup soup = ism::io::read_polygon_soup(p);
  TriangleMesh m;
  m.positions = soup.positions;
  for (const auto& f : soup.faces) m.triangles.push_back({f[0], f[1], f[2]});
  return m;
}

// The overlay placed on `surface` (metrics' overlay_on_surface, nearest
// points only): every vertex on it, every triangle inside one face of it
// with that face's orientation, and the triangles' areas summing to the
// surface's, signed and unsigned (so no part of the surface is covered twice
// or left out).
void expect_overlay_on(const TriangleMesh& overlay, const TriangleMesh& surface, const char* name) {
  const ism::OverlayOnSurface on = ism::overlay_on_surface(overlay, surface);
  EXPECT_LT(on.largest_distance, 1e-9) << name << ": an overlay vertex off the surface";
  EXPECT_EQ(on.flipped, 0u) << name << ": overlay triangles flipped against their face";
  EXPECT_NEAR(on.signed_area / on.surface_area, 1, 1e-6) << name;
  EXPECT_NEAR(on.unsigned_area / on.surface_area, 1, 1e-6) << name;
  EXPECT_TRUE(on.bijective()) << name;
}

// One source vertex's rows: the target face's corners and their weights.
using Rows = std::array<std::pair<int, double>, 3>;

// Rows `i j w`, three per vertex of the source: j the corners of a face of
// the target, weights in [0, 1] summing to 1; returns the images (and the
// rows, when asked).
std::vector<Vec3> read_correspondence(const fs::path& p, std::size_t sources,
                                      const TriangleMesh& target,
                                      std::vector<Rows>* rows = nullptr) {
  std::set<std::array<int, 3>> faces;
  for (const auto& t : target.triangles) {
    std::array<int, 3> s{t[0], t[1], t[2]};
    std::sort(s.begin(), s.end());
    faces.insert(s);
  }
  std::ifstream in(p);
  std::vector<Vec3> images;
  std::size_t i;
  for (std::size_t v = 0; v < sources; ++v) {
    std::array<int, 3> j{};
    double sum = 0;
    Vec3 image = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      double w = -1;
      if (!(in >> i >> j[std::size_t(k)] >> w)) {
        ADD_FAILURE() << p << ": ends at vertex " << v;
        return images;
      }
      EXPECT_EQ(i, v);
      EXPECT_GE(w, 0);
      EXPECT_LE(w, 1);
      sum += w;
      image += w * target.positions[std::size_t(j[std::size_t(k)])];
      if (rows) {
        rows->resize(v + 1);
        (*rows)[v][std::size_t(k)] = {j[std::size_t(k)], w};
      }
    }
    EXPECT_NEAR(sum, 1, 1e-12);
    std::sort(j.begin(), j.end());
    EXPECT_TRUE(faces.count(j)) << p << ": vertex " << v << " not mapped into a face";
    images.push_back(image);
  }
  std::string rest;
  EXPECT_FALSE(in >> rest) << p << ": more rows than vertices";
  return images;
}

// The schedule: the thorough one below kLargeMapFaces faces together, the
// fast one from there (automatic), either when named; a level-sweep count
// or relaxation gain given is kept whatever the schedule.
TEST(IsmMap, ScheduleBySize) {
  using ism::pipeline::kLargeMapFaces;
  using ism::pipeline::map_schedule;
  using Kind = ism::pipeline::MapSurfacesOptions::ScheduleKind;
  const ism::pipeline::MapSurfacesOptions automatic;
  const auto small = map_schedule(kLargeMapFaces - 1, automatic);
  EXPECT_FALSE(small.fast);
  EXPECT_EQ(small.level_sweeps, 2);
  EXPECT_EQ(small.relaxation_gain, 1e-4);
  const auto large = map_schedule(kLargeMapFaces, automatic);
  EXPECT_TRUE(large.fast);
  EXPECT_EQ(large.level_sweeps, 1);
  EXPECT_EQ(large.relaxation_gain, 1e-3);
  ism::pipeline::MapSurfacesOptions named;
  named.schedule = Kind::thorough;
  EXPECT_FALSE(map_schedule(10 * kLargeMapFaces, named).fast);
  EXPECT_EQ(map_schedule(10 * kLargeMapFaces, named).level_sweeps, 2);
  named.schedule = Kind::fast;
  EXPECT_TRUE(map_schedule(1000, named).fast);
  EXPECT_EQ(map_schedule(1000, named).relaxation_gain, 1e-3);
  ism::pipeline::MapSurfacesOptions given;
  given.level_sweeps = 3;
  given.relaxation_gain = 0.0;
  for (const Kind kind : {Kind::automatic, Kind::thorough, Kind::fast}) {
    given.schedule = kind;
    for (std::size_t faces : {std::size_t(1000), kLargeMapFaces, 10 * kLargeMapFaces}) {
      const auto kept = map_schedule(faces, given);
      EXPECT_EQ(kept.level_sweeps, 3);
      EXPECT_EQ(kept.relaxation_gain, 0.0);
    }
  }
}

TEST(IsmMap, TwoGenusZeroSurfacesGiveABijectiveOverlayPair) {
  const Files& f = files();
  const fs::path prefix = f.dir / "sb", report = f.dir / "sb.json", meta = f.dir / "sb.meta";
  const auto pairs = text_file("sb_pairs.txt", "# sphere blob\n0 0\n100 300\n");
  const auto r = run_tool("ism-map", quoted(f.sphere) + " " + quoted(f.blob) + " --features " +
                                         quoted(pairs) + " -o " + quoted(prefix) + " --meta-mesh " +
                                         quoted(meta) + " --report " + quoted(report));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string json = slurp(report);
  const double efficiency = report_number(json, "symmetric_efficiency", "map");
  EXPECT_GT(efficiency, 0.9);
  EXPECT_LE(efficiency, 1);
  EXPECT_NEAR(report_number(json, "symmetric_dirichlet", "map"), 4 / efficiency, 1e-9);
  EXPECT_EQ(report_number(json, "features_given", "partition"), 2);
  EXPECT_EQ(report_number(json, "release_features_at", "map"), 0.5);  // the default
  EXPECT_EQ(report_number(json, "relaxation_gain", "map"), 1e-4);     // the default
  EXPECT_EQ(report_number(json, "level_sweeps", "map"), 2);           // (small inputs)
  EXPECT_EQ(nlohmann::json::parse(json)["map"]["schedule"], "thorough");
  {
    // The fast schedule named on a small pair, with a looser relaxation
    // queue than its own: fewer optimisations, a valid map.
    const auto loose = f.dir / "sb_loose.json";
    const auto l = run_tool(
        "ism-map", quoted(f.sphere) + " " + quoted(f.blob) + " --features " + quoted(pairs) +
                       " -q --schedule fast --relaxation-gain 0.01 --report " + quoted(loose));
    ASSERT_EQ(l.status, 0) << l.err;
    const std::string lj = slurp(loose);
    EXPECT_EQ(report_number(lj, "relaxation_gain", "map"), 0.01);  // given: kept
    EXPECT_EQ(report_number(lj, "level_sweeps", "map"), 1);        // the schedule's
    const auto lmap = nlohmann::json::parse(lj)["map"];
    EXPECT_EQ(lmap["schedule"], "fast");
    EXPECT_LT(report_number(lj, "optimizations", "map"),
              report_number(json, "optimizations", "map"));
    EXPECT_GT(report_number(lj, "symmetric_efficiency", "map"), 0.8);
  }
  // The coarse race (default 2,3): two copies, the more efficient kept.
  {
    const auto race = nlohmann::json::parse(json)["map"]["coarse_race"];
    ASSERT_EQ(race["efficiencies"].size(), 2u) << json;
    std::vector<double> e = race["efficiencies"].get<std::vector<double>>();
    const auto best = std::max_element(e.begin(), e.end()) - e.begin();
    EXPECT_EQ(race["kept"].get<int>(), int(best));
    EXPECT_GT(e[std::size_t(best)], 0.5);
  }
  // Peak memory at the end of every stage timed: never falling, at most the
  // run's peak.
  {
    const auto report_json = nlohmann::ordered_json::parse(json);  // (stages in order)
    const auto& peaks = report_json["peak_memory_mb_by_stage"];
    ASSERT_TRUE(peaks.is_object()) << json;
    double before = 0;
    for (const auto& [stage, seconds] : report_json["seconds"].items()) {
      if (stage == "total") continue;
      ASSERT_TRUE(peaks.contains(stage)) << stage;
      const double mb = peaks[stage].get<double>();
      EXPECT_GE(mb, before) << stage;
      before = mb;
    }
    EXPECT_GT(before, 0);
    EXPECT_LE(before, report_json["peak_memory_mb"].get<double>());
  }

  const TriangleMesh a = read_input(f.sphere), b = read_input(f.blob);
  const TriangleMesh on_a = read_raw(prefix.string() + "_on_A.obj"),
                     on_b = read_raw(prefix.string() + "_on_B.obj");
  ASSERT_EQ(on_a.triangles, on_b.triangles) << "the overlay pair's connectivity differs";
  ASSERT_EQ(on_a.n_vertices(), on_b.n_vertices());
  EXPECT_GT(on_a.n_faces(), a.n_faces() + b.n_faces());
  EXPECT_EQ(double(on_a.n_faces()), report_number(json, "triangles", "overlay"));
  expect_overlay_on(on_a, a, "on A");
  expect_overlay_on(on_b, b, "on B");
  // The overlay is a closed genus-0 surface itself.
  const auto check = ism::prepare_mesh(ism::io::read_polygon_soup(prefix.string() + "_on_A.obj"));
  EXPECT_TRUE(check.check.closed());
  EXPECT_EQ(check.check.genus, 0);

  std::vector<Rows> rows_a_to_b;
  const auto a_to_b =
      read_correspondence(prefix.string() + "_A_to_B.txt", a.n_vertices(), b, &rows_a_to_b);
  const auto b_to_a = read_correspondence(prefix.string() + "_B_to_A.txt", b.n_vertices(), a);
  // There and back: A's vertex v lies in the face of B named for it, whose
  // corners the other file sends back to A; v comes back as their images'
  // barycentric combination. The map is linear on the overlay's pieces, not
  // on B's faces, so the return is not exact, but (a convex combination) it
  // is never farther from v than the farthest corner's image, and with a
  // continuous map those are near v.
  {
    const double diagonal_a = ism::bounding_box_diagonal(a);
    double sum = 0, worst = 0;
    for (std::size_t v = 0; v < a.n_vertices(); ++v) {
      Vec3 back = Vec3::Zero();
      double farthest = 0;
      for (const auto& [j, w] : rows_a_to_b[v]) {
        back += w * b_to_a[std::size_t(j)];
        farthest = std::max(farthest, (b_to_a[std::size_t(j)] - a.positions[v]).norm());
      }
      const double error = (back - a.positions[v]).norm();
      EXPECT_LE(error, farthest + 1e-12 * diagonal_a) << v;
      sum += error;
      worst = std::max(worst, error);
    }
    EXPECT_LT(sum / double(a.n_vertices()), 0.006 * diagonal_a)
        << "mean A -> B -> A error";                                     // 0.0036
    EXPECT_LT(worst, 0.02 * diagonal_a) << "largest A -> B -> A error";  // 0.0061
  }
  // A's vertices are vertices of the overlay: their images on B are where
  // the overlay pair places them.
  ASSERT_EQ(a_to_b.size(), a.n_vertices());
  std::map<std::array<double, 3>, std::size_t> overlay_vertex;
  for (std::size_t v = 0; v < on_a.n_vertices(); ++v)
    overlay_vertex[{on_a.positions[v].x(), on_a.positions[v].y(), on_a.positions[v].z()}] = v;
  const double diagonal = ism::bounding_box_diagonal(b);
  std::size_t found = 0;
  for (std::size_t v = 0; v < a.n_vertices(); ++v) {
    const auto it =
        overlay_vertex.find({a.positions[v].x(), a.positions[v].y(), a.positions[v].z()});
    if (it == overlay_vertex.end()) continue;
    ++found;
    EXPECT_LT((on_b.positions[it->second] - a_to_b[v]).norm(), 1e-9 * diagonal) << v;
  }
  EXPECT_GT(found, a.n_vertices() * 9 / 10);
  EXPECT_EQ(b_to_a.size(), b.n_vertices());
  // The meta-mesh file reads back and validates from both sides.
  const ism::MetaMesh read = ism::read_meta_mesh(meta);
  EXPECT_FALSE(ism::validate(read));
}

// Rows of numbers (a field file as written).
std::vector<std::vector<double>> read_rows(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    rows.emplace_back();
    double x;
    while (words >> x) rows.back().push_back(x);
  }
  return rows;
}

TEST(IsmMap, HeldFeaturesMorphsAndFieldsCarriedBothWays) {
  const Files& f = files();
  const fs::path report = f.dir / "held.json", prefix = f.dir / "held";
  const auto pairs = text_file("held_pairs.txt", "0 0\n100 300\n250 20\n");
  const TriangleMesh a = read_input(f.sphere), b = read_input(f.blob);
  // Each surface's own coordinates as its field (written as read).
  std::array<fs::path, 2> field{f.dir / "field_a.txt", f.dir / "field_b.txt"};
  for (int s = 0; s < 2; ++s) {
    std::ofstream out(field[std::size_t(s)]);
    out << "# x y z\n";
    out.precision(17);
    for (const Vec3& p : (s ? b : a).positions)
      out << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  const auto r =
      run_tool("ism-map", quoted(f.sphere) + " " + quoted(f.blob) + " --features " + quoted(pairs) +
                              " --hold-features -q -o " + quoted(prefix) + " --report " +
                              quoted(report) + " --morph 0.5 --morph-frames 3 --transfer-field " +
                              quoted(field[0]) + " --transfer-field-b " + quoted(field[1]));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::string json = slurp(report);
  const std::size_t at = json.find("\"feature_residuals\"");
  ASSERT_NE(at, std::string::npos);
  for (const char* key : {"error_on_b", "error_on_a"}) {
    std::size_t from = at;
    for (int k = 0; k < 3; ++k) {
      from = json.find(std::string("\"") + key + "\": ", from);
      ASSERT_NE(from, std::string::npos);
      from += std::strlen(key) + 4;
      EXPECT_LT(std::strtod(json.c_str() + from, nullptr), 1e-12) << key << " " << k;
    }
  }
  const auto a_to_b = read_correspondence(prefix.string() + "_A_to_B.txt", a.n_vertices(), b);
  const auto b_to_a = read_correspondence(prefix.string() + "_B_to_A.txt", b.n_vertices(), a);
  EXPECT_LT((a_to_b[100] - b.positions[300]).norm(), 1e-12);
  EXPECT_LT((b_to_a[20] - a.positions[250]).norm(), 1e-12);

  // Frames from A to B: the overlay on A, half way, on B; --morph 0.5 is the
  // middle frame; every frame a closed surface.
  const TriangleMesh on_a = read_raw(prefix.string() + "_on_A.obj"),
                     on_b = read_raw(prefix.string() + "_on_B.obj");
  std::array<TriangleMesh, 3> frame;
  for (int k = 0; k < 3; ++k) {
    const fs::path p = prefix.string() + "_frame_00" + std::to_string(k) + ".obj";
    frame[std::size_t(k)] = read_raw(p);
    ASSERT_EQ(frame[std::size_t(k)].triangles, on_a.triangles) << p;
    EXPECT_TRUE(ism::prepare_mesh(ism::io::read_polygon_soup(p)).check.closed()) << p;
  }
  const TriangleMesh half = read_raw(prefix.string() + "_morph.obj");
  for (std::size_t v = 0; v < on_a.n_vertices(); ++v) {
    EXPECT_EQ(frame[0].positions[v], on_a.positions[v]);
    EXPECT_EQ(frame[2].positions[v], on_b.positions[v]);
    EXPECT_LT((frame[1].positions[v] - 0.5 * (on_a.positions[v] + on_b.positions[v])).norm(),
              1e-12);
    EXPECT_EQ(half.positions[v], frame[1].positions[v]);
  }

  // A's coordinates carried onto B's vertices are their images on A, and B's
  // onto A's their images on B; A's feature goes to B's and back exactly.
  const auto on_b_field = read_rows(prefix.string() + "_field_on_B.txt");
  const auto on_a_field = read_rows(prefix.string() + "_field_on_A.txt");
  ASSERT_EQ(on_b_field.size(), b.n_vertices());
  ASSERT_EQ(on_a_field.size(), a.n_vertices());
  for (std::size_t v = 0; v < b.n_vertices(); ++v)
    EXPECT_LT((Vec3(on_b_field[v][0], on_b_field[v][1], on_b_field[v][2]) - b_to_a[v]).norm(),
              1e-12);
  for (std::size_t v = 0; v < a.n_vertices(); ++v)
    EXPECT_LT((Vec3(on_a_field[v][0], on_a_field[v][1], on_a_field[v][2]) - a_to_b[v]).norm(),
              1e-12);
  const double diagonal = ism::bounding_box_diagonal(a);
  for (const auto& [ia, ib] : {std::pair{0, 0}, {100, 300}, {250, 20}})
    EXPECT_LT(
        (Vec3(on_b_field[ib][0], on_b_field[ib][1], on_b_field[ib][2]) - a.positions[ia]).norm(),
        1e-9 * diagonal);
}

// A sphere written with vertex colours ('v x y z r g b') and texture
// coordinates per corner: uv(p) on faces whose centroid has x <= 0.3, and
// uv(p) + (10, 0) on the others (a seam between two charts).
Vec3 colour_of(const Vec3& p) {
  return Vec3(0.5, 0.5, 0.5) + 0.2 * p;
}
std::array<double, 2> uv_of(const Vec3& p) {
  return {0.3 + 0.2 * p.x() + 0.1 * p.y(), 0.5 + 0.15 * p.z() - 0.05 * p.x()};
}
bool second_chart(const TriangleMesh& m, const ism::Triangle& t) {
  return (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]).x() / 3 > 0.3;
}

TEST(IsmMap, TexturesColoursAndAMorphTargetCarried) {
  const Files& f = files();
  const TriangleMesh a = read_input(f.sphere), b = read_input(f.blob);
  const fs::path textured = f.dir / "textured.obj", coloured = f.dir / "coloured_blob.ply",
                 prefix = f.dir / "attr", report = f.dir / "attr.json";
  {
    std::ofstream out(textured);
    out.precision(17);
    for (const Vec3& p : a.positions) {
      const Vec3 c = colour_of(p);
      out << "v " << p.x() << " " << p.y() << " " << p.z() << " " << c.x() << " " << c.y() << " "
          << c.z() << "\n";
    }
    for (int chart = 0; chart < 2; ++chart)
      for (const Vec3& p : a.positions) {
        const auto uv = uv_of(p);
        out << "vt " << uv[0] + 10 * chart << " " << uv[1] << "\n";
      }
    for (const auto& t : a.triangles) {
      const std::size_t offset = second_chart(a, t) ? a.n_vertices() : 0;
      out << "f";
      for (int v : t) out << " " << v + 1 << "/" << offset + std::size_t(v) + 1;
      out << "\n";
    }
  }
  // B with 8-bit colours, a function of position.
  std::vector<ism::io::Rgb> b_colours;
  for (const Vec3& p : b.positions) {
    const Vec3 c = 255 * colour_of(p).cwiseMax(0).cwiseMin(1);
    b_colours.push_back({static_cast<unsigned char>(c.x()), static_cast<unsigned char>(c.y()),
                         static_cast<unsigned char>(c.z())});
  }
  ism::io::write_colored_ply(b, b_colours, {}, coloured);
  const auto pairs = text_file("attr_pairs.txt", "0 0\n100 300\n");
  const auto r = run_tool("ism-map", quoted(textured) + " " + quoted(coloured) + " --features " +
                                         quoted(pairs) + " -q -o " + quoted(prefix) + " --report " +
                                         quoted(report) +
                                         " --transfer-uv --transfer-colors --transfer-colors-b "
                                         "--morph-glb --morph-frames 2");
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<Rows> a_to_b, b_to_a;
  read_correspondence(prefix.string() + "_A_to_B.txt", a.n_vertices(), b, &a_to_b);
  const auto b_images =
      read_correspondence(prefix.string() + "_B_to_A.txt", b.n_vertices(), a, &b_to_a);

  // Texture coordinates on B: uv of the image, in the chart of the face of A
  // holding it; B's triangles whose corners land in both charts counted.
  std::map<std::array<int, 3>, bool> chart_of_face;
  for (const auto& t : a.triangles) {
    std::array<int, 3> key{t[0], t[1], t[2]};
    std::sort(key.begin(), key.end());
    chart_of_face[key] = second_chart(a, t);
  }
  auto chart_of = [&](const Rows& rows) {
    std::array<int, 3> key{rows[0].first, rows[1].first, rows[2].first};
    std::sort(key.begin(), key.end());
    return chart_of_face.at(key);
  };
  const ism::PolygonSoup with_uv = ism::io::read_polygon_soup(prefix.string() + "_B_uv.obj");
  ASSERT_EQ(with_uv.positions.size(), b.n_vertices());
  ASSERT_EQ(with_uv.texcoords.size(), b.n_vertices());
  ASSERT_EQ(with_uv.faces.size(), b.n_faces());
  for (std::size_t t = 0; t < b.n_faces(); ++t)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(with_uv.faces[t][std::size_t(k)], b.triangles[t][std::size_t(k)]);
      EXPECT_EQ(with_uv.face_texcoords[t][std::size_t(k)], b.triangles[t][std::size_t(k)]);
    }
  for (std::size_t v = 0; v < b.n_vertices(); ++v) {
    auto expected = uv_of(b_images[v]);
    if (chart_of(b_to_a[v])) expected[0] += 10;
    EXPECT_NEAR(with_uv.texcoords[v][0], expected[0], 1e-9) << v;
    EXPECT_NEAR(with_uv.texcoords[v][1], expected[1], 1e-9) << v;
  }
  std::size_t seams = 0;
  for (const auto& t : b.triangles)
    seams += chart_of(b_to_a[std::size_t(t[0])]) != chart_of(b_to_a[std::size_t(t[1])]) ||
             chart_of(b_to_a[std::size_t(t[0])]) != chart_of(b_to_a[std::size_t(t[2])]);
  EXPECT_GT(seams, 0u);
  const std::string json = slurp(report);
  EXPECT_EQ(report_number(json, "uv_seam_triangles_on_B", "transfer"), double(seams));

  // Colours both ways, each within rounding to 8 bits of the interpolated
  // source colours.
  const ism::PolygonSoup b_painted = ism::io::read_polygon_soup(prefix.string() + "_B_colors.ply");
  ASSERT_EQ(b_painted.colors.size(), b.n_vertices());
  for (std::size_t v = 0; v < b.n_vertices(); ++v) {
    Vec3 expected = Vec3::Zero();
    for (const auto& [j, w] : b_to_a[v]) expected += w * colour_of(a.positions[std::size_t(j)]);
    EXPECT_LT((b_painted.colors[v] - expected).cwiseAbs().maxCoeff(), 0.5 / 255 + 1e-9) << v;
  }
  const ism::PolygonSoup a_painted = ism::io::read_polygon_soup(prefix.string() + "_A_colors.ply");
  ASSERT_EQ(a_painted.colors.size(), a.n_vertices());
  for (std::size_t v = 0; v < a.n_vertices(); ++v) {
    Vec3 expected = Vec3::Zero();
    for (const auto& [j, w] : a_to_b[v])
      for (int c = 0; c < 3; ++c)
        expected[c] += w * b_colours[std::size_t(j)][std::size_t(c)] / 255.0;
    EXPECT_LT((a_painted.colors[v] - expected).cwiseAbs().maxCoeff(), 0.5 / 255 + 1e-9) << v;
  }

  // The morph target pair: the overlay on A, and on B as its one target (as
  // displacements), in single precision; indices the overlay's faces.
  const TriangleMesh on_a = read_raw(prefix.string() + "_on_A.obj"),
                     on_b = read_raw(prefix.string() + "_on_B.obj");
  const fs::path glb = prefix.string() + "_morph.glb";
  const std::string bytes = slurp(glb);
  ASSERT_GE(bytes.size(), 28u);
  std::uint32_t head[5];
  std::memcpy(head, bytes.data(), sizeof head);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(head[1], 2u);
  EXPECT_EQ(head[2], bytes.size());
  const auto gltf = ism::Json::parse(bytes.substr(20, head[3]));
  const std::size_t bin = 20 + head[3] + 8;
  const auto& primitive = gltf["meshes"][0]["primitives"][0];
  const auto& accessors = gltf["accessors"];
  auto floats = [&](int accessor) {
    const auto& view = gltf["bufferViews"][accessors[accessor]["bufferView"].get<int>()];
    std::vector<Vec3> out(accessors[accessor]["count"].get<std::size_t>());
    for (std::size_t v = 0; v < out.size(); ++v) {
      float xyz[3];
      std::memcpy(xyz, bytes.data() + bin + view["byteOffset"].get<std::size_t>() + 12 * v, 12);
      out[v] = Vec3(xyz[0], xyz[1], xyz[2]);
    }
    return out;
  };
  const auto base = floats(primitive["attributes"]["POSITION"].get<int>());
  const auto moved = floats(primitive["targets"][0]["POSITION"].get<int>());
  ASSERT_EQ(base.size(), on_a.n_vertices());
  ASSERT_EQ(moved.size(), on_a.n_vertices());
  for (std::size_t v = 0; v < base.size(); ++v) {
    EXPECT_LT((base[v] - on_a.positions[v]).norm(), 1e-6) << v;
    EXPECT_LT((base[v] + moved[v] - on_b.positions[v]).norm(), 1e-6) << v;
  }
  const auto& indices = accessors[primitive["indices"].get<int>()];
  ASSERT_EQ(indices["count"].get<std::size_t>(), 3 * on_a.n_faces());
  const auto& index_view = gltf["bufferViews"][indices["bufferView"].get<int>()];
  for (std::size_t t = 0; t < on_a.n_faces(); ++t)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t i;
      std::memcpy(
          &i, bytes.data() + bin + index_view["byteOffset"].get<std::size_t>() + 12 * t + 4 * k, 4);
      EXPECT_EQ(int(i), on_a.triangles[t][std::size_t(k)]);
    }

  // The written meshes read back through ism-info: closed, of the inputs' genus.
  for (const char* name : {"_B_uv.obj", "_B_colors.ply", "_A_colors.ply", "_frame_001.obj"}) {
    const auto info = run_tool("ism-info", quoted(fs::path(prefix.string() + name)) + " --json");
    ASSERT_EQ(info.status, 0) << name << ": " << info.err;
    EXPECT_NE(info.out.find("\"closed\": true"), std::string::npos) << name;
    EXPECT_NE(info.out.find("\"genus\": 0"), std::string::npos) << name;
  }
  ISM_REQUIRE_GLTF_VALIDATOR();
  ISM_EXPECT_VALID_GLTF(std::vector<fs::path>({glb}), f.dir / "morph_validator.log");
}

// One line on stderr, a non-zero status, and none of the outputs.
void expect_refusal(const std::string& args, const std::string& words) {
  const Files& f = files();
  const fs::path prefix = f.dir / "refused", meta = f.dir / "refused.meta",
                 report = f.dir / "refused.json";
  std::vector<fs::path> outputs = {meta, report};
  for (const char* s : {"_on_A.obj", "_on_B.obj", "_A_to_B.txt", "_B_to_A.txt"})
    outputs.push_back(prefix.string() + s);
  for (const auto& p : outputs) fs::remove(p);
  const auto r = run_tool("ism-map", args + " -o " + quoted(prefix) + " --meta-mesh " +
                                         quoted(meta) + " --report " + quoted(report));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  for (const auto& p : outputs) EXPECT_FALSE(fs::exists(p)) << p;
}

TEST(IsmMap, RefusesBadInput) {
  const Files& f = files();
  const std::string two = quoted(f.sphere) + " " + quoted(f.blob);
  expect_refusal(quoted(f.sphere) + " " + quoted(f.torus), "genus");
  expect_refusal(quoted(f.sphere) + " " + quoted(f.disc), "boundary loop");
  expect_refusal(two + " --features " + quoted(text_file("range.txt", "1 2\n3 999999\n")),
                 "range.txt:2: vertex index 999999");
  expect_refusal(two + " --features " + quoted(text_file("empty.txt", "# none\n")),
                 "no feature pairs");
  expect_refusal(two + " --features " + quoted(f.dir / "missing.txt"), "missing.txt");
  expect_refusal(quoted(f.sphere) + " " + quoted(f.dir / "missing.obj"), "missing.obj");
  expect_refusal(two + " --transfer-field " + quoted(text_file("short.txt", "1\n2\n")),
                 "short.txt: 2 rows, the mesh has");
  expect_refusal(two + " --transfer-field " + quoted(text_file("ragged.txt", "1 2\n3\n")),
                 "ragged.txt:2: 1 values, the first row has 2");
  expect_refusal(two + " --release-features-at 2", "--release-features-at takes a fraction");
  expect_refusal(two + " --transfer-uv",
                 "sphere.obj: cannot carry its texture coordinates: no "
                 "texture coordinates (vt)");
  expect_refusal(two + " --transfer-colors-b", "blob.obj: cannot carry its colours: no vertex");
  expect_refusal(two + " --race-level-sweeps 2,2000", "--race-level-sweeps");
  expect_refusal(two + " --relaxation-gain -1", "--relaxation-gain takes a share");
  // (The command line refused by its parser: one line too.)
  expect_refusal(two + " --schedule quick", "--schedule: quick not in {auto,thorough,fast}");
  expect_refusal(two + " --level-sweeps many", "--level-sweeps");
  expect_refusal(two + " --morph-frames 1", "--morph-frames takes 2 to 10000 frames (got 1)");
  expect_refusal(two + " --morph 0.5 --morph-frames 20000", "(got 20000)");
  // An output over an input is refused before any work, the input intact.
  const std::string before = slurp(f.blob);
  const auto r = run_tool("ism-map", two + " --meta-mesh " + quoted(f.blob));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(slurp(f.blob), before);
}

}  // namespace
