#include "map/common_refinement.hpp"

#include "map/domain_geometry.hpp"
#include "map/meta_cut.hpp"

#include <map>
#include <stdexcept>

namespace ism {

namespace {

// The 3D point of a point given in face f's canonical layout.
Vec3 place(const MetaSide& side, const std::array<Vec2, 3>& layout, int f, const Vec2& p) {
  const Eigen::Vector3d b = barycentric(p, layout[0], layout[1], layout[2]);
  const Triangle& t = side.faces[std::size_t(f)];
  return b[0] * side.positions[t[0]] + b[1] * side.positions[t[1]] + b[2] * side.positions[t[2]];
}

}  // namespace

CommonRefinement common_refinement(const MetaMesh& meta, std::span<const MetaPiece> pieces) {
  for (const MetaSide& side : meta.side)
    if (side.positions.size() != side.n_vertices())
      throw std::invalid_argument("common_refinement: both sides must be embedded surfaces");
  CommonRefinement out;
  std::map<NodeKey, int> index;
  std::vector<int> local;
  for (const MetaPiece& piece : pieces) {
    std::array<std::array<Vec2, 3>, 2> layout;
    for (int s = 0; s < 2; ++s)
      layout[std::size_t(s)] =
          meta_face_layout(meta.side[std::size_t(s)].lengths[std::size_t(piece.face[s])]);
    const PieceTriangulation tri = triangulate_piece(piece);
    if (tri.triangles.empty())
      throw std::invalid_argument("common_refinement: a piece of faces " +
                                  std::to_string(piece.face[0]) + " and " +
                                  std::to_string(piece.face[1]) + " has no triangulation");
    local.assign(tri.points[0].size(), -1);
    for (std::size_t k = 0; k < tri.points[0].size(); ++k) {
      if (k < piece.nodes.size()) {
        const auto [it, added] = index.emplace(piece.nodes[k], int(out.positions[0].size()));
        local[k] = it->second;
        if (!added) continue;
        const NodeKey& n = piece.nodes[k];
        out.mesh_vertex.push_back(n.kind == 0 ? std::array<int, 2>{n.a, n.b}
                                              : std::array<int, 2>{-1, -1});
      } else {
        local[k] = int(out.positions[0].size());
        out.mesh_vertex.push_back({-1, -1});
      }
      for (int s = 0; s < 2; ++s)
        out.positions[std::size_t(s)].push_back(place(meta.side[std::size_t(s)],
                                                      layout[std::size_t(s)], piece.face[s],
                                                      tri.points[std::size_t(s)][k]));
    }
    for (const auto& t : tri.triangles) {
      out.triangles.push_back(
          {local[std::size_t(t[0])], local[std::size_t(t[1])], local[std::size_t(t[2])]});
      out.face.push_back(piece.face);
    }
  }
  return out;
}

}  // namespace ism
