// Folded triangles of a semi-regular remesh re-sampled at nearby points of
// their base face or edge (unfold_semiregular(), semiregular.hpp).
#include "sample/semiregular.hpp"
#include "sample/unfold.hpp"

#include <exception>
#include <stdexcept>

namespace ism {

UnfoldReport unfold_semiregular(
    const TriangleMesh& base, int levels,
    const std::function<Vec3(int face, const Eigen::Vector3d& bary)>& point, TriangleMesh& mesh,
    int max_rounds) {
  const SemiregularLayout layout = semiregular_layout(base, levels);
  if (layout.sites.size() != mesh.n_vertices() || layout.triangles.size() != mesh.n_faces())
    throw std::invalid_argument(
        "unfold_semiregular: the mesh is not the semi-regular mesh of the base at this level");
  const int n = 1 << levels;

  // Which face edges are base boundary edges (edge k: corner k to k + 1),
  // and the faces at each base vertex.
  const std::size_t nb = base.n_vertices();
  auto boundary_edge = [&](int f, int k) {
    return (layout.boundary_edges[std::size_t(f)] >> k & 1) != 0;
  };
  std::vector<char> on_boundary(mesh.n_vertices(), 0);
  std::vector<std::vector<SemiregularSite>> corner_sites(nb);
  const int corner_i[3] = {0, n, 0}, corner_j[3] = {0, 0, n};
  for (int f = 0; f < int(base.n_faces()); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = base.triangles[std::size_t(f)][k];
      corner_sites[std::size_t(v)].push_back({f, corner_i[k], corner_j[k]});
      if (boundary_edge(f, k))
        on_boundary[std::size_t(v)] = on_boundary[std::size_t(base.triangles[f][(k + 1) % 3])] = 1;
    }
  for (std::size_t v = nb; v < mesh.n_vertices(); ++v) {
    const SemiregularSite& s = layout.sites[v];
    if (s.face >= 0 && layout.second_sites[v].face < 0)
      on_boundary[v] = (s.j == 0 && boundary_edge(s.face, 0)) ||
                       (s.i + s.j == n && boundary_edge(s.face, 1)) ||
                       (s.i == 0 && boundary_edge(s.face, 2));
  }
  // The face edge a move from (i, j) by (di, dj) runs along, if any.
  auto along_boundary = [&](const SemiregularSite& s, const int d[2]) {
    return (s.j == 0 && d[1] == 0 && boundary_edge(s.face, 0)) ||
           (s.i + s.j == n && d[0] + d[1] == 0 && boundary_edge(s.face, 1)) ||
           (s.i == 0 && d[0] == 0 && boundary_edge(s.face, 2));
  };

  // Grid directions (di, dj): the six neighbours of an interior grid point.
  static constexpr int kDirections[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
  static constexpr double kSteps[3] = {0.25, 0.5, 0.75};
  std::vector<SemiregularSite> sites;
  auto candidates = [&](int v, std::vector<Vec3>& out) {
    // The vertex's grid point on each base face holding it.
    sites.clear();
    if (std::size_t(v) < nb) {
      sites = corner_sites[std::size_t(v)];
    } else {
      for (const SemiregularSite& s :
           {layout.sites[std::size_t(v)], layout.second_sites[std::size_t(v)]})
        if (s.face >= 0) sites.push_back(s);
    }
    for (double step : kSteps)
      for (const SemiregularSite& s : sites)
        for (const auto& d : kDirections) {
          if (s.i + d[0] < 0 || s.j + d[1] < 0 || s.i + d[0] + s.j + d[1] > n)
            continue;  // no grid neighbour there
          // On the base's boundary: along a boundary edge only.
          if (on_boundary[std::size_t(v)] && !along_boundary(s, d)) continue;
          try {
            out.push_back(point(s.face, layout.weights(s.i + step * d[0], s.j + step * d[1])));
          } catch (const std::exception&) {
          }
        }
  };
  return unfold_samples(mesh, candidates, {.max_rounds = max_rounds});
}

}  // namespace ism
