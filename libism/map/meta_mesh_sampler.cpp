#include "map/meta_mesh_sampler.hpp"

#include "map/meta_cut.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ism {

MetaMeshSampler::MetaMeshSampler(const MetaMesh& meta) {
  auto pieces = meta_pieces(meta);
  if (!pieces) throw std::invalid_argument("MetaMeshSampler: the meta-mesh does not validate");
  index(meta, *pieces);
}

MetaMeshSampler::MetaMeshSampler(const MetaMesh& meta, std::vector<MetaPiece> pieces) {
  index(meta, pieces);
}

void MetaMeshSampler::index(const MetaMesh& meta, const std::vector<MetaPiece>& pieces) {
  // Of each piece: its faces, and its triangulation's triangles and points.
  face_.reserve(pieces.size());
  first_point_.assign(1, 0);
  first_triangle_.assign(1, 0);
  for (const MetaPiece& piece : pieces) {
    const PieceTriangulation tri = triangulate_piece(piece);
    face_.push_back(piece.face);
    for (int m = 0; m < 2; ++m)
      point_[m].insert(point_[m].end(), tri.points[m].begin(), tri.points[m].end());
    triangle_.insert(triangle_.end(), tri.triangles.begin(), tri.triangles.end());
    first_point_.push_back(int(point_[0].size()));
    first_triangle_.push_back(int(triangle_.size()));
  }
  for (int m = 0; m < 2; ++m) {
    const MetaSide& side = meta.side[m];
    const std::size_t nf = side.faces.size();
    layout_[m].resize(nf);
    for (std::size_t f = 0; f < nf; ++f) layout_[m][f] = meta_face_layout(side.lengths[f]);
    std::vector<std::vector<int>> in_face(nf);
    for (std::size_t i = 0; i < face_.size(); ++i) in_face[face_[i][m]].push_back(int(i));
    grid_[m].resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      Grid& g = grid_[m][f];
      const auto& l = layout_[m][f];
      g.lo = l[0].cwiseMin(l[1]).cwiseMin(l[2]);
      const Vec2 hi = l[0].cwiseMax(l[1]).cwiseMax(l[2]);
      // About one piece per cell.
      g.n = std::max(1, int(std::ceil(std::sqrt(double(in_face[f].size())))));
      g.cell = std::max((hi - g.lo).maxCoeff() / g.n, 1e-300);
      auto cell_of = [&](const Vec2& p) {
        return Eigen::Vector2i(std::clamp(int((p.x() - g.lo.x()) / g.cell), 0, g.n - 1),
                               std::clamp(int((p.y() - g.lo.y()) / g.cell), 0, g.n - 1));
      };
      std::vector<std::vector<int>> cells(std::size_t(g.n) * g.n);
      for (int i : in_face[f]) {
        Vec2 a = point_[m][first_point_[i]], b = a;
        for (int j = first_point_[i]; j < first_point_[i + 1]; ++j)
          a = a.cwiseMin(point_[m][j]), b = b.cwiseMax(point_[m][j]);
        const Eigen::Vector2i c0 = cell_of(a), c1 = cell_of(b);
        for (int y = c0.y(); y <= c1.y(); ++y)
          for (int x = c0.x(); x <= c1.x(); ++x) cells[std::size_t(y) * g.n + x].push_back(i);
      }
      g.start.assign(1, 0);
      for (const auto& c : cells) {
        g.items.insert(g.items.end(), c.begin(), c.end());
        g.start.push_back(int(g.items.size()));
      }
    }
  }
}

std::optional<MetaPoint> MetaMeshSampler::map_point(int m, int face,
                                                    const Eigen::Vector3d& bary) const {
  if (m < 0 || m > 1 || face < 0 || std::size_t(face) >= layout_[m].size()) return std::nullopt;
  const auto& l = layout_[m][face];
  const Vec2 p = from_barycentric(bary, l);
  const Grid& g = grid_[m][face];
  const int x = std::clamp(int(std::floor((p.x() - g.lo.x()) / g.cell)), 0, g.n - 1);
  const int y = std::clamp(int(std::floor((p.y() - g.lo.y()) / g.cell)), 0, g.n - 1);
  const std::size_t c = std::size_t(y) * g.n + x;
  // The triangle of a piece's triangulation that p is deepest inside
  // (points on a shared side belong to either).
  int best = -1, best_triangle = 0;
  Eigen::Vector3d in = Eigen::Vector3d::Constant(-HUGE_VAL);
  for (int k = g.start[c]; k < g.start[c + 1]; ++k) {
    const int i = g.items[k];
    const Vec2* q = point_[m].data() + first_point_[i];
    for (int j = first_triangle_[i]; j < first_triangle_[i + 1]; ++j) {
      const auto& t = triangle_[j];
      const Eigen::Vector3d b = barycentric(p, q[t[0]], q[t[1]], q[t[2]]);
      if (b.minCoeff() > in.minCoeff()) in = b, best = i, best_triangle = j;
    }
  }
  if (best < 0 || in.minCoeff() < -1e-9) return std::nullopt;
  const auto& t = triangle_[best_triangle];
  const Vec2* r = point_[1 - m].data() + first_point_[best];
  const Vec2 image = in[0] * r[t[0]] + in[1] * r[t[1]] + in[2] * r[t[2]];
  const int other = face_[best][1 - m];
  const auto& lo = layout_[1 - m][other];
  Eigen::Vector3d out = barycentric(image, lo[0], lo[1], lo[2]).cwiseMax(0.0);
  out /= out.sum();
  return MetaPoint{other, out};
}

DomainSurfaceSampler::DomainSurfaceSampler(const MetaMesh& meta, const DomainGeometry& domain)
    : DomainSurfaceSampler(
          meta,
          [&] {
            auto pieces = meta_pieces(meta);
            if (!pieces)
              throw std::invalid_argument("DomainSurfaceSampler: the meta-mesh does not validate");
            return std::move(*pieces);
          }(),
          domain) {}

DomainSurfaceSampler::DomainSurfaceSampler(const MetaMesh& meta, std::vector<MetaPiece> pieces,
                                           const DomainGeometry& domain)
    : sampler_(meta, std::move(pieces)),
      faces_(meta.side[1].faces),
      positions_(meta.side[1].positions) {
  if (positions_.empty())
    throw std::invalid_argument("DomainSurfaceSampler: side 1 is not an embedded surface");
  side_face_.assign(domain.n_faces(), {-1, 0});
  const auto& faces = meta.side[0].faces;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto found = domain.find_face(faces[i]);
    if (!found) throw std::invalid_argument("DomainSurfaceSampler: a face is not a domain face");
    side_face_[(*found)[0]] = {int(i), (*found)[1]};
  }
}

std::optional<SurfacePoint> DomainSurfaceSampler::surface_point(int face,
                                                                const Eigen::Vector3d& bary) const {
  if (face < 0 || std::size_t(face) >= side_face_.size() || side_face_[face][0] < 0)
    return std::nullopt;
  // Side-0 corner k is the domain face's corner (k + r) % 3.
  const auto [f, r] = side_face_[face];
  const Eigen::Vector3d b(bary[r], bary[(r + 1) % 3], bary[(r + 2) % 3]);
  const auto q = sampler_.map_point(0, f, b);
  if (!q) return std::nullopt;
  const Triangle& t = faces_[q->face];
  return SurfacePoint{q->face, q->bary,
                      q->bary[0] * positions_[t[0]] + q->bary[1] * positions_[t[1]] +
                          q->bary[2] * positions_[t[2]]};
}

}  // namespace ism
