// glTF 2.0 binary with one morph target, written here: Draco's glTF encoder
// (draco_io.cpp) has no morph targets. The layout follows the glTF 2.0
// specification: a 12-byte header, a JSON chunk padded with spaces and a
// binary chunk padded with zeros, each to 4 bytes.
#include "io/io.hpp"
#include "report/json.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace ism::io {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;
constexpr std::uint32_t kBinChunk = 0x004E4942;
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

void append(std::vector<char>& bytes, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  bytes.insert(bytes.end(), p, p + size);
}

// Appends points as float triples; the accessor (with the bounds glTF
// requires of positions) describing them.
Json float_triples(std::vector<char>& bin, Json& views, const std::vector<Vec3>& points) {
  const std::size_t offset = bin.size();
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<float>::max();
    hi[k] = std::numeric_limits<float>::lowest();
  }
  for (const Vec3& p : points) {
    const float xyz[3] = {float(p.x()), float(p.y()), float(p.z())};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], xyz[k]);
      hi[k] = std::max(hi[k], xyz[k]);
    }
    append(bin, xyz, sizeof xyz);
  }
  views.push_back({{"buffer", 0},
                   {"byteOffset", offset},
                   {"byteLength", bin.size() - offset},
                   {"target", kArrayBuffer}});
  return {{"bufferView", views.size() - 1}, {"componentType", kFloat},
          {"count", points.size()},         {"type", "VEC3"},
          {"min", {lo[0], lo[1], lo[2]}},   {"max", {hi[0], hi[1], hi[2]}}};
}

}  // namespace

void write_morph_glb(const TriangleMesh& mesh, const std::vector<Vec3>& target,
                     const std::filesystem::path& path, const std::string& target_name) {
  if (mesh.positions.empty() || mesh.triangles.empty())
    throw std::invalid_argument("write_morph_glb: a mesh without vertices or faces");
  if (target.size() != mesh.positions.size())
    throw std::invalid_argument("write_morph_glb: the target has " + std::to_string(target.size()) +
                                " positions, the mesh " + std::to_string(mesh.positions.size()));
  static_assert(std::endian::native == std::endian::little, "glTF is little-endian");
  std::vector<char> bin;
  Json views = Json::array(), accessors = Json::array();
  // Indices first (4-byte aligned by construction), then the positions and
  // the target's displacements.
  for (const Triangle& t : mesh.triangles)
    for (int v : t) {
      if (v < 0 || std::size_t(v) >= mesh.positions.size())
        throw std::invalid_argument("write_morph_glb: a face index is not a vertex");
      const std::uint32_t i = std::uint32_t(v);
      append(bin, &i, sizeof i);
    }
  views.push_back({{"buffer", 0},
                   {"byteOffset", 0},
                   {"byteLength", bin.size()},
                   {"target", kElementArrayBuffer}});
  accessors.push_back({{"bufferView", 0},
                       {"componentType", kUnsignedInt},
                       {"count", 3 * mesh.triangles.size()},
                       {"type", "SCALAR"}});
  accessors.push_back(float_triples(bin, views, mesh.positions));
  std::vector<Vec3> displacement(target.size());
  for (std::size_t v = 0; v < target.size(); ++v) displacement[v] = target[v] - mesh.positions[v];
  accessors.push_back(float_triples(bin, views, displacement));

  Json gltf = Json::object();
  gltf["asset"] = {{"version", "2.0"}, {"generator", "ism"}};
  gltf["scene"] = 0;
  gltf["scenes"] = Json::array({{{"nodes", {0}}}});
  gltf["nodes"] = Json::array({{{"mesh", 0}}});
  Json primitive = {{"attributes", {{"POSITION", 1}}},
                    {"indices", 0},
                    {"mode", 4},
                    {"targets", Json::array({{{"POSITION", 2}}})}};
  gltf["meshes"] = Json::array({{{"primitives", Json::array({primitive})},
                                 {"weights", {0.0}},
                                 {"extras", {{"targetNames", {target_name}}}}}});
  gltf["accessors"] = accessors;
  gltf["bufferViews"] = views;
  gltf["buffers"] = Json::array({{{"byteLength", bin.size()}}});

  std::string json = gltf.dump();
  while (json.size() % 4) json.push_back(' ');
  while (bin.size() % 4) bin.push_back(0);
  const std::uint32_t total = std::uint32_t(12 + 8 + json.size() + 8 + bin.size());
  if (12 + 8 + json.size() + 8 + bin.size() > std::numeric_limits<std::uint32_t>::max())
    throw FileError(path.string() + ": too large for a glTF binary file (4 GB)");
  std::vector<char> out;
  out.reserve(total);
  const std::uint32_t header[3] = {kMagic, 2, total};
  append(out, header, sizeof header);
  const std::uint32_t json_head[2] = {std::uint32_t(json.size()), kJsonChunk};
  append(out, json_head, sizeof json_head);
  append(out, json.data(), json.size());
  const std::uint32_t bin_head[2] = {std::uint32_t(bin.size()), kBinChunk};
  append(out, bin_head, sizeof bin_head);
  append(out, bin.data(), bin.size());
  std::ofstream file(path, std::ios::binary);
  if (!file) throw FileError(path.string() + ": cannot write the file");
  file.write(out.data(), std::streamsize(out.size()));
  file.flush();
  if (!file) throw FileError(path.string() + ": write failed");
}

}  // namespace ism::io
