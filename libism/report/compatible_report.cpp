#include "report/report.hpp"

#include <set>

namespace ism {

Json compatible_partition_report(const CompatibleNetworks& networks,
                                 const std::array<ProgressiveMesh, 2>& pms) {
  Json j = Json::object();
  j["genus"] = networks.genus;
  j["boundary_loops"] = networks.boundary_loops;
  std::size_t given = 0;
  Json added = Json::array();
  for (std::size_t i = 0; i < networks.features.size(); ++i) {
    const FeaturePair& f = networks.features[i];
    if (f.origin == FeatureOrigin::given) {
      ++given;
      continue;
    }
    Json p = Json::object();
    p["base_vertex"] = i;
    p["a"] = f.vertex[0];
    p["b"] = f.vertex[1];
    p["origin"] = to_string(f.origin);
    added.push_back(p);
  }
  j["features_given"] = given;
  j["features_added"] = added.size();
  j["added"] = added;
  std::set<std::pair<int, int>> edges;
  for (const Triangle& t : networks.base.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  Json base = Json::object();
  base["vertices"] = networks.base.n_vertices();
  base["edges"] = edges.size();
  base["faces"] = networks.base.n_faces();
  j["base_mesh"] = base;
  j["patches"] = networks.base.n_faces();
  const char* const side[2] = {"a", "b"};
  for (int s = 0; s < 2; ++s) {
    const PathNetwork& net = networks.networks[s];
    Json n = Json::object();
    n["vertices"] = net.surface.n_vertices();
    n["faces"] = net.surface.n_faces();
    n["steiner_vertices"] = net.steiner_vertices();
    n["total_path_length"] = net.total_length();
    n["vertex_splits"] = pms[s].splits.size();
    n["relaxed_collapses"] = pms[s].relaxed_collapses;
    j[side[s]] = n;
  }
  Json search = Json::object();
  search["candidates_traced"] = networks.candidates_traced;
  search["sector_conflicts"] = networks.sector_conflicts;
  search["swirl_delays"] = networks.swirl_delays;
  search["reroutes"] = networks.reroutes;
  j["search"] = search;
  return j;
}

}  // namespace ism
