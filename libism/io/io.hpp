#pragma once
// Mesh files in and out. Reading goes through OpenMesh's readers (OBJ, PLY
// ascii/binary, OFF, STL) into a raw polygon soup, so that broken files reach
// the checks intact instead of being silently patched by a mesh kernel.
#include "mesh/polygon_soup.hpp"
#include "mesh/quad_mesh.hpp"
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <filesystem>
#include <stdexcept>

namespace ism::io {

/// A file that cannot be read or written; the message names the file.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Extensions read_polygon_soup() understands, lower case with the dot.
bool is_readable_mesh_extension(const std::filesystem::path& path);

/// Reads positions and faces as the file stores them. Throws FileError.
PolygonSoup read_polygon_soup(const std::filesystem::path& path);

/// Writes a triangle mesh as OBJ, PLY (binary), OFF or STL, chosen by the
/// extension. Throws FileError. Callers that must not leave partial files
/// write to a temporary name first (see tool/output_file.hpp).
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Writes a quad mesh as OBJ ("f a b c d"), PLY (binary) or OFF, chosen by
/// the extension, vertex and face indices as in the mesh. STL and Draco store
/// triangles only: triangulate() first. Throws FileError.
void write_quad_mesh(const QuadMesh& mesh, const std::filesystem::path& path);

/// 8-bit RGB colour.
using Rgb = std::array<unsigned char, 3>;

/// Writes an ASCII PLY with per-vertex and per-face colours (either list may
/// be empty), for looking at partitions in MeshLab or Blender.
void write_colored_ply(const TriangleMesh& mesh, const std::vector<Rgb>& vertex_colors,
                       const std::vector<Rgb>& face_colors, const std::filesystem::path& path);

}  // namespace ism::io
