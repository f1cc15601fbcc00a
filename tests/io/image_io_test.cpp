// Geometry images (float EXR), PNG previews, Draco meshes and glTF binaries
// survive a round trip, and bad files fail with a FileError naming the file.
#include "io/image_io.hpp"
#include "gltf_validator.hpp"
#include "io/draco_io.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "report/json.hpp"
#include "test_support.hpp"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>

namespace ism {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  fs::path dir = test::binary_dir() / "test-scratch";
  fs::create_directories(dir);
  return dir / name;
}

// Runs f, expects a FileError and returns its message.
template <class F>
std::string file_error_message(F&& f) {
  try {
    f();
  } catch (const io::FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no FileError thrown";
  return {};
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

// ---------------------------------------------------------------- OpenEXR

TEST(ExrIo, FloatRoundTripIsBitExactWithAttributes) {
  const int n = 4;
  std::vector<Eigen::Vector3f> pixels;
  for (int i = 0; i < n * n; ++i)
    pixels.emplace_back(std::sin(0.37f * i), -1e-3f * i * i, 12345.678f / (i + 1));
  // Values that a half or lossy path would change.
  pixels[0] = {std::numeric_limits<float>::denorm_min(), -0.0f, std::numeric_limits<float>::max()};
  pixels[1] = {0.1f, 1.0f / 3.0f, std::numeric_limits<float>::quiet_NaN()};
  const io::ExrAttributes attributes = {{"ism:layout", "octahedral"}, {"ism:version", "0.1.0"}};
  const fs::path path = scratch("geometry_image.exr");
  io::write_exr_rgb(path, n, n, pixels, attributes);

  int width = 0, height = 0;
  io::ExrAttributes read_attributes;
  const auto back = io::read_exr_rgb(path, width, height, &read_attributes);
  ASSERT_EQ(width, n);
  ASSERT_EQ(height, n);
  ASSERT_EQ(back.size(), pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_TRUE(same_bits(back[i][c], pixels[i][c])) << "pixel " << i << " channel " << c;
  const std::map<std::string, std::string> found(read_attributes.begin(), read_attributes.end());
  EXPECT_EQ(found.at("ism:layout"), "octahedral");
  EXPECT_EQ(found.at("ism:version"), "0.1.0");

  // The attributes are optional on the way in and out.
  io::write_exr_rgb(path, n, n, pixels);
  EXPECT_EQ(io::read_exr_rgb(path, width, height).size(), pixels.size());
}

TEST(ExrIo, AlphaChannelRoundTripsBitExactAndIsAbsentUnlessWritten) {
  const int width = 5, height = 3;
  std::vector<Eigen::Vector3f> pixels;
  std::vector<float> alpha;
  for (int i = 0; i < width * height; ++i) {
    pixels.emplace_back(float(i), -float(i), 0.5f * float(i));
    alpha.push_back(i % 3 == 0 ? 0.0f : (i % 3 == 1 ? 1.0f : 0.25f));
  }
  const fs::path path = scratch("alpha.exr");
  io::write_exr_rgb(path, width, height, pixels, {}, alpha);
  int w = 0, h = 0;
  std::vector<float> back_alpha;
  const auto back = io::read_exr_rgb(path, w, h, nullptr, &back_alpha);
  ASSERT_EQ(back_alpha.size(), alpha.size());
  for (std::size_t i = 0; i < alpha.size(); ++i) {
    EXPECT_TRUE(same_bits(back_alpha[i], alpha[i])) << i;
    EXPECT_TRUE(same_bits(back[i][0], pixels[i][0])) << i;
  }
  // OpenImageIO sees four channels, the fourth named A.
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 4);
  EXPECT_EQ(in->spec().channelnames.at(3), "A");
  in->close();
  // Without alpha: three channels, and the reader leaves alpha empty.
  io::write_exr_rgb(path, width, height, pixels);
  io::read_exr_rgb(path, w, h, nullptr, &back_alpha);
  EXPECT_TRUE(back_alpha.empty());
  EXPECT_THROW(io::write_exr_rgb(path, width, height, pixels, {}, std::vector<float>(3, 1.0f)),
               std::invalid_argument);
}

TEST(ExrIo, NonSquareKeepsRowMajorTopRowFirst) {
  const int width = 3, height = 5;
  std::vector<Eigen::Vector3f> pixels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) pixels.emplace_back(x, y, x + 10.0f * y);
  const fs::path path = scratch("non_square.exr");
  io::write_exr_rgb(path, width, height, pixels);

  int w = 0, h = 0;
  const auto back = io::read_exr_rgb(path, w, h);
  EXPECT_EQ(w, width);
  EXPECT_EQ(h, height);
  ASSERT_EQ(back.size(), pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) EXPECT_EQ(back[i], pixels[i]) << i;
  // Cross-check the orientation with an independent reader: OIIO's row 0 is the top.
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  std::vector<float> rgb(width * height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.data()));
  EXPECT_EQ(rgb[(1 * width + 2) * 3 + 2], 12.0f);  // x = 2, y = 1
}

