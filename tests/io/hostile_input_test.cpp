// The readers on hostile files (tests/data/hostile): every file is read or
// refused with one FileError line naming it, never a crash, hang or an
// allocation the file cannot back; the fuzzers' seeds read back as the
// meshes they are; declared sizes are upper bounds.
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "map/meta_mesh.hpp"
#include "mesh/mesh_check.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace ism {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> files_in(const fs::path& dir, const std::string& prefix = "") {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().rfind(prefix, 0) == 0) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The message of the FileError `read` throws, or "" when it reads.
template <class Read>
std::string refusal(Read read) {
  try {
    read();
  } catch (const io::FileError& e) {
    return e.what();
  }
  return "";
}

struct Expected {
  const char* file;
  const char* message;  // part of the refusal; nullptr: the file reads
};

// Each regression file and what the reader says of it.
constexpr Expected kMeshFiles[] = {
    {"obj_all_coincident.obj", nullptr},  // reads; the mesh checks name it
    {"obj_continuation_at_eof.obj", nullptr},
    {"obj_index_overflow.obj", ":4: '99999999999999999999' is not a vertex index"},
    {"obj_nan.obj", nullptr},
    {"obj_relative_before_first.obj", ":1: relative index -1 before the first vertex"},
    {"obj_tetrahedron.obj", nullptr},
    {"obj_utf16_bom.obj", "UTF-16"},
    {"obj_utf8_bom.obj", nullptr},
    {"obj_zero_area.obj", nullptr},
    {"off_2e9_vertices.off", "declares 2000000000 vertices"},
    {"off_binary_truncated.off", "declares 6 vertices, more than the 24 bytes"},
    {"off_face_count_lie.off", "a face of 200000000 vertices lists fewer"},
    {"off_fused_modelnet.off", nullptr},
    {"off_negative_counts.off", ":2: negative count (-3 vertices, -1 faces)"},
    {"ply_face_list_bomb.ply", "list length 4000000000 out of range"},
    {"ply_negative_index.ply", "vertex index -7 out of range"},
    {"ply_no_end_header.ply", "the file ends inside the PLY header"},
    {"ply_random_after_header.ply", ":3: unknown PLY header line"},
    {"ply_truncated_binary.ply", "declares 100 vertex elements"},
    {"ply_vertex_count_bomb.ply", "declares 4000000000 vertex elements"},
    {"stl_count_bomb.stl", "declares 4294967295 triangles"},
    {"stl_solid_garbage.stl", "the file has no faces"},
};

