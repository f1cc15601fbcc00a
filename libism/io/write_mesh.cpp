#include "io/io.hpp"
#include "mesh/edge_key.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace ism::io {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

// Checks that faces form a 2-manifold (each directed edge once): the files
// written must read back as the mesh.
template <std::size_t Corners>
void check_manifold(const std::vector<std::array<int, Corners>>& faces, std::size_t vertices,
                    const std::filesystem::path& path) {
  std::unordered_set<std::uint64_t> directed;
  directed.reserve(Corners * faces.size());
  for (const auto& face : faces)
    for (std::size_t k = 0; k < Corners; ++k) {
      const int a = face[k], b = face[(k + 1) % Corners];
      if (a < 0 || b < 0 || std::size_t(a) >= vertices || std::size_t(b) >= vertices || a == b ||
          !directed.insert(directed_edge_key(a, b)).second)
        throw FileError(path.string() + ": mesh is not a 2-manifold, cannot write it");
    }
}

// OBJ, OFF (text, every coordinate to 17 significant digits: read back
// exactly) and PLY (binary little-endian doubles) written here; STL (single
// precision by its format) through OpenMesh. Indices of the written file match
// the mesh.
template <class Kernel, std::size_t Corners>
void write_faces(const std::vector<Vec3>& positions,
                 const std::vector<std::array<int, Corners>>& faces,
                 const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".stl") {
    OpenMesh::IO::Options options;
    options += OpenMesh::IO::Options::Binary;
    Kernel out;
    out.reserve(positions.size(), Corners * faces.size() / 2, faces.size());
    std::vector<typename Kernel::VertexHandle> handles;
    handles.reserve(positions.size());
    for (const Vec3& p : positions) handles.push_back(out.add_vertex({p.x(), p.y(), p.z()}));
    omerr().disable();
    std::vector<typename Kernel::VertexHandle> corners(Corners);
    for (const auto& face : faces) {
      for (std::size_t k = 0; k < Corners; ++k) corners[k] = handles[face[k]];
      if (!out.add_face(corners).is_valid())
        throw FileError(path.string() + ": mesh is not a 2-manifold, cannot write it");
    }
    omlog().disable();
    omout().disable();
    if (!OpenMesh::IO::write_mesh(out, path.string(), options, 17))
      throw FileError(path.string() + ": cannot write the file");
    return;
  }
  check_manifold(faces, positions.size(), path);
  std::FILE* file = std::fopen(path.string().c_str(), ext == ".ply" ? "wb" : "w");
  if (!file) throw FileError(path.string() + ": cannot write the file");
  if (ext == ".obj") {
    std::fprintf(file, "# %zu vertices, %zu faces\n", positions.size(), faces.size());
    for (const Vec3& p : positions)
      std::fprintf(file, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    for (const auto& face : faces) {
      std::fputc('f', file);
      for (int v : face) std::fprintf(file, " %d", v + 1);
      std::fputc('\n', file);
    }
  } else if (ext == ".off") {
    std::fprintf(file, "OFF\n%zu %zu 0\n", positions.size(), faces.size());
    for (const Vec3& p : positions) std::fprintf(file, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    for (const auto& face : faces) {
      std::fprintf(file, "%zu", Corners);
      for (int v : face) std::fprintf(file, " %d", v);
      std::fputc('\n', file);
    }
  } else {  // .ply
    std::fprintf(file,
                 "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty double x\n"
                 "property double y\nproperty double z\nelement face %zu\n"
                 "property list uchar int vertex_indices\nend_header\n",
                 positions.size(), faces.size());
    static_assert(std::endian::native == std::endian::little, "PLY is written little-endian");
    for (const Vec3& p : positions) {
      const double xyz[3] = {p.x(), p.y(), p.z()};
      std::fwrite(xyz, sizeof xyz, 1, file);
    }
    for (const auto& face : faces) {
      const unsigned char n = Corners;
      std::fwrite(&n, 1, 1, file);
      std::fwrite(face.data(), sizeof(int), Corners, file);
    }
  }
  const bool ok = !std::ferror(file);
  if (std::fclose(file) != 0 || !ok) throw FileError(path.string() + ": cannot write the file");
}

}  // namespace

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (!(ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl"))
    throw FileError(path.string() + ": unsupported output format (use .obj, .ply, .off or .stl)");
  write_faces<OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>>(mesh.positions, mesh.triangles, path);
}

void write_textured_obj(const TriangleMesh& mesh,
                        const std::vector<std::array<double, 2>>& texcoords,
                        const std::filesystem::path& path) {
  if (texcoords.size() != mesh.n_vertices())
    throw std::invalid_argument("write_textured_obj: " + std::to_string(texcoords.size()) +
                                " texture coordinates for " + std::to_string(mesh.n_vertices()) +
                                " vertices");
  check_manifold(mesh.triangles, mesh.n_vertices(), path);
  std::FILE* file = std::fopen(path.string().c_str(), "w");
  if (!file) throw FileError(path.string() + ": cannot write the file");
  std::fprintf(file, "# %zu vertices, %zu faces, a texture coordinate per vertex\n",
               mesh.n_vertices(), mesh.n_faces());
  for (const Vec3& p : mesh.positions)
    std::fprintf(file, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  for (const auto& uv : texcoords) std::fprintf(file, "vt %.17g %.17g\n", uv[0], uv[1]);
  for (const Triangle& t : mesh.triangles)
    std::fprintf(file, "f %d/%d %d/%d %d/%d\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1,
                 t[2] + 1);
  const bool ok = !std::ferror(file);
  if (std::fclose(file) != 0 || !ok) throw FileError(path.string() + ": cannot write the file");
}

void write_quad_mesh(const QuadMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (!(ext == ".obj" || ext == ".ply" || ext == ".off"))
    throw FileError(path.string() +
                    ": unsupported format for quads (use .obj, .ply or .off; .stl and .drc "
                    "store triangles only)");
  write_faces<OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>>(mesh.positions, mesh.quads, path);
}

}  // namespace ism::io

namespace ism::io {

void write_colored_ply(const TriangleMesh& mesh, const std::vector<Rgb>& vertex_colors,
                       const std::vector<Rgb>& face_colors, const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.string().c_str(), "w");
  if (!file) throw FileError(path.string() + ": cannot write the file");
  const bool per_vertex = vertex_colors.size() == mesh.n_vertices();
  const bool per_face = face_colors.size() == mesh.n_faces();
  std::fprintf(file, "ply\nformat ascii 1.0\nelement vertex %zu\n", mesh.n_vertices());
  std::fprintf(file, "property double x\nproperty double y\nproperty double z\n");
  if (per_vertex)
    std::fprintf(file, "property uchar red\nproperty uchar green\nproperty uchar blue\n");
  std::fprintf(file, "element face %zu\nproperty list uchar int vertex_indices\n", mesh.n_faces());
  if (per_face)
    std::fprintf(file, "property uchar red\nproperty uchar green\nproperty uchar blue\n");
  std::fprintf(file, "end_header\n");
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    std::fprintf(file, "%.17g %.17g %.17g", p.x(), p.y(), p.z());
    if (per_vertex)
      std::fprintf(file, " %d %d %d", vertex_colors[v][0], vertex_colors[v][1],
                   vertex_colors[v][2]);
    std::fputc('\n', file);
  }
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const Triangle& t = mesh.triangles[f];
    std::fprintf(file, "3 %d %d %d", t[0], t[1], t[2]);
    if (per_face)
      std::fprintf(file, " %d %d %d", face_colors[f][0], face_colors[f][1], face_colors[f][2]);
    std::fputc('\n', file);
  }
  const bool ok = std::ferror(file) == 0;
  if (std::fclose(file) != 0 || !ok) throw FileError(path.string() + ": cannot write the file");
}

}  // namespace ism::io