TEST(ExrIo, WrongPixelCountIsRejected) {
  const std::vector<Eigen::Vector3f> pixels(5);
  EXPECT_THROW(io::write_exr_rgb(scratch("bad.exr"), 2, 3, pixels), std::invalid_argument);
  EXPECT_THROW(io::write_exr_rgb(scratch("bad.exr"), 0, 0, {}), std::invalid_argument);
  // A standard attribute of another type cannot be replaced by a string.
  EXPECT_THROW(io::write_exr_rgb(scratch("bad.exr"), 5, 1, pixels, {{"compression", "zip"}}),
               std::invalid_argument);
}

TEST(ExrIo, MissingFileThrowsNamingIt) {
  const fs::path path = scratch("does_not_exist.exr");
  fs::remove(path);
  int w, h;
  EXPECT_NE(file_error_message([&] { io::read_exr_rgb(path, w, h); }).find(path.string()),
            std::string::npos);
}

TEST(ExrIo, NonExrFileThrowsNamingIt) {
  const fs::path path = scratch("not_an_image.exr");
  std::ofstream(path) << "this is not an OpenEXR file\n";
  int w, h;
  const std::string message = file_error_message([&] { io::read_exr_rgb(path, w, h); });
  EXPECT_EQ(message.rfind(path.string(), 0), 0u) << message;
}

TEST(ExrIo, MissingChannelThrows) {
  // An EXR whose channels are X, Y, Z instead of R, G, B, written by OIIO.
  const fs::path path = scratch("xyz_channels.exr");
  OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"X", "Y", "Z"};
  const std::vector<float> data(12, 1.0f);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
  ASSERT_TRUE(out->close());
  int w, h;
  const std::string message = file_error_message([&] { io::read_exr_rgb(path, w, h); });
  EXPECT_NE(message.find(path.string()), std::string::npos);
  EXPECT_NE(message.find("channel R"), std::string::npos) << message;
}

