#include "io/io.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <fstream>

namespace ism::io {
namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

// An OpenMesh importer that records what the reader sees and ignores all
// attributes. Every attribute hook of the interface is a deliberate no-op.
class SoupImporter final : public OpenMesh::IO::BaseImporter {
 public:
  explicit SoupImporter(PolygonSoup& soup) : soup_(soup) {}

  VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return add(Vec3(p[0], p[1], p[2])); }
  VertexHandle add_vertex(const OpenMesh::Vec3d& p) override { return add(Vec3(p[0], p[1], p[2])); }
  VertexHandle add_vertex() override { return add(Vec3::Zero()); }
  FaceHandle add_face(const VHandles& corners) override {
    std::vector<int>& face = soup_.faces.emplace_back();
    face.reserve(corners.size());
    for (VertexHandle v : corners) {
      if (!v.is_valid() || std::size_t(v.idx()) >= soup_.positions.size()) {
        bad_index_ = true;
        soup_.faces.pop_back();
        return FaceHandle();
      }
      face.push_back(v.idx());
    }
    return FaceHandle(int(soup_.faces.size()) - 1);
  }
  void set_point(VertexHandle v, const OpenMesh::Vec3f& p) override {
    if (v.is_valid() && std::size_t(v.idx()) < soup_.positions.size())
      soup_.positions[v.idx()] = Vec3(p[0], p[1], p[2]);
  }
  bool bad_index() const { return bad_index_; }

  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return soup_.positions.size(); }
  size_t n_faces() const override { return soup_.faces.size(); }
  size_t n_edges() const override { return 0; }

 private:
  VertexHandle add(const Vec3& p) {
    soup_.positions.push_back(p);
    return VertexHandle(int(soup_.positions.size()) - 1);
  }
  PolygonSoup& soup_;
  bool bad_index_ = false;
};

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

bool is_readable_mesh_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

PolygonSoup read_polygon_soup(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (!is_readable_mesh_extension(path))
    throw FileError(name + ": unsupported mesh format (use .obj, .ply, .off or .stl)");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw FileError(name + ": no such file");
  if (!std::ifstream(path)) throw FileError(name + ": cannot open the file");

  // OpenMesh reports its own diagnostics on its log streams; ours are the
  // one-line messages thrown below.
  omlog().disable();
  omerr().disable();
  omout().disable();

  PolygonSoup soup;
  SoupImporter importer(soup);
  OpenMesh::IO::Options options;
  const bool ok = OpenMesh::IO::IOManager().read(name, importer, options);
  if (!ok) throw FileError(name + ": unreadable or malformed mesh file");
  if (importer.bad_index())
    throw FileError(name + ": a face refers to a vertex that does not exist");
  if (soup.faces.empty()) throw FileError(name + ": the file has no faces");
  return soup;
}

}  // namespace ism::io
