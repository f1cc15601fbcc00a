#include "io/io.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdio>

namespace ism::io {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using WriteMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

}  // namespace

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  OpenMesh::IO::Options options;
  if (ext == ".ply" || ext == ".stl") options += OpenMesh::IO::Options::Binary;
  if (!(ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl"))
    throw FileError(path.string() + ": unsupported output format (use .obj, .ply, .off or .stl)");

  // OpenMesh writes through a kernel; faces are added in order, so indices
  // of the written file match the mesh.
  WriteMesh out;
  out.reserve(mesh.n_vertices(), 3 * mesh.n_faces() / 2, mesh.n_faces());
  std::vector<WriteMesh::VertexHandle> handles;
  handles.reserve(mesh.n_vertices());
  for (const Vec3& p : mesh.positions) handles.push_back(out.add_vertex({p.x(), p.y(), p.z()}));
  omerr().disable();
  for (const Triangle& t : mesh.triangles)
    if (!out.add_face(handles[t[0]], handles[t[1]], handles[t[2]]).is_valid())
      throw FileError(path.string() + ": mesh is not a 2-manifold, cannot write it");
  omlog().disable();
  omout().disable();
  if (!OpenMesh::IO::write_mesh(out, path.string(), options, 17))
    throw FileError(path.string() + ": cannot write the file");
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
