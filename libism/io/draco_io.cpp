#include "io/draco_io.hpp"

#include "io/io.hpp"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/io/gltf_encoder.h>
#include <draco/mesh/mesh.h>

#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace ism::io {

namespace {

void check_bits(int bits, int lowest) {
  if (bits < lowest || bits > 30)
    throw std::invalid_argument("Draco quantization bits must be " + std::to_string(lowest) +
                                "..30, not " + std::to_string(bits));
}

// One Draco point per vertex with an identity attribute mapping, so point
// indices are our vertex indices (no welding, no splitting by us). Throws
// std::invalid_argument for an empty mesh or a bad face index.
std::unique_ptr<draco::Mesh> to_draco(const TriangleMesh& mesh, const char* caller) {
  // No points crashes Draco's quantizer; no faces writes a file that Draco
  // then refuses to decode (sequential) or fails to encode (edgebreaker).
  if (mesh.positions.empty() || mesh.triangles.empty())
    throw std::invalid_argument(std::string(caller) + ": the mesh has no vertices or no faces");
  const auto n = static_cast<int>(mesh.positions.size());
  auto out = std::make_unique<draco::Mesh>();
  out->set_num_points(static_cast<draco::PointIndex::ValueType>(n));
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false,
                3 * sizeof(float), 0);
  draco::PointAttribute* attribute = out->attribute(out->AddAttribute(position, true, n));
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3f p = mesh.positions[v].cast<float>();
    attribute->SetAttributeValue(draco::AttributeValueIndex(v), p.data());
  }
  for (const Triangle& t : mesh.triangles) {
    draco::Mesh::Face face;
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= n)
        throw std::invalid_argument(std::string(caller) + ": face index " + std::to_string(t[k]) +
                                    " out of range for " + std::to_string(n) + " vertices");
      face[k] = draco::PointIndex(static_cast<draco::PointIndex::ValueType>(t[k]));
    }
    out->AddFace(face);
  }
  return out;
}

void write_bytes(const std::filesystem::path& path, const draco::EncoderBuffer& buffer) {
  std::ofstream file(path, std::ios::binary);
  if (!file) throw FileError(path.string() + ": cannot open for writing");
  file.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  file.close();
  if (!file) throw FileError(path.string() + ": write failed");
}

}  // namespace

void write_draco(const TriangleMesh& mesh, const std::filesystem::path& path, int quantization_bits,
                 DracoConnectivity connectivity) {
  check_bits(quantization_bits, 0);
  const std::unique_ptr<draco::Mesh> out = to_draco(mesh, "write_draco");

  draco::Encoder encoder;
  if (quantization_bits > 0)
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, quantization_bits);
  encoder.SetEncodingMethod(connectivity == DracoConnectivity::sequential
                                ? draco::MESH_SEQUENTIAL_ENCODING
                                : draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buffer;
  if (const draco::Status status = encoder.EncodeMeshToBuffer(*out, &buffer); !status.ok())
    throw FileError(path.string() + ": Draco encoding failed: " + status.error_msg_string());
  write_bytes(path, buffer);
}

void write_glb(const TriangleMesh& mesh, const std::filesystem::path& path,
               std::optional<int> draco_bits) {
  if (draco_bits) check_bits(*draco_bits, 8);
  const std::unique_ptr<draco::Mesh> out = to_draco(mesh, "write_glb");
  if (draco_bits) {
    draco::DracoCompressionOptions options;
    options.quantization_position.SetQuantizationBits(*draco_bits);
    out->SetCompressionOptions(options);
    out->SetCompressionEnabled(true);
  }
  draco::GltfEncoder encoder;
  draco::EncoderBuffer buffer;
  if (const draco::Status status = encoder.EncodeToBuffer(*out, &buffer); !status.ok())
    throw FileError(path.string() + ": glTF encoding failed: " + status.error_msg_string());
  write_bytes(path, buffer);
}

TriangleMesh read_draco(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw FileError(path.string() + ": cannot open the Draco file");
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)),
                                std::istreambuf_iterator<char>());
  if (file.bad()) throw FileError(path.string() + ": read failed");

  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  // Checked first: DecodeMeshFromBuffer's message for a point cloud is vague.
  const auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok())
    throw FileError(path.string() + ": not a Draco file: " + type.status().error_msg_string());
  if (type.value() != draco::TRIANGULAR_MESH)
    throw FileError(path.string() + ": Draco file holds a point cloud, not a mesh");
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    throw FileError(path.string() +
                    ": Draco decoding failed: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> in = std::move(decoded).value();

  const draco::PointAttribute* position = in->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!position || position->num_components() != 3)
    throw FileError(path.string() + ": Draco mesh has no 3D positions");
  TriangleMesh mesh;
  mesh.positions.resize(in->num_points());
  for (draco::PointIndex p(0); p < in->num_points(); ++p) {
    float xyz[3];  // dequantized by the decoder; ConvertValue also handles integer types
    if (!position->ConvertValue<float, 3>(position->mapped_index(p), xyz))
      throw FileError(path.string() + ": unreadable Draco position");
    mesh.positions[p.value()] = Vec3(xyz[0], xyz[1], xyz[2]);
  }
  mesh.triangles.resize(in->num_faces());
  for (draco::FaceIndex f(0); f < in->num_faces(); ++f) {
    const draco::Mesh::Face& face = in->face(f);
    for (int k = 0; k < 3; ++k) mesh.triangles[f.value()][k] = static_cast<int>(face[k].value());
  }
  return mesh;
}

void write_mesh_file(const TriangleMesh& mesh, const std::filesystem::path& path,
                     const MeshFileOptions& options) {
  if (path.extension() == ".drc")
    write_draco(mesh, path, options.draco_bits);
  else if (path.extension() == ".glb")
    write_glb(mesh, path,
              options.glb_draco ? std::optional<int>(options.draco_bits) : std::nullopt);
  else
    write_mesh(mesh, path);
}

}  // namespace ism::io
