#include "report/report.hpp"

#include <set>

namespace ism {

Json partition_report(const PathNetwork& network, const TriangleMesh& domain,
                      const ProgressiveMesh& pm) {
  Json j = Json::object();
  j["features"] = network.features.size();
  j["steiner_vertices"] = network.steiner_vertices();
  j["patches"] = domain.n_faces();
  j["total_path_length"] = network.total_length();
  // Per patch: faces and Euler characteristic V - E + F of its faces.
  std::vector<std::set<int>> vertices(domain.n_faces());
  std::vector<std::set<std::pair<int, int>>> edges(domain.n_faces());
  std::vector<long> faces(domain.n_faces(), 0);
  for (std::size_t f = 0; f < network.surface.n_faces(); ++f) {
    const int p = network.face_patch[f];
    const Triangle& t = network.surface.triangles[f];
    ++faces[p];
    for (int k = 0; k < 3; ++k) {
      vertices[p].insert(t[k]);
      edges[p].insert(std::minmax(t[k], t[(k + 1) % 3]));
    }
  }
  Json list = Json::array();
  for (std::size_t p = 0; p < domain.n_faces(); ++p) {
    Json patch = Json::object();
    patch["faces"] = faces[p];
    patch["euler_characteristic"] = long(vertices[p].size()) - long(edges[p].size()) + faces[p];
    list.push_back(patch);
  }
  j["patch_list"] = list;
  const TriangleMesh base = base_mesh(pm);
  std::set<std::pair<int, int>> base_edges;
  for (const Triangle& t : base.triangles)
    for (int k = 0; k < 3; ++k) base_edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  Json b = Json::object();
  b["vertices"] = base.n_vertices();
  b["edges"] = base_edges.size();
  b["faces"] = base.n_faces();
  j["base_mesh"] = b;
  j["vertex_splits"] = pm.splits.size();
  j["relaxed_collapses"] = pm.relaxed_collapses;
  return j;
}

}  // namespace ism
