// Refinement of M² by one vertex split of its progressive mesh, with the map
// updated locally: the new vertex is embedded inside the old one-ring, close
// to the split vertex, in the sector of the faces it takes over, so every
// face stays positive; optimisation then moves it to a good place.
#include "map/surface_map.hpp"

#include <cmath>
#include <stdexcept>

namespace ism {

int SurfaceMap::split_next() {
  if (next_split_ >= pm_.splits.size()) return -1;
  const VertexSplit& s = pm_.splits[next_split_];
  const std::string where = "split " + std::to_string(next_split_) + " (vertex " +
                            std::to_string(s.vs) + " from " + std::to_string(s.vt) + ")";

  // The ring of vt in a chart, starting at the face (vt, vl, *): for a
  // vertex on a cone the fan vl..vr is then unwrapped contiguously.
  Ring ring;
  if (!build_ring(s.vt, ring, s.vl)) throw std::runtime_error(where + ": invalid ring");
  const std::size_t m = ring.faces.size();
  const int x = at_domain_vertex_[s.vt];
  std::size_t last = m;  // index of vr in the ring
  for (std::size_t i = 1; i < m; ++i)
    if (ring.vertices[i] == s.vr) last = i;
  if (last == m) throw std::runtime_error(where + ": vr is not a neighbour after vl");

  // A cone keeps the larger share of its angle: when vs takes at least half
  // of it, vs goes onto the cone and vt moves off (with more than 2π a cone
  // could otherwise leave vs a one-ring that cannot be flat).
  if (x >= 0 && domain_.is_cone(x) && !is_fixed(x)) {
    double sector = 0.0;
    for (std::size_t i = 0; i < last; ++i) {
      const Vec2 a = ring.positions[i], b = ring.positions[i + 1];
      sector += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    }
    if (sector >= 0.5 * domain_.total_angle(x)) return split_onto_cone(ring, last, where);
  }

  // vs goes to the middle of the kernel of its new one-ring (vl .. vr, vt):
  // exactly the places where all its faces, and the two new ones, are
  // positive.
  const Vec2 pt = ring.centre;
  std::vector<Vec2> polygon(ring.positions.begin(), ring.positions.begin() + last + 1);
  polygon.push_back(pt);
  const std::optional<Vec2> kernel = kernel_centroid(polygon);
  if (!kernel) throw SplitBlocked(where + ": no valid position for the new vertex");
  Vec2 ps = *kernel;
  // Locate vs in M¹: from vt's position, in the face holding direction d.
  int face = ring.centre_face;
  std::array<Vec2, 3> layout = ring.centre_layout;
  if (x >= 0) {
    for (std::size_t i = 0; i < domain_.fan(x).size(); ++i) {
      const Triangle& t = domain_.mesh().triangles[face];
      const int c = t[0] == x ? 0 : t[1] == x ? 1 : 2;
      if (orient(layout[c], layout[(c + 1) % 3], ps) >= 0 &&
          orient(layout[c], ps, layout[(c + 2) % 3]) >= 0)
        break;
      layout = domain_.unfold(face, layout, (c + 2) % 3);
      face = domain_.neighbour(face, (c + 2) % 3);
    }
  }
  EdgeWalk scratch;
  WalkEnd at;
  if (!trace(face, layout, pt, ps, scratch, at))
    throw std::runtime_error(where + ": cannot locate");
  ps = interior_point(at.layout, ps);

  // Walks from vs to vl..vr and to vt.
  std::vector<EdgeWalk> forward(last + 1);
  for (std::size_t i = 0; i <= last; ++i) {
    WalkEnd e;
    if (!trace(at.face, at.layout, ps, ring.positions[i], forward[i], e))
      throw std::runtime_error(where + ": cannot trace a new edge");
  }
  EdgeWalk to_vt;
  {
    WalkEnd e;
    if (!trace(at.face, at.layout, ps, pt, to_vt, e))
      throw std::runtime_error(where + ": cannot trace the new edge to vt");
  }
  const EdgeWalk vt_to_vl = walks_[ring.faces[0]][ring.corner[0]];
  const EdgeWalk vr_to_vt = walks_[ring.faces[last - 1]][(ring.corner[last - 1] + 2) % 3];

  // Topology: the fan vl..vr moves from vt to vs.
  for (std::size_t i = 0; i < last; ++i) {
    const int f = ring.faces[i], c = ring.corner[i];
    move_corner(f, c, s.vs);
    walks_[f][c] = forward[i];
    walks_[f][(c + 2) % 3] = reversed(forward[i + 1]);
  }
  set_location(s.vs, at.face, at.layout, ps);
  pinned_[s.vs] = 0;
  const int a = int(faces_.size());
  add_face({s.vs, s.vt, s.vl});
  walks_[a] = {to_vt, vt_to_vl, reversed(forward[0])};
  const int b = int(faces_.size());
  add_face({s.vt, s.vs, s.vr});
  walks_[b] = {reversed(to_vt), forward[last], vr_to_vt};
  ++active_vertices_;
  ++next_split_;
  return s.vs;
}

int SurfaceMap::split_onto_cone(const Ring& fan, std::size_t last, const std::string& where) {
  const VertexSplit& s = pm_.splits[next_split_];
  const int x = at_domain_vertex_[s.vt];
  // vt's ring from vr: vr .. vl are the faces vt keeps; with vs on the cone
  // (the origin of the fan chart) they form vt's new one-ring.
  Ring ring;
  if (!build_ring(s.vt, ring, s.vr)) throw std::runtime_error(where + ": invalid ring");
  std::size_t j = ring.vertices.size();
  for (std::size_t i = 1; i < ring.vertices.size(); ++i)
    if (ring.vertices[i] == s.vl) j = i;
  if (j == ring.vertices.size())
    throw std::runtime_error(where + ": vl is not a neighbour after vr");
  std::vector<Vec2> polygon(ring.positions.begin(), ring.positions.begin() + j + 1);
  polygon.push_back(Vec2::Zero());
  const std::optional<Vec2> kernel = kernel_centroid(polygon);
  if (!kernel) throw SplitBlocked(where + ": no valid position for the split vertex");
  Vec2 p = *kernel;
  int face = ring.centre_face;
  std::array<Vec2, 3> layout = ring.centre_layout;
  EdgeWalk scratch;
  WalkEnd at;
  if (!wedge_containing(x, face, layout, p) || !trace(face, layout, Vec2::Zero(), p, scratch, at))
    throw std::runtime_error(where + ": cannot locate the split vertex");
  p = interior_point(at.layout, p);
  std::vector<EdgeWalk> forward(j + 1);
  for (std::size_t i = 0; i <= j; ++i) {
    WalkEnd e;
    if (!trace(at.face, at.layout, p, ring.positions[i], forward[i], e))
      throw std::runtime_error(where + ": cannot trace a new edge");
  }
  EdgeWalk to_cone;
  {
    WalkEnd e;
    if (!trace(at.face, at.layout, p, Vec2::Zero(), to_cone, e))
      throw std::runtime_error(where + ": cannot trace the new edge to the cone");
  }
  // Segments that do not move: cone -> vr and vl -> cone.
  const EdgeWalk cone_to_vr = walks_[ring.faces[0]][ring.corner[0]];
  const EdgeWalk vl_to_cone = walks_[ring.faces[j - 1]][(ring.corner[j - 1] + 2) % 3];

  // The fan vl..vr goes to vs, which sits where vt sat: its walks stay.
  for (std::size_t i = 0; i < last; ++i) {
    const int f = fan.faces[i], c = fan.corner[i];
    move_corner(f, c, s.vs);
  }
  // vt moves to p: new walks in the faces it keeps.
  for (std::size_t i = 0; i < j; ++i) {
    const int f = ring.faces[i], c = ring.corner[i];
    walks_[f][c] = forward[i];
    walks_[f][(c + 2) % 3] = reversed(forward[i + 1]);
  }
  at_domain_vertex_[s.vs] = x;
  location_[s.vs] = location_[s.vt];
  pinned_[s.vs] = 1;
  pinned_[s.vt] = 0;
  set_location(s.vt, at.face, at.layout, p);
  const int a = int(faces_.size());
  add_face({s.vs, s.vt, s.vl});
  walks_[a] = {reversed(to_cone), forward[j], vl_to_cone};
  const int b = int(faces_.size());
  add_face({s.vt, s.vs, s.vr});
  walks_[b] = {to_cone, cone_to_vr, reversed(forward[0])};
  ++active_vertices_;
  ++next_split_;
  std::vector<int> touched = vertex_faces_[s.vs];
  touched.insert(touched.end(), vertex_faces_[s.vt].begin(), vertex_faces_[s.vt].end());
  if (!faces_are_valid(touched))
    throw std::runtime_error(where + ": the cone could not move to the new vertex");
  return s.vs;
}

}  // namespace ism