TEST(ExrIo, HostileFilesFoundByFuzzingAreRefusedBeforeOpenExrAllocates) {
  // exr_oom_attribute: OpenEXR allocated 1.7 GB for an attribute whose type
  // name runs into the next attribute; exr_chlist_overrun: a channel list
  // running past its declared size, after which OpenEXR parsed a 1.9 GB
  // opaque attribute that a size-based reading never sees.
  const std::pair<const char*, const char*> cases[] = {
      {"exr_oom_attribute.exr", "has no type"},
      {"exr_chlist_overrun.exr", "not terminated or too long"},
  };
  for (const auto& [file, expected] : cases) {
    SCOPED_TRACE(file);
    const fs::path path = test::hostile_dir() / file;
    int w = 0, h = 0;
    const std::string message = file_error_message([&] { io::read_exr_rgb(path, w, h); });
    EXPECT_EQ(message.rfind(path.string() + ": cannot read OpenEXR: ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(ExrIo, DataWindowBeyondTheFileIsRefused) {
  // A valid 2x2 image whose data window is widened to 65536 x 65536 pixels.
  const fs::path path = scratch("window_bomb.exr");
  io::write_exr_rgb(path, 2, 2, std::vector<Eigen::Vector3f>(4, Eigen::Vector3f(1, 2, 3)));
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t at = bytes.find("dataWindow");
  ASSERT_NE(at, std::string::npos);
  const std::size_t box = at + std::strlen("dataWindow") + 1 + std::strlen("box2i") + 1 + 4;
  const std::int32_t max = 65535;
  std::memcpy(&bytes[box + 8], &max, 4);
  std::memcpy(&bytes[box + 12], &max, 4);
  std::ofstream(path, std::ios::binary) << bytes;
  int w = 0, h = 0;
  const std::string message = file_error_message([&] { io::read_exr_rgb(path, w, h); });
  EXPECT_NE(message.find("65536x65536 pixels"), std::string::npos) << message;
}

TEST(ExrIo, FuzzSeedsInEveryCompressionReadBack) {
  // One 5x5 geometry image saved with each of OpenEXR's compressions (and
  // tiled): the lossless ones read back bit for bit, the lossy ones close.
  int w = 0, h = 0;
  const auto reference = io::read_exr_rgb(test::fuzz_corpus_dir("exr") / "zip.exr", w, h);
  ASSERT_EQ(w, 5);
  ASSERT_EQ(h, 5);
  for (const auto& entry : fs::directory_iterator(test::fuzz_corpus_dir("exr"))) {
    SCOPED_TRACE(entry.path().string());
    const std::string stem = entry.path().stem().string();
    const auto pixels = io::read_exr_rgb(entry.path(), w, h);
    ASSERT_EQ(w, 5);
    ASSERT_EQ(h, 5);
    const bool lossy = stem == "b44" || stem == "dwaa" || stem == "pxr24";
    for (std::size_t i = 0; i < pixels.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (lossy)
          EXPECT_NEAR(pixels[i][k], reference[i][k], 1e-2);
        else
          EXPECT_TRUE(same_bits(pixels[i][k], reference[i][k]));
  }
}

TEST(ExrIo, UnwritablePathThrows) {
  const fs::path path = scratch("no_such_dir") / "sub" / "x.exr";
  const std::vector<Eigen::Vector3f> pixels(1);
  EXPECT_NE(file_error_message([&] { io::write_exr_rgb(path, 1, 1, pixels); }).find(path.string()),
            std::string::npos);
}

// ---------------------------------------------------------------- PNG

TEST(PngIo, PreviewIsReadableBack) {
  const int width = 4, height = 3;
  std::vector<std::array<unsigned char, 3>> pixels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      pixels.push_back({static_cast<unsigned char>(60 * x), static_cast<unsigned char>(100 * y),
                        static_cast<unsigned char>(7)});
  const fs::path path = scratch("preview.png");
  io::write_png_preview(path, width, height, pixels);

  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_STREQ(in->format_name(), "png");
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.width, width);
  EXPECT_EQ(spec.height, height);
  ASSERT_EQ(spec.nchannels, 3);
  std::vector<unsigned char> back(width * height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data()));
  const int x = 3, y = 2;
  for (int c = 0; c < 3; ++c) EXPECT_EQ(back[(y * width + x) * 3 + c], pixels[y * width + x][c]);
}

TEST(PngIo, FailuresThrow) {
  const std::vector<std::array<unsigned char, 3>> pixels(4);
  EXPECT_THROW(io::write_png_preview(scratch("bad.png"), 3, 1, pixels), std::invalid_argument);
  const fs::path path = scratch("no_such_dir") / "sub" / "x.png";
  EXPECT_NE(
      file_error_message([&] { io::write_png_preview(path, 2, 2, pixels); }).find(path.string()),
      std::string::npos);
}

// ---------------------------------------------------------------- Draco

// Octahedron split 1:4 `levels` times, midpoints shared and pushed to the
// unit sphere, so that no two vertices coincide.
TriangleMesh subdivided_octahedron(int levels) {
  TriangleMesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = midpoint.find(key); it != midpoint.end()) return it->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      return midpoint[key] = static_cast<int>(m.positions.size()) - 1;
    };
    std::vector<Triangle> finer;
    for (const auto [a, b, c] : m.triangles) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
    }
    m.triangles = std::move(finer);
  }
  return m;
}

