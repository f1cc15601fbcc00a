#pragma once
// Mesh files in and out. Reading (OBJ, PLY ascii/binary, OFF and its
// variants, STL ascii/binary) yields a raw polygon soup, so that broken files
// reach the checks intact instead of being silently patched by a mesh kernel.
// The readers are our own and take hostile files: they never hang (every loop
// consumes input), never reserve what a header claims before checking it
// against the bytes the file holds, and end every failure in a FileError.
// Writing is ours too (OBJ, OFF and PLY at full double precision), STL's
// through OpenMesh.
#include "mesh/polygon_soup.hpp"
#include "mesh/quad_mesh.hpp"
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ism::io {

/// A file that cannot be read or written; the message names the file.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The mesh formats read_polygon_soup() understands.
enum class MeshFormat { obj, off, ply, stl };

/// The format named by the extension (.obj, .off, .ply, .stl in any case).
std::optional<MeshFormat> mesh_format_of(const std::filesystem::path& path);

/// Extensions read_polygon_soup() understands, in any case.
bool is_readable_mesh_extension(const std::filesystem::path& path);

/// Reads positions and faces as the file stores them: OBJ (v and f lines,
/// "i/t/n" corners, negative relative indices, '\' continuations), PLY
/// (ascii, binary little and big endian; any numeric types; x y z of the
/// vertex element, vertex_indices or vertex_index of the face element; other
/// elements and properties skipped), OFF (ascii and "OFF BINARY", the ST, C
/// and N prefixes; extra values on a line ignored), STL (ascii and binary,
/// exactly equal corners joined, as STL has no other connectivity). A UTF-8
/// byte-order mark is skipped. Throws FileError naming the file (and the line
/// for text formats) for anything else: a count the file cannot hold, a
/// truncated file, a face index that is not a vertex, no faces.
/// Coordinates are kept at single precision (each rounded to the nearest
/// float), as mesh files mostly store them and as the tools have always read
/// them: every published figure was measured on inputs read so, and the
/// optimisation is sensitive to the last bits of its input.
PolygonSoup read_polygon_soup(const std::filesystem::path& path);

/// read_polygon_soup() on the bytes of a file already in memory; `name`
/// prefixes the messages.
PolygonSoup parse_polygon_soup(std::string_view bytes, MeshFormat format, const std::string& name);

/// The triangles of a mesh file with its coordinates exactly as stored (not
/// rounded, nothing welded): for reading back double-precision outputs such
/// as ism-map's overlay pair. Throws FileError as read_polygon_soup(), or
/// for a face that is not a triangle.
TriangleMesh read_triangles_exact(const std::filesystem::path& path);

/// Upper bounds on what a mesh file holds, known before reading it.
struct MeshFileSize {
  std::uint64_t bytes = 0;
  std::uint64_t vertices = 0;  // positions in the file (before welding)
  std::uint64_t faces = 0;     // polygons in the file (before triangulation)
  /// A header declares more vertices or faces than the file's bytes can hold
  /// (the counts above are then that cap): the file is truncated or corrupt,
  /// and reading it fails with the reason.
  bool capped = false;
};

/// The sizes a mesh file declares, without building the mesh: PLY and OFF
/// from their headers, binary STL from its count, each capped by what the
/// file's size can hold; OBJ by counting its v and f lines (a pass over the
/// file in small chunks); ASCII STL from the file's size. Throws FileError
/// for a missing file or an unknown extension, and for a header that cannot
/// be read (the same message read_polygon_soup() would give).
MeshFileSize peek_mesh_size(const std::filesystem::path& path);

/// Writes a triangle mesh as OBJ, PLY (binary little-endian), OFF or STL,
/// chosen by the extension: OBJ and OFF coordinates to 17 significant digits
/// and PLY's as doubles, so they read back exactly (STL is single precision
/// by its format). Throws FileError, also for faces that are not a 2-manifold
/// (a directed edge twice, a repeated or missing vertex). Callers that must not leave partial files
/// write to a temporary name first (see tool/output_file.hpp).
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Writes a quad mesh as OBJ ("f a b c d"), PLY (binary) or OFF, chosen by
/// the extension, vertex and face indices as in the mesh. STL and Draco store
/// triangles only: triangulate() first. Throws FileError.
void write_quad_mesh(const QuadMesh& mesh, const std::filesystem::path& path);

/// Writes an OBJ with one texture coordinate per vertex ('vt u v', faces
/// 'f a/a b/b c/c'), everything to 17 significant digits. Throws FileError
/// (also for a non-manifold mesh, as write_mesh()) and
/// std::invalid_argument when `texcoords` is not one per vertex.
void write_textured_obj(const TriangleMesh& mesh,
                        const std::vector<std::array<double, 2>>& texcoords,
                        const std::filesystem::path& path);

/// Writes a glTF 2.0 binary file (.glb): one mesh, positions as 32-bit floats
/// with their bounds, 32-bit indices in face order, and one morph target
/// named `target_name` moving every vertex to `target` (same count), weight
/// 0 (the mesh as given; weight 1: the target). Plain glTF, no extension:
/// every viewer with morph targets plays it. Throws std::invalid_argument for
/// an empty mesh, a bad face index or a target of another size, FileError
/// when writing fails or the file would pass glTF's 4 GB.
void write_morph_glb(const TriangleMesh& mesh, const std::vector<Vec3>& target,
                     const std::filesystem::path& path, const std::string& target_name = "target");

/// 8-bit RGB colour.
using Rgb = std::array<unsigned char, 3>;

/// Writes an ASCII PLY with per-vertex and per-face colours (either list may
/// be empty), for looking at partitions in MeshLab or Blender.
void write_colored_ply(const TriangleMesh& mesh, const std::vector<Rgb>& vertex_colors,
                       const std::vector<Rgb>& face_colors, const std::filesystem::path& path);

/// Per-vertex values (scalars or vectors): row i holds vertex i's, every row
/// the same number of columns.
struct VertexField {
  std::size_t columns = 0;
  std::vector<double> values;  // row-major, rows × columns
  std::size_t rows() const { return columns ? values.size() / columns : 0; }
};

/// Reads a per-vertex field: one row per vertex, numbers separated by blanks
/// (or commas); lines empty or starting with '#' skipped. Throws FileError
/// naming the file and line: not a number, rows of different lengths, or a
/// row count other than `rows`.
VertexField read_vertex_field(const std::filesystem::path& path, std::size_t rows);
/// Writes a field as read_vertex_field() reads it, every value to 17
/// significant digits. Throws FileError.
void write_vertex_field(const VertexField& field, const std::filesystem::path& path);

}  // namespace ism::io