TEST(HostileInput, EveryMeshFileIsReadOrRefusedInOneLineNamingIt) {
  std::size_t mesh_files = 0;
  for (const fs::path& path : files_in(test::hostile_dir()))
    if (io::is_readable_mesh_extension(path)) ++mesh_files;
  EXPECT_EQ(mesh_files, std::size(kMeshFiles)) << "a regression file without an expectation";
  for (const Expected& e : kMeshFiles) {
    SCOPED_TRACE(e.file);
    const fs::path path = test::hostile_dir() / e.file;
    ASSERT_TRUE(fs::exists(path));
    PolygonSoup soup;
    const std::string message = refusal([&] { soup = io::read_polygon_soup(path); });
    if (!e.message) {
      EXPECT_EQ(message, "");
      for (const auto& face : soup.faces)
        for (int v : face) EXPECT_LT(std::size_t(v), soup.positions.size());
      continue;
    }
    EXPECT_EQ(message.rfind(path.string(), 0), 0u) << message;
    EXPECT_NE(message.find(e.message), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "unprintable byte in " << message;
  }
}

TEST(HostileInput, ReadableRegressionFilesAreTheMeshesTheyClaim) {
  // A UTF-8 byte-order mark and ModelNet's fused "OFF6 8 0": the octahedron.
  for (const char* file : {"obj_utf8_bom.obj", "off_fused_modelnet.off"}) {
    SCOPED_TRACE(file);
    const MeshCheck c = prepare_mesh(io::read_polygon_soup(test::hostile_dir() / file)).check;
    EXPECT_EQ(c.vertices, 6u);
    EXPECT_EQ(c.faces, 8u);
    EXPECT_EQ(c.genus, 0);
    EXPECT_TRUE(c.valid_surface());
  }
  // Degenerate geometry is named, not passed as a surface.
  const MeshCheck line =
      prepare_mesh(io::read_polygon_soup(test::hostile_dir() / "obj_zero_area.obj")).check;
  EXPECT_FALSE(line.valid_surface());
  EXPECT_TRUE(line.collinear);
  const MeshCheck point =
      prepare_mesh(io::read_polygon_soup(test::hostile_dir() / "obj_all_coincident.obj")).check;
  EXPECT_FALSE(point.valid_surface());
  ASSERT_FALSE(point.defects().empty());
  EXPECT_NE(point.defects().front().find("every vertex is at one point"), std::string::npos);
}

TEST(HostileInput, FeatureFilesAreRefusedInOneLine) {
  const TriangleMesh octahedron = domain::octahedron();
  const std::pair<const char*, const char*> cases[] = {
      {"features_nan.txt", ":3: 'nan' is not a finite number"},
      {"features_huge_index.txt", ":3: 1e+300 is not a vertex index"},
      {"features_inf_point.txt", ":6: '1e308' is"},  // finite, but snapped: see below
      {"features_too_many.txt", "50 features, more than the surface's 6 vertices"},
      {"features_grid_overflow.txt", "outside the"},
  };
  for (const auto& [file, expected] : cases) {
    SCOPED_TRACE(file);
    const fs::path path = test::hostile_dir() / file;
    const std::string message = refusal(
        [&] { io::resolve_features(io::read_feature_file(path), octahedron, 3, path.string()); });
    if (std::string(file) == "features_inf_point.txt") {
      // Large but finite: it snaps to a vertex (the distances overflow to infinity).
      EXPECT_EQ(message, "");
      const auto features =
          io::resolve_features(io::read_feature_file(path), octahedron, 0, path.string());
      for (int v : features) EXPECT_GE(v, 0);
      continue;
    }
    EXPECT_EQ(message.rfind(path.string(), 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(HostileInput, MetaMeshFilesFoundByFuzzingAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      // "mesh 0 623730951 ..." asked for 29 GB of vertex locations.
      {"meta_mesh_oom_vertices.txt", "bad mesh line"},
      // Mesh 1 missing: validate() passed an empty meta-mesh and measures() threw.
      {"meta_mesh_empty_side.txt", "bad mesh line"},
  };
  for (const auto& [file, expected] : cases) {
    SCOPED_TRACE(file);
    const fs::path path = test::hostile_dir() / file;
    const std::string message = refusal([&] { read_meta_mesh(path); });
    EXPECT_EQ(message.rfind(path.string() + ":2: ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(HostileInput, MetaMeshCountsAreCheckedAgainstTheFileSize) {
  const fs::path path = test::binary_dir() / "test-scratch" / "meta_mesh_bomb.txt";
  fs::create_directories(path.parent_path());
  std::ofstream(path) << "ism-meta-mesh 1\nmesh 0 100000000 8\n";
  const std::string message = refusal([&] { read_meta_mesh(path); });
  EXPECT_NE(message.find("declares 100000000 vertices and 8 faces, more than the file's"),
            std::string::npos)
      << message;
}

TEST(HostileInput, FuzzSeedsReadBackAsTheirMeshes) {
  // Every seed of the mesh readers is a closed genus-0 surface: a
  // tetrahedron (4 vertices) or a cube of quads (8).
  for (const char* target : {"obj", "off", "ply", "stl"})
    for (const fs::path& path : files_in(test::fuzz_corpus_dir(target))) {
      SCOPED_TRACE(path.string());
      const io::MeshFileSize declared = io::peek_mesh_size(path);
      const PolygonSoup soup = io::read_polygon_soup(path);
      EXPECT_LE(soup.positions.size(), declared.vertices);
      EXPECT_LE(soup.faces.size(), declared.faces);
      EXPECT_FALSE(declared.capped);
      const MeshCheck c = prepare_mesh(soup).check;
      EXPECT_TRUE(c.valid_surface());
      EXPECT_EQ(c.genus, 0);
      EXPECT_TRUE(c.closed());
      EXPECT_TRUE(c.vertices == 4 || c.vertices == 8) << c.vertices;
    }
  for (const fs::path& path : files_in(test::fuzz_corpus_dir("features")))
    EXPECT_EQ(io::read_feature_file(path).size(), 6u) << path;
  for (const fs::path& path : files_in(test::fuzz_corpus_dir("meta_mesh"))) {
    SCOPED_TRACE(path.string());
    const auto error = validate(read_meta_mesh(path));
    EXPECT_FALSE(error) << *error;
  }
}

TEST(HostileInput, DeclaredSizesOfBombsAreBoundedByTheFile) {
  // peek_mesh_size caps a header's claim by what the file's bytes can hold.
  const io::MeshFileSize off = io::peek_mesh_size(test::hostile_dir() / "off_2e9_vertices.off");
  EXPECT_LE(off.vertices, off.bytes);
  EXPECT_TRUE(off.capped);
  const io::MeshFileSize stl = io::peek_mesh_size(test::hostile_dir() / "stl_count_bomb.stl");
  EXPECT_LE(stl.faces, stl.bytes / 40);
  const io::MeshFileSize ply =
      io::peek_mesh_size(test::hostile_dir() / "ply_vertex_count_bomb.ply");
  EXPECT_LE(ply.vertices, ply.bytes);
  EXPECT_TRUE(ply.capped);
}

}  // namespace
}  // namespace ism