PolygonSoup to_soup(const TriangleMesh& m) {
  PolygonSoup soup{m.positions, {}};
  for (const Triangle& t : m.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  return soup;
}

double quantization_tolerance(const TriangleMesh& m, int bits) {
  return bounding_box_diagonal(m) / std::ldexp(1.0, bits) * 2;
}

TEST(DracoIo, SequentialKeepsOrderWithinQuantization) {
  const TriangleMesh mesh = subdivided_octahedron(2);  // 66 vertices, 128 faces
  const fs::path path = scratch("octahedron_seq.drc");
  const int bits = 14;
  io::write_draco(mesh, path, bits);
  const TriangleMesh back = io::read_draco(path);

  ASSERT_EQ(back.n_vertices(), mesh.n_vertices());
  ASSERT_EQ(back.n_faces(), mesh.n_faces());
  EXPECT_EQ(back.triangles, mesh.triangles);
  const double tolerance = quantization_tolerance(mesh, bits);
  double worst = 0;
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    worst = std::max(worst, (back.positions[v] - mesh.positions[v]).norm());
  EXPECT_LE(worst, tolerance);
  EXPECT_GT(worst, 0.0);  // really quantized, not stored as floats
  // The tighter per-axis bound documented in draco_io.hpp (box side is 2 here).
  const double step = 2.0 / (std::ldexp(1.0, bits) - 1);
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    EXPECT_LE((back.positions[v] - mesh.positions[v]).cwiseAbs().maxCoeff(), step / 2 + 1e-6) << v;
}

TEST(DracoIo, EdgebreakerKeepsTopologyWithinQuantization) {
  const TriangleMesh mesh = subdivided_octahedron(3);  // 258 vertices, 512 faces
  const fs::path path = scratch("octahedron_eb.drc");
  const int bits = 11;
  io::write_draco(mesh, path, bits, io::DracoConnectivity::edgebreaker);
  const TriangleMesh back = io::read_draco(path);

  EXPECT_EQ(back.n_faces(), mesh.n_faces());
  const PreparedMesh prepared = prepare_mesh(to_soup(back));
  EXPECT_EQ(prepared.check.vertices, mesh.n_vertices());
  EXPECT_EQ(prepared.check.faces, mesh.n_faces());
  EXPECT_TRUE(prepared.check.closed());
  EXPECT_EQ(prepared.check.genus, 0);
  EXPECT_EQ(prepared.check.flipped_inward, false);
  EXPECT_EQ(prepared.check.reoriented_faces, 0u);
  // Vertices may be renumbered: match each to the nearest input vertex.
  const double tolerance = quantization_tolerance(mesh, bits);
  for (const Vec3& p : back.positions) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& q : mesh.positions) nearest = std::min(nearest, (p - q).norm());
    EXPECT_LE(nearest, tolerance);
  }
  EXPECT_NEAR(signed_volume(back), signed_volume(mesh), 1e-2);
}

TEST(DracoIo, ZeroBitsIsLosslessFloat) {
  const TriangleMesh mesh = subdivided_octahedron(1);
  const fs::path path = scratch("octahedron_float.drc");
  io::write_draco(mesh, path, 0);
  const TriangleMesh back = io::read_draco(path);
  ASSERT_EQ(back.n_vertices(), mesh.n_vertices());
  EXPECT_EQ(back.triangles, mesh.triangles);
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    EXPECT_EQ(back.positions[v], mesh.positions[v].cast<float>().cast<double>());
}

TEST(DracoIo, BadInputThrows) {
  const TriangleMesh mesh = subdivided_octahedron(0);
  EXPECT_THROW(io::write_draco(mesh, scratch("bad.drc"), 31), std::invalid_argument);
  TriangleMesh broken = mesh;
  broken.triangles[0][1] = 6;
  EXPECT_THROW(io::write_draco(broken, scratch("bad.drc")), std::invalid_argument);
  EXPECT_THROW(io::write_draco(TriangleMesh{}, scratch("bad.drc")), std::invalid_argument);

  const fs::path missing = scratch("does_not_exist.drc");
  fs::remove(missing);
  EXPECT_NE(file_error_message([&] { io::read_draco(missing); }).find(missing.string()),
            std::string::npos);
  const fs::path garbage = scratch("garbage.drc");
  std::ofstream(garbage) << "DRACO but not really";
  EXPECT_NE(file_error_message([&] { io::read_draco(garbage); }).find(garbage.string()),
            std::string::npos);
  const fs::path unwritable = scratch("no_such_dir") / "sub" / "x.drc";
  EXPECT_NE(
      file_error_message([&] { io::write_draco(mesh, unwritable); }).find(unwritable.string()),
      std::string::npos);
}

