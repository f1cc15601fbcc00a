// ism-info MESH [--json]: what a mesh is (sizes, topology, defects) and what
// reading it repaired. Exit 0 for one connected, orientable 2-manifold of any
// genus, with or without boundary; 1 with the defect otherwise.
#include "pipeline/mesh_info.hpp"
#include "tool/cli.hpp"
#include "tool/failure.hpp"

#include <cstdio>
#include <iostream>

namespace {

const char* yes_no(bool b) {
  return b ? "yes" : "no";
}

void print_check(const std::string& file, const ism::MeshCheck& c) {
  std::printf("%s\n", file.c_str());
  std::printf("  vertices %zu, edges %zu, faces %zu\n", c.vertices, c.edges, c.faces);
  std::printf("  components %zu, boundary loops %zu, Euler characteristic %ld, genus %s\n",
              c.components, c.boundary_loops, c.euler_characteristic,
              c.genus ? std::to_string(*c.genus).c_str() : "undefined");
  for (std::size_t l = 0; l < c.loops.size(); ++l)
    std::printf("  boundary loop %zu: %zu vertices, length %.6g\n", l, c.loops[l].vertices,
                c.loops[l].length);
  std::printf("  manifold %s, orientable %s, closed %s\n", yes_no(c.manifold()),
              yes_no(c.orientable), yes_no(c.closed()));
  std::printf("  bounding-box diagonal %.6g, area %.6g\n", c.bounding_box_diagonal, c.area);
  std::printf(
      "  zero-area faces %zu, non-manifold edges %zu, non-manifold vertices %zu, "
      "non-finite coordinates %zu\n",
      c.degenerate_faces, c.nonmanifold_edges, c.nonmanifold_vertices, c.nonfinite_coordinates);
  for (const auto& r : c.repairs()) std::printf("  repaired: %s\n", r.c_str());
  for (const auto& w : c.warnings()) std::printf("  warning: %s\n", w.c_str());
  for (const auto& d : c.defects()) std::printf("  defect: %s\n", d.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ism-info: check a triangle mesh and print its topology"};
  ism::tool::CommonOptions common;
  std::string input;
  bool json = false;
  app.add_option("mesh", input, "Mesh file (.obj, .ply, .off, .stl)")->required();
  app.add_flag("--json", json, "Print the report as JSON on stdout");
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);

  return ism::tool::run_main("ism-info", [&] {
    ism::tool::Run run("ism-info", common);
    const ism::pipeline::MeshInfo info = ism::pipeline::mesh_info(run, {input, std::nullopt});
    if (json)
      std::cout << ism::report_text(info.info) << '\n';
    else
      print_check(input, info.check);
    run.finish();
    const auto unmet = ism::unmet_requirement(info.check, {.tool = "ism-info"});
    if (unmet) throw ism::tool::Failure(input + ": " + *unmet);
    return 0;
  });
}
