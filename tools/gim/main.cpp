// gim-remesh MESH -o IMAGE.exr: octahedral geometry image of a genus-0
// surface, closed or with holes (paper §6.3); the pipeline is
// pipeline/gim_remesh.hpp.
#include "pipeline/gim_remesh.hpp"
#include "tool/cli.hpp"

int main(int argc, char** argv) {
  using namespace ism;
  CLI::App app{"gim-remesh: octahedral geometry image of a genus-0 surface (holes are capped)"};
  pipeline::GimRemeshOptions o;
  tool::CommonOptions common;
  app.add_option("mesh", o.input.path,
                 "Genus-0 surface, closed or with holes (.obj, .ply, .off, .stl)")
      ->required();
  app.add_option("-o,--output", o.output,
                 "Geometry image (.exr, float RGB positions; A: 1 on the surface, 0 on a cap)")
      ->required();
  app.add_option("--size", o.size, "Image size n = 2^k+1");
  app.add_option("--metric", o.metric, "Face metric of the octahedron")
      ->check(CLI::IsMember({"right-isosceles", "equilateral"}));
  app.add_option("--features", o.features.path,
                 "6 vertex indices for +x -x +y -y +z -z (default: automatic)");
  tool::add_map_options(app, o.map);
  tool::add_core_option(app, o.map);
  app.add_option("--normals", o.normals, "Normal map (.exr) at the same samples");
  app.add_option("--mesh", o.mesh, "Remesh of the image (.obj, .ply, .off, .stl, .drc, .glb)");
  tool::add_mesh_file_options(app, o.mesh_file);
  app.add_option("--preview", o.preview, "PNG preview: image and shaded normals side by side");
  app.add_option("--cap-rings", o.cap.rings,
                 "Open surfaces: flat rings cutting each hole's fan cap (default 4; 0: the fan)")
      ->check(CLI::Range(0, 64));
  app.add_option("--cap-height", o.cap.height,
                 "Open surfaces: the cap's dome height, times the hole's radius (default 0: flat)")
      ->check(CLI::Range(0.0, 4.0));
  bool grid_points = false;
  app.add_flag("--grid-points", grid_points,
               "Every pixel at its grid point: folded triangles are not re-sampled nearby");
  app.add_option("--mask", o.mask, "PNG mask of an open surface: 255 on the surface, 0 on a cap");
  app.add_option("--dump-patches", o.dump_patches, "PLY of the path network's patches");
  tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  o.unfold = !grid_points;
  return tool::run_main("gim-remesh", [&] {
    tool::Run run("gim-remesh", common);
    pipeline::gim_remesh(run, o);
    run.finish();
    return 0;
  });
}