// ---------------------------------------------------------------- glTF

// A glTF binary file: its JSON chunk and its BIN chunk.
struct Glb {
  Json json;
  std::string bin;
};

Glb read_glb(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  Glb glb;
  if (bytes.size() < 12 || bytes.substr(0, 4) != "glTF" || u32(4) != 2 || u32(8) != bytes.size()) {
    ADD_FAILURE() << path << ": not a glTF 2.0 binary of the length its header gives";
    return glb;
  }
  for (std::size_t at = 12; at + 8 <= bytes.size(); at += 8 + u32(at)) {
    const std::string kind = bytes.substr(at + 4, 4), chunk = bytes.substr(at + 8, u32(at));
    if (kind == "JSON") glb.json = Json::parse(chunk);
    if (kind == std::string("BIN\0", 4)) glb.bin = chunk;
  }
  return glb;
}

// The mesh of the file's one triangle primitive: read from its accessors, or,
// Draco-compressed, decoded by io::read_draco from the extension's buffer view.
TriangleMesh glb_mesh(const Glb& glb, const fs::path& scratch_drc) {
  const Json& primitive = glb.json["meshes"][0]["primitives"][0];
  EXPECT_EQ(primitive.value("mode", 4), 4) << "triangles";
  auto view_bytes = [&](int view) {
    const Json& v = glb.json["bufferViews"][view];
    return glb.bin.substr(v.value("byteOffset", 0), v["byteLength"].get<std::size_t>());
  };
  if (primitive.contains("extensions")) {
    const int view = primitive["extensions"]["KHR_draco_mesh_compression"]["bufferView"];
    std::ofstream(scratch_drc, std::ios::binary) << view_bytes(view);
    return io::read_draco(scratch_drc);
  }
  auto accessor = [&](int index) {
    const Json& a = glb.json["accessors"][index];
    return std::pair(a, view_bytes(a["bufferView"]).substr(a.value("byteOffset", 0)));
  };
  TriangleMesh mesh;
  const auto [positions, position_bytes] = accessor(primitive["attributes"]["POSITION"]);
  EXPECT_EQ(positions["componentType"], 5126);  // float
  for (std::size_t i = 0; i < positions["count"].get<std::size_t>(); ++i) {
    float xyz[3];
    std::memcpy(xyz, position_bytes.data() + 12 * i, 12);
    mesh.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(positions["min"][k].get<float>(),
              std::min_element(mesh.positions.begin(), mesh.positions.end(),
                               [k](const Vec3& a, const Vec3& b) { return a[k] < b[k]; })
                  ->
                  operator[](k));
  }
  const auto [indices, index_bytes] = accessor(primitive["indices"]);
  const int type = indices["componentType"];
  const std::size_t width = type == 5125 ? 4 : type == 5123 ? 2 : 1;  // uint32, uint16, uint8
  EXPECT_TRUE(type == 5125 || type == 5123 || type == 5121) << type;
  const std::size_t count = indices["count"];
  EXPECT_EQ(count % 3, 0u);
  for (std::size_t i = 0; i + 2 < count; i += 3) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t v = 0;
      std::memcpy(&v, index_bytes.data() + width * (i + k), width);
      t[k] = int(v);
    }
    mesh.triangles.push_back(t);
  }
  return mesh;
}

