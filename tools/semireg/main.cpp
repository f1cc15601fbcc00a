// semireg MESH -o OUT (--base BASE | --base-vertices FILE | --base-size N):
// semi-regular remesh of a surface of any genus, closed or with boundary
// loops, over a coarse base mesh
// (paper §6.2); the pipeline is pipeline/semireg.hpp.
#include "pipeline/semireg.hpp"
#include "tool/cli.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "semireg: semi-regular remesh of a surface (closed or open) over a coarse base mesh"};
  ism::pipeline::SemiregOptions o;
  ism::tool::CommonOptions common;
  app.add_option("mesh", o.input.path,
                 "Surface of any genus, closed or with boundary loops (.obj, .ply, .off, .stl)")
      ->required();
  app.add_option("-o,--output", o.output,
                 "Semi-regular remesh (.obj, .ply, .off, .stl, .drc, .glb)")
      ->required();
  auto* base =
      app.add_option("--base", o.base.path,
                     "Base mesh (.obj, .ply, .off, .stl): vertices snap to the nearest surface "
                     "vertices, its faces give the connectivity");
  auto* size =
      app.add_option("--base-size", o.base_size, "Decimate the surface to a base of N vertices")
          ->check(CLI::Range(std::size_t(4), std::size_t(1) << 24));
  auto* vertices = app.add_option(
      "--base-vertices", o.base_vertices.path,
      "Base vertices only (vertex indices or X Y Z points snapped to the surface, one per line); "
      "the connectivity is the dual of their geodesic Voronoi regions");
  base->excludes(size)->excludes(vertices);
  size->excludes(base)->excludes(vertices);
  vertices->excludes(base)->excludes(size);
  app.add_option("--levels", o.levels, "Subdivision levels of each base face (faces x 4^levels)")
      ->check(CLI::Range(0, 8));
  bool grid_points = false;
  app.add_flag("--grid-points", grid_points,
               "Every vertex at its grid point: folded triangles are not re-sampled nearby");
  app.add_option("--write-base", o.write_base, "Write the base used, its vertices on the surface");
  app.add_option("--dump-patches", o.dump_patches, "PLY of the path network's patches");
  ism::tool::add_map_options(app, o.map);
  ism::tool::add_core_option(app, o.map);
  ism::tool::add_mesh_file_options(app, o.mesh_file);
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  o.unfold = !grid_points;
  return ism::tool::run_main("semireg", [&] {
    ism::tool::Run run("semireg", common);
    ism::pipeline::semireg(run, o);
    run.finish();
    return 0;
  });
}
