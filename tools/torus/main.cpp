// torus-remesh MESH -o OUT: valence-4 remesh of a closed genus-1 surface
// (paper §6.4); the pipeline is pipeline/torus_remesh.hpp.
#include "pipeline/torus_remesh.hpp"
#include "tool/cli.hpp"

int main(int argc, char** argv) {
  using namespace ism;
  CLI::App app{"torus-remesh: valence-4 grid remesh of a closed genus-1 surface"};
  pipeline::TorusRemeshOptions o;
  tool::CommonOptions common;
  app.add_option("mesh", o.input.path, "Closed genus-1 surface (.obj, .ply, .off, .stl)")
      ->required();
  app.add_option("-o,--output", o.output,
                 "Grid remesh: quads as .obj, .ply, .off; with --triangulate also .stl, .drc; .glb "
                 "(triangles)")
      ->required();
  app.add_option("--features", o.features.path,
                 "9 features, row-major in the 3x3 torus grid: vertex indices, points (snapped), "
                 "or ROW COL INDEX X Y Z lines (default: automatic)");
  app.add_option("--size", o.size, "Grid size N (NxN) or UxV, at least 3x3")->capture_default_str();
  app.add_flag("--triangulate", o.triangulate, "Write two triangles per grid quad");
  app.add_option("--image", o.image, "Periodic geometry image (.exr, V rows x U columns)");
  app.add_option("--dump-patches", o.dump_patches, "PLY of the path network's patches");
  tool::add_map_options(app, o.map);
  tool::add_core_option(app, o.map, RefineOptions{}.reembed_max_vertices);
  app.add_flag("--no-global-reembedding", o.no_global_reembedding,
               "Optimise one vertex at a time only (no global flat-torus re-embeddings)");
  bool grid_points = false;
  app.add_flag("--grid-points", grid_points,
               "Every vertex at its grid point: folded triangles are not re-sampled nearby");
  tool::add_mesh_file_options(app, o.mesh_file);
  tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  o.unfold = !grid_points;
  return tool::run_main("torus-remesh", [&] {
    tool::Run run("torus-remesh", common);
    pipeline::torus_remesh(run, o);
    run.finish();
    return 0;
  });
}
