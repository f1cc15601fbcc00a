// Replaying vertex splits: the inverse of simplify.cpp's half-edge collapses.
#include "pm/pm.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ism {
namespace {

int corner_of(const Triangle& t, int v) {
  return t[0] == v ? 0 : t[1] == v ? 1 : 2;
}

/// The face around v whose corner after v is x: (v, x, *) counter-clockwise.
int face_after(const TriangleMesh& mesh, const std::vector<std::vector<int>>& vertex_faces, int v,
               int x) {
  for (int f : vertex_faces[v]) {
    const Triangle& t = mesh.triangles[f];
    if (t[(corner_of(t, v) + 1) % 3] == x) return f;
  }
  return -1;
}

/// The face around v whose corner before v is x: (v, *, x) counter-clockwise.
int face_before(const TriangleMesh& mesh, const std::vector<std::vector<int>>& vertex_faces, int v,
                int x) {
  for (int f : vertex_faces[v]) {
    const Triangle& t = mesh.triangles[f];
    if (t[(corner_of(t, v) + 2) % 3] == x) return f;
  }
  return -1;
}

void add_face(TriangleMesh& mesh, std::vector<std::vector<int>>& vertex_faces, const Triangle& t) {
  const int f = static_cast<int>(mesh.triangles.size());
  mesh.triangles.push_back(t);
  for (int v : t) vertex_faces[v].push_back(f);
}

/// Splits vt: the fan of vt's faces from (vt, vl, *) counter-clockwise to
/// (vt, *, vr) moves to vs, and the faces (vs, vt, vl), (vt, vs, vr) fill
/// the gap. On a manifold both ends of the fan are unique, so (vl, vr) name
/// the split unambiguously. On the boundary of an open surface one wing is
/// -1: the fan runs from the other wing to the boundary, and one face fills
/// the gap.
void apply_split(TriangleMesh& mesh, std::vector<std::vector<int>>& vertex_faces,
                 const VertexSplit& s, std::size_t index) {
  const int nv = static_cast<int>(mesh.n_vertices());
  auto fail = [&](const std::string& why) {
    throw std::runtime_error("replay: split " + std::to_string(index) + " (vs " +
                             std::to_string(s.vs) + ", vt " + std::to_string(s.vt) + "): " + why);
  };
  for (int v : {s.vs, s.vt})
    if (v < 0 || v >= nv) fail("vertex index out of range");
  for (int v : {s.vl, s.vr})
    if (v < -1 || v >= nv) fail("vertex index out of range");
  if (s.vl < 0 && s.vr < 0) fail("both wings missing");
  if (!vertex_faces[s.vs].empty()) fail("vs is already in the mesh");
  auto move_to_vs = [&](int f) {
    Triangle& t = mesh.triangles[f];
    t[corner_of(t, s.vt)] = s.vs;
    std::erase(vertex_faces[s.vt], f);
    vertex_faces[s.vs].push_back(f);
  };
  if (s.vl < 0 || s.vr < 0) {
    // Boundary split: from the wing's face to the boundary. The new face
    // holds the directed edge vt -> vl (vr -> vt), so a face that holds it
    // now is one that moves; none when vs had no other face.
    const bool ccw = s.vr < 0;
    int f = ccw ? face_after(mesh, vertex_faces, s.vt, s.vl)
                : face_before(mesh, vertex_faces, s.vt, s.vr);
    for (std::size_t guard = vertex_faces[s.vt].size(); f >= 0; --guard) {
      if (guard == 0) fail("vt's fan does not reach the boundary");
      const Triangle& t = mesh.triangles[f];
      const int k = corner_of(t, s.vt);
      const int next = ccw ? t[(k + 2) % 3] : t[(k + 1) % 3];
      move_to_vs(f);
      f = ccw ? face_after(mesh, vertex_faces, s.vt, next)
              : face_before(mesh, vertex_faces, s.vt, next);
    }
    if (ccw)
      add_face(mesh, vertex_faces, {s.vs, s.vt, s.vl});
    else
      add_face(mesh, vertex_faces, {s.vt, s.vs, s.vr});
    mesh.positions[s.vs] = s.position;
    return;
  }

  int f = face_after(mesh, vertex_faces, s.vt, s.vl);
  if (f < 0) fail("no face (vt, vl, *)");
  for (std::size_t guard = vertex_faces[s.vt].size();; --guard) {
    if (guard == 0) fail("the fan from vl does not reach vr");
    Triangle& t = mesh.triangles[f];
    const int k = corner_of(t, s.vt);
    const int next = t[(k + 2) % 3];
    t[k] = s.vs;
    std::erase(vertex_faces[s.vt], f);
    vertex_faces[s.vs].push_back(f);
    if (next == s.vr) break;
    f = face_after(mesh, vertex_faces, s.vt, next);
    if (f < 0) fail("vt's fan is broken");
  }
  add_face(mesh, vertex_faces, {s.vs, s.vt, s.vl});
  add_face(mesh, vertex_faces, {s.vt, s.vs, s.vr});
  mesh.positions[s.vs] = s.position;
}

}  // namespace

TriangleMesh replay(const ProgressiveMesh& pm, std::size_t count) {
  count = std::min(count, pm.splits.size());
  TriangleMesh mesh;
  mesh.positions = pm.base.positions;
  mesh.triangles.reserve(pm.base.n_faces() + 2 * count);
  std::vector<std::vector<int>> vertex_faces(mesh.n_vertices());
  for (const Triangle& t : pm.base.triangles) add_face(mesh, vertex_faces, t);
  for (std::size_t i = 0; i < count; ++i) apply_split(mesh, vertex_faces, pm.splits[i], i);
  return mesh;
}

TriangleMesh base_mesh(const ProgressiveMesh& pm) {
  std::vector<int> index(pm.base.n_vertices(), -1);
  TriangleMesh mesh;
  for (std::size_t i = 0; i < pm.base_vertices.size(); ++i) {
    index.at(pm.base_vertices[i]) = static_cast<int>(i);
    mesh.positions.push_back(pm.base.positions[pm.base_vertices[i]]);
  }
  for (const Triangle& t : pm.base.triangles) {
    Triangle r;
    for (int k = 0; k < 3; ++k) {
      r[k] = index.at(t[k]);
      if (r[k] < 0)
        throw std::runtime_error("base_mesh: base face uses vertex " + std::to_string(t[k]) +
                                 ", which is not a base vertex");
    }
    mesh.triangles.push_back(r);
  }
  return mesh;
}

}  // namespace ism

namespace ism {

std::optional<std::string> replay_mismatch(const ProgressiveMesh& pm, const TriangleMesh& surface) {
  TriangleMesh full;
  try {
    full = replay(pm);
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
  if (full.n_vertices() != surface.n_vertices())
    return std::to_string(full.n_vertices()) + " vertices replayed, the surface has " +
           std::to_string(surface.n_vertices());
  if (full.positions != surface.positions) return "a replayed position differs";
  auto canonical = [](std::vector<Triangle> faces) {
    for (Triangle& t : faces) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    std::sort(faces.begin(), faces.end());
    return faces;
  };
  if (canonical(full.triangles) != canonical(surface.triangles))
    return "the replayed faces differ from the surface's";
  return std::nullopt;
}

}  // namespace ism
