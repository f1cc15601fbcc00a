#include "report/report.hpp"

namespace ism {
namespace {

Json strings(const std::vector<std::string>& list) {
  Json a = Json::array();
  for (const auto& s : list) a.push_back(s);
  return a;
}

}  // namespace

Json to_json(const MeshCheck& c) {
  Json j = Json::object();
  j["vertices"] = c.vertices;
  j["edges"] = c.edges;
  j["faces"] = c.faces;
  j["components"] = c.components;
  j["boundary_loops"] = c.boundary_loops;
  Json loops = Json::array();
  for (const MeshCheck::Loop& l : c.loops) {
    Json lj = Json::object();
    lj["vertices"] = l.vertices;
    lj["length"] = l.length;
    loops.push_back(lj);
  }
  j["loops"] = loops;
  j["euler_characteristic"] = c.euler_characteristic;
  j["genus"] = c.genus ? Json(*c.genus) : Json();
  j["manifold"] = c.manifold();
  j["orientable"] = c.orientable;
  j["closed"] = c.closed();
  j["valid_surface"] = c.valid_surface();
  j["bounding_box_diagonal"] = c.bounding_box_diagonal;
  j["area"] = c.area;
  j["degenerate_faces"] = c.degenerate_faces;
  j["duplicate_faces"] = c.duplicate_faces;
  j["nonmanifold_edges"] = c.nonmanifold_edges;
  j["nonmanifold_vertices"] = c.nonmanifold_vertices;
  if (c.example_nonmanifold_edge) {
    Json e = Json::array();
    e.push_back(c.example_nonmanifold_edge->first);
    e.push_back(c.example_nonmanifold_edge->second);
    j["example_nonmanifold_edge"] = e;
  }
  if (c.example_nonmanifold_vertex) j["example_nonmanifold_vertex"] = *c.example_nonmanifold_vertex;
  j["nonfinite_coordinates"] = c.nonfinite_coordinates;
  j["repairs"] = strings(c.repairs());
  j["defects"] = strings(c.defects());
  j["warnings"] = strings(c.warnings());
  return j;
}

}  // namespace ism
