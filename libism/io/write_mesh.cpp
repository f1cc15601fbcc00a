#include "io/io.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdio>

namespace ism::io {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

// Writes positions and faces through an OpenMesh kernel (a TriMesh for
// triangles, a PolyMesh for polygons, which a TriMesh would split). Faces are
// added in order, so indices of the written file match the mesh.
template <class Kernel, std::size_t Corners>
void write_through_openmesh(const std::vector<Vec3>& positions,
                            const std::vector<std::array<int, Corners>>& faces,
                            const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  OpenMesh::IO::Options options;
  if (ext == ".ply" || ext == ".stl") options += OpenMesh::IO::Options::Binary;
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
}

}  // namespace

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (!(ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl"))
    throw FileError(path.string() + ": unsupported output format (use .obj, .ply, .off or .stl)");
  write_through_openmesh<OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>>(mesh.positions,
                                                                       mesh.triangles, path);
}

void write_quad_mesh(const QuadMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (!(ext == ".obj" || ext == ".ply" || ext == ".off"))
    throw FileError(path.string() +
                    ": unsupported format for quads (use .obj, .ply or .off; .stl and .drc "
                    "store triangles only)");
  write_through_openmesh<OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>>(mesh.positions, mesh.quads,
                                                                        path);
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
