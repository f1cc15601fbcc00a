#include "io/io.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

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