TEST(GltfIo, PlainGlbHoldsEveryFaceWithFloatPositions) {
  const TriangleMesh mesh = subdivided_octahedron(2);
  const fs::path path = scratch("octahedron_plain.glb");
  io::write_glb(mesh, path);
  const Glb glb = read_glb(path);
  EXPECT_EQ(glb.json["asset"]["version"], "2.0");
  EXPECT_FALSE(glb.json.contains("extensionsUsed"));
  const TriangleMesh back = glb_mesh(glb, scratch("octahedron_plain_glb.drc"));
  // The same vertices as floats and the same faces, in order and orientation.
  ASSERT_EQ(back.n_vertices(), mesh.n_vertices());
  EXPECT_EQ(back.triangles, mesh.triangles);
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    EXPECT_EQ(back.positions[v], mesh.positions[v].cast<float>().cast<double>()) << v;
}

TEST(GltfIo, DracoGlbIsCompressedWithinQuantization) {
  const TriangleMesh mesh = subdivided_octahedron(4);  // 1026 vertices, 2048 faces
  const fs::path plain = scratch("octahedron4_plain.glb"),
                 packed = scratch("octahedron4_draco.glb");
  const int bits = 11;
  io::write_glb(mesh, plain);
  io::write_glb(mesh, packed, bits);
  const Glb glb = read_glb(packed);
  EXPECT_EQ(glb.json["extensionsRequired"][0], "KHR_draco_mesh_compression");
  EXPECT_LT(fs::file_size(packed) * 3, fs::file_size(plain));
  const TriangleMesh back = glb_mesh(glb, scratch("octahedron4_glb.drc"));
  // Draco may renumber the vertices: every decoded vertex within the
  // quantization step of an input vertex, the surface closed, genus 0 and
  // oriented outward as the input.
  ASSERT_EQ(back.n_faces(), mesh.n_faces());
  const double tolerance = quantization_tolerance(mesh, bits);
  for (const Vec3& p : back.positions) {
    double nearest = INFINITY;
    for (const Vec3& q : mesh.positions) nearest = std::min(nearest, (p - q).norm());
    ASSERT_LE(nearest, tolerance);
  }
  const PreparedMesh prepared = prepare_mesh(to_soup(back));
  EXPECT_TRUE(prepared.check.closed());
  EXPECT_EQ(prepared.check.genus, 0);
  EXPECT_FALSE(prepared.check.flipped_inward);
  EXPECT_NEAR(signed_volume(back), signed_volume(mesh), 1e-2);
}

TEST(GltfIo, BadInputThrows) {
  const TriangleMesh mesh = subdivided_octahedron(0);
  EXPECT_THROW(io::write_glb(TriangleMesh{}, scratch("bad.glb")), std::invalid_argument);
  EXPECT_THROW(io::write_glb(mesh, scratch("bad.glb"), 7), std::invalid_argument);
  TriangleMesh broken = mesh;
  broken.triangles[0][1] = -1;
  EXPECT_THROW(io::write_glb(broken, scratch("bad.glb")), std::invalid_argument);
  const fs::path unwritable = scratch("no_such_dir") / "sub" / "x.glb";
  EXPECT_NE(file_error_message([&] { io::write_glb(mesh, unwritable); }).find(unwritable.string()),
            std::string::npos);
}

TEST(GltfIo, MeshFileOptionsChooseCompression) {
  const TriangleMesh mesh = subdivided_octahedron(3);
  const fs::path plain = scratch("octahedron3_file.glb"),
                 packed = scratch("octahedron3_file_d.glb");
  io::write_mesh_file(mesh, plain);
  io::write_mesh_file(mesh, packed, {.draco_bits = 12, .glb_draco = true});
  EXPECT_FALSE(read_glb(plain).json.contains("extensionsRequired"));
  EXPECT_EQ(read_glb(packed).json["extensionsRequired"][0], "KHR_draco_mesh_compression");
}

TEST(GltfIo, KhronosValidatorFindsNoError) {
  ISM_REQUIRE_GLTF_VALIDATOR();
  const TriangleMesh mesh = subdivided_octahedron(3);
  const fs::path plain = scratch("validated_plain.glb"), packed = scratch("validated_draco.glb");
  io::write_glb(mesh, plain);
  io::write_glb(mesh, packed, 14);
  ISM_EXPECT_VALID_GLTF(std::vector<fs::path>({plain, packed}), scratch("validated_glb.log"));
}

}  // namespace
}  // namespace ism
