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
