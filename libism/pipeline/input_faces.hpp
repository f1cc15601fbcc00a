#pragma once
// Internal to the pipelines: which faces of a map of a capped surface lie on
// the input and which on a cap.
#include "map/map.hpp"
#include "mesh/boundary.hpp"
#include "partition/partition.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

namespace ism::pipeline {

// Which faces of a map lie on the input surface and which on a cap. Every
// candidate network cuts the capped surface's faces at Steiner vertices
// (each at a position of its own), and a map's faces are its network's, so
// a face is known by its corners' positions whichever network it came from.
class InputFaces {
 public:
  using Key = std::array<double, 9>;

  void add(const PathNetwork& network, const CappedMesh& capped) {
    if (network.face_origin.size() != network.surface.n_faces())
      throw std::logic_error("the network does not record its faces' origins");
    for (std::size_t f = 0; f < network.surface.n_faces(); ++f)
      on_input_[key(network.surface.positions, network.surface.triangles[f])] =
          !capped.is_cap_face(network.face_origin[f]);
    for (std::size_t v = capped.input_vertices; v < capped.mesh.n_vertices(); ++v)
      cap_points_.insert(point_key(capped.mesh.positions[v]));
  }

  /// Per face of a map at any resolution: 0 where a corner is a vertex the
  /// caps added (a cap's centre or ring), else 1 (empty when there are no
  /// caps). At full resolution a face on the input never has such a corner,
  /// a cap face may (its corners all on the loop) : a coarse judge.
  std::vector<char> of_any_level(const SurfaceMap& map) const {
    return of_any_level(map.faces(), map.positions());
  }
  std::vector<char> of_any_level(const std::vector<Triangle>& faces,
                                 const std::vector<Vec3>& positions) const {
    if (on_input_.empty()) return {};
    std::vector<char> out(faces.size(), 1);
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (int v : faces[f])
        if (cap_points_.count(point_key(positions[v]))) out[f] = 0;
    return out;
  }

  /// Per face of the map: 1 on the input surface, 0 on a cap (empty when
  /// there are no caps: every face counts).
  std::vector<char> of(const SurfaceMap& map) const { return of(map.faces(), map.positions()); }

  /// The same for a surface at full resolution given by its faces and
  /// positions (side 1 of a map's meta-mesh, from either core).
  std::vector<char> of(const std::vector<Triangle>& faces,
                       const std::vector<Vec3>& positions) const {
    if (on_input_.empty()) return {};
    std::vector<char> out(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto it = on_input_.find(key(positions, faces[f]));
      if (it == on_input_.end())
        throw std::logic_error("a face of the map is not a face of its network");
      out[f] = it->second;
    }
    return out;
  }

 private:
  static Key key(const std::vector<Vec3>& positions, const Triangle& t) {
    std::array<Vec3, 3> p{positions[t[0]], positions[t[1]], positions[t[2]]};
    std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    Key k;
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) k[3 * c + i] = p[c][i];
    return k;
  }
  static std::array<double, 3> point_key(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
  std::map<Key, char> on_input_;
  std::set<std::array<double, 3>> cap_points_;
};

}  // namespace ism::pipeline
