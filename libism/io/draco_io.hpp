#pragma once
// Compressed meshes through Google's Draco (.drc), and glTF 2.0 binary (.glb)
// through Draco's glTF encoder, plain or Draco-compressed. Quantized positions
// make a round trip lossy; see write_draco() for what is kept exactly.
#include "mesh/triangle_mesh.hpp"

#include <filesystem>
#include <optional>

namespace ism::io {

/// How write_draco() lays out the connectivity.
enum class DracoConnectivity {
  /// Faces and vertices keep their order and indices, but connectivity is
  /// barely compressed: a 16k-vertex sphere takes 259 KB at 14 bits.
  sequential,
  /// Edgebreaker: ~8x smaller (32 KB for that sphere), but the decoder returns vertices and faces
  /// in its
  /// own traversal order and rotates corners within a face (orientation is
  /// kept). It also drops unreferenced vertices and faces with a repeated
  /// corner, and splits vertices at non-manifold edges (e.g. duplicate faces)
  /// into copies, so weld by position afterwards if topology matters.
  edgebreaker,
};

/// Writes the mesh as Draco with positions quantized to `quantization_bits`
/// per axis over the bounding box (1..30; 0 stores the floats losslessly,
/// rounded to float precision). Decoded positions are then within
/// (largest box side) / (2^bits - 1) / 2 per axis of the input. Throws
/// std::invalid_argument for a mesh without vertices or faces (Draco cannot
/// round-trip those), a bad bit count or face index, and FileError when
/// encoding or writing fails.
void write_draco(const TriangleMesh& mesh, const std::filesystem::path& path,
                 int quantization_bits = 14,
                 DracoConnectivity connectivity = DracoConnectivity::sequential);

/// Reads a Draco mesh: one vertex per Draco point, in the decoded order.
/// Throws FileError for a missing or invalid file, a point cloud, or a file
/// without positions.
TriangleMesh read_draco(const std::filesystem::path& path);

/// Writes the mesh as a glTF 2.0 binary file: one mesh, one triangle
/// primitive, positions (and their bounds) as 32-bit floats, indices in face
/// order, no normals or material. With `draco_bits` the primitive is
/// Draco-compressed (extension KHR_draco_mesh_compression, required by the
/// file), positions quantized to that many bits (8..30) as in write_draco();
/// without, it is stored plainly, readable by every glTF viewer. Throws
/// std::invalid_argument for a mesh without vertices or faces, a bad bit count
/// or face index, and FileError when encoding or writing fails.
void write_glb(const TriangleMesh& mesh, const std::filesystem::path& path,
               std::optional<int> draco_bits = std::nullopt);

/// How write_mesh_file() writes the formats that have settings.
struct MeshFileOptions {
  int draco_bits = 14;     // position quantization of .drc, and of .glb with glb_draco
  bool glb_draco = false;  // .glb: Draco-compressed (else plain)
};

/// Writes .drc through write_draco(), .glb through write_glb(), any other
/// extension through write_mesh().
void write_mesh_file(const TriangleMesh& mesh, const std::filesystem::path& path,
                     const MeshFileOptions& options = {});

}  // namespace ism::io
