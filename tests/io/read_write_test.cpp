// Every supported format round-trips through write_mesh/read_polygon_soup, and
// unreadable input fails with one message naming the file.
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace ism {
namespace {

namespace fs = std::filesystem;

TriangleMesh octahedron() {
  return domain::octahedron();
}

fs::path scratch(const std::string& name) {
  fs::path dir = test::binary_dir() / "test-scratch";
  fs::create_directories(dir);
  return dir / name;
}

TEST(MeshIo, EveryFormatRoundTrips) {
  for (const char* ext : {".obj", ".ply", ".off", ".stl"}) {
    SCOPED_TRACE(ext);
    const fs::path path = scratch(std::string("octahedron") + ext);
    io::write_mesh(octahedron(), path);
    const PreparedMesh p = prepare_mesh(io::read_polygon_soup(path));
    EXPECT_EQ(p.check.vertices, 6u);  // STL stores corners per face: welding rebuilds them
    EXPECT_EQ(p.check.faces, 8u);
    EXPECT_EQ(p.check.genus, 0);
    EXPECT_TRUE(p.check.closed());
    EXPECT_NEAR(p.check.area, 4 * std::sqrt(3.0), 1e-6);
    EXPECT_NEAR(signed_volume(p.mesh), 4.0 / 3.0, 1e-6);
  }
}

// Coordinates are rounded to single precision, every one of them: a
// per-vertex loop once left the last (n mod 4) vertices at double precision
// after GCC vectorised it, and the optimised maps moved with those bits.
TEST(MeshIo, EveryCoordinateIsReadAtSinglePrecision) {
  for (int n : {3, 4, 5, 6, 7, 11}) {
    SCOPED_TRACE(n);
    const fs::path path = scratch("precision.obj");
    {
      std::ofstream out(path);
      out.precision(17);
      for (int i = 0; i < n; ++i)
        out << "v " << 0.1 * (i + 1) << ' ' << 1.0 / (i + 3) << ' ' << -2.2 * i << '\n';
      out << "f 1 2 3\n";
    }
    const PolygonSoup soup = io::read_polygon_soup(path);
    ASSERT_EQ(soup.positions.size(), std::size_t(n));
    for (int i = 0; i < n; ++i) {
      const double expected[3] = {0.1 * (i + 1), 1.0 / (i + 3), -2.2 * i};
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(soup.positions[i][k], double(float(expected[k])))
            << "vertex " << i << " axis " << k;
    }
  }
}

TEST(MeshIo, AsciiPlyIsRead) {
  const fs::path path = scratch("ascii.ply");
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 4\n"
                         "property list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const MeshCheck c = prepare_mesh(io::read_polygon_soup(path)).check;
  EXPECT_EQ(c.vertices, 4u);
  EXPECT_EQ(c.faces, 4u);
  EXPECT_EQ(c.genus, 0);
}

TEST(MeshIo, TextureCoordinatesAndColoursAreRead) {
  // OBJ: 'v x y z r g b', 'vt', corners i/t, i/t/n and relative, a quad, a
  // face without coordinates after textured ones; the second copy of vertex
  // 1 (index 4) is welded to it.
  const fs::path obj = scratch("textured.obj");
  std::ofstream(obj) << "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 0.5 0.5 0.5\n"
                        "v 1 0 0 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                        "f 1/1 3/3 5/2\nf 1/1/1 2/2/1 4/4/1\nf -4/-3 -3/-2 -2/-1 1/1\n";
  const PolygonSoup soup = io::read_polygon_soup(obj);
  ASSERT_EQ(soup.colors.size(), 5u);
  EXPECT_EQ(soup.colors[3], Vec3(0.5, 0.5, 0.5));
  ASSERT_EQ(soup.texcoords.size(), 4u);
  ASSERT_EQ(soup.face_texcoords.size(), 3u);
  EXPECT_EQ(soup.face_texcoords[0], (std::vector<int>{0, 2, 1}));
  EXPECT_EQ(soup.face_texcoords[2], (std::vector<int>{1, 2, 3, 0}));
  // Where each triangle and vertex came from: the quad gives two triangles
  // of face 2; position 4 is vertex 1.
  const PreparedMesh prepared = prepare_mesh(soup);
  EXPECT_EQ(prepared.face_origin, (std::vector<int>{0, 1, 2, 2}));
  EXPECT_EQ(prepared.position_vertex, (std::vector<int>{0, 1, 2, 3, 1}));
  // A face without coordinates among textured ones: -1 at its corners; a
  // colour on some vertices only: none kept.
  const fs::path mixed = scratch("mixed.obj");
  std::ofstream(mixed) << "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n"
                          "f 1 2 3\nf 1/1 3/1 4/1\n";
  const PolygonSoup m = io::read_polygon_soup(mixed);
  EXPECT_TRUE(m.colors.empty());
  EXPECT_EQ(m.face_texcoords, (std::vector<std::vector<int>>{{-1, -1, -1}, {0, 0, 0}}));
  const fs::path bad = scratch("bad_vt.obj");
  std::ofstream(bad) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n";
  EXPECT_THROW(io::read_polygon_soup(bad), io::FileError);

  // PLY: 8-bit channels scaled by 1/255, float ones as they are.
  const fs::path ply = scratch("coloured.ply");
  std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nproperty uchar red\n"
                        "property uchar green\nproperty float blue\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0 255 0 0.25\n1 0 0 51 102 1\n0 1 0 0 0 0\n3 0 1 2\n";
  const PolygonSoup p = io::read_polygon_soup(ply);
  ASSERT_EQ(p.colors.size(), 3u);
  EXPECT_EQ(p.colors[0], Vec3(1, 0, 0.25));
  EXPECT_NEAR(p.colors[1].x(), 0.2, 1e-15);
  EXPECT_NEAR(p.colors[1].y(), 0.4, 1e-15);
  EXPECT_TRUE(io::read_polygon_soup(scratch("ascii.ply")).colors.empty());
}

TEST(MeshIo, MorphGlbHoldsTheMeshAndItsTarget) {
  const TriangleMesh m = octahedron();
  std::vector<Vec3> target = m.positions;
  for (Vec3& p : target) p *= 2;
  const fs::path path = scratch("morph.glb");
  io::write_morph_glb(m, target, path, "twice");
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GE(bytes.size(), 20u);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(bytes.substr(16, 4), "JSON");
  EXPECT_NE(bytes.find("\"targetNames\":[\"twice\"]"), std::string::npos);
  EXPECT_EQ(bytes.size() % 4, 0u);
  target.pop_back();
  EXPECT_THROW(io::write_morph_glb(m, target, path), std::invalid_argument);
}

TEST(MeshIo, StlIsWeldedIntoOneSurface) {
  const fs::path path = scratch("welded.stl");
  io::write_mesh(octahedron(), path);
  // The file stores three corners per facet; OpenMesh's STL reader or our
  // welding joins them back into one closed surface.
  const MeshCheck c = prepare_mesh(io::read_polygon_soup(path)).check;
  EXPECT_EQ(c.vertices, 6u);
  EXPECT_TRUE(c.valid_surface());
  EXPECT_TRUE(c.closed());
}

TEST(MeshIo, BadFilesGiveOneMessageNamingTheFile) {
  auto message_of = [](const fs::path& p) -> std::string {
    try {
      io::read_polygon_soup(p);
    } catch (const io::FileError& e) {
      return e.what();
    }
    return "";
  };
  const fs::path missing = scratch("missing.obj");
  fs::remove(missing);
  EXPECT_EQ(message_of(missing), missing.string() + ": no such file");
  const fs::path unknown = scratch("mesh.xyz");
  std::ofstream(unknown) << "nothing";
  EXPECT_NE(message_of(unknown).find("unsupported mesh format"), std::string::npos);
  const fs::path empty = scratch("empty.obj");
  std::ofstream(empty) << "# no faces\nv 0 0 0\n";
  EXPECT_NE(message_of(empty).find("no faces"), std::string::npos);
  const fs::path garbage = scratch("garbage.ply");
  std::ofstream(garbage) << "this is not a ply file\n";
  EXPECT_NE(message_of(garbage).find(garbage.string()), std::string::npos);
  const fs::path bad_index = scratch("bad_index.obj");
  std::ofstream(bad_index) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  EXPECT_NE(message_of(bad_index), "");
}

}  // namespace
}  // namespace ism
