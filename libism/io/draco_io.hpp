#pragma once
// Compressed meshes through Google's Draco (.drc). Positions are quantized, so
// a round trip is lossy; see write_draco() for what is kept exactly.
#include "mesh/triangle_mesh.hpp"

#include <filesystem>

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

/// Writes .drc through write_draco() (with `quantization_bits`), any other
/// extension through write_mesh().
void write_mesh_file(const TriangleMesh& mesh, const std::filesystem::path& path,
                     int quantization_bits = 14);

}  // namespace ism::io
