// ism-map A B [--features PAIRS] -o PREFIX: a continuous bijective
// piecewise-linear map between two closed surfaces of the same genus (the
// paper's subject), both refined to full resolution on the symmetric map
// core; the pipeline is pipeline/map_surfaces.hpp.
#include "pipeline/map_surfaces.hpp"
#include "tool/cli.hpp"

#include <string>

int main(int argc, char** argv) {
  CLI::App app{
      "ism-map: a bijective map between two closed surfaces of the same genus, optimised for "
      "symmetric stretch (the overlay pair, correspondences both ways, the meta-mesh)"};
  ism::pipeline::MapSurfacesOptions o;
  ism::tool::CommonOptions common;
  app.add_option("a", o.a.path, "Surface A (.obj, .ply, .off, .stl)")->required();
  app.add_option("b", o.b.path, "Surface B, closed, of A's genus")->required();
  app.add_option("--features", o.features,
                 "Feature pairs: 'IA IB' (0-based vertex indices) or 'XA YA ZA XB YB ZB' per "
                 "line; default: features chosen automatically");
  app.add_option("-o,--output", o.output_prefix,
                 "Write PREFIX_on_A.obj and PREFIX_on_B.obj (the overlay on each surface, same "
                 "vertex and face lists) and PREFIX_A_to_B.txt, PREFIX_B_to_A.txt (rows 'i j w', "
                 "three per source vertex)");
  app.add_option("--meta-mesh", o.meta_mesh, "Write the map as a meta-mesh file");
  app.add_flag("--hold-features", o.hold_features,
               "Keep the features on each other throughout (default: released half way through "
               "the refinement, see --release-features-at)");
  app.add_option("--release-features-at", o.release_features_at,
                 "Hold the features until this fraction (0 to 1) of the refinement's splits, then "
                 "release them (default 0.5; 0: released from the start)");
  app.add_option("--morph", o.morph,
                 "Write the overlay at (1 - T) A + T B as PREFIX_morph.obj (several T: "
                 "PREFIX_morph_000.obj, ...)");
  app.add_option("--morph-frames", o.morph_frames,
                 "Write N frames from A (T = 0) to B (T = 1) as PREFIX_frame_000.obj, ...");
  app.add_option("--transfer-field", o.transfer_field_a,
                 "Per-vertex values of A (one row per vertex of A, any number of columns) carried "
                 "onto B's vertices by barycentric interpolation: PREFIX_field_on_B.txt");
  app.add_option("--transfer-field-b", o.transfer_field_b,
                 "The same from B onto A's vertices: PREFIX_field_on_A.txt");
  app.add_flag("--morph-glb", o.morph_glb,
               "Write the overlay on A with the overlay on B as its morph target (weight 0: A, "
               "1: B) as glTF binary: PREFIX_morph.glb");
  app.add_flag("--transfer-uv", o.transfer_uv_a,
               "Carry A's texture coordinates (OBJ vt) onto B's vertices: PREFIX_B_uv.obj");
  app.add_flag("--transfer-uv-b", o.transfer_uv_b,
               "The same from B onto A's vertices: PREFIX_A_uv.obj");
  app.add_flag("--transfer-colors", o.transfer_colors_a,
               "Carry A's vertex colours (PLY red green blue, or OBJ 'v x y z r g b') onto B's "
               "vertices: PREFIX_B_colors.ply");
  app.add_flag("--transfer-colors-b", o.transfer_colors_b,
               "The same from B onto A's vertices: PREFIX_A_colors.ply");
  app.add_option_function<std::string>(
         "--schedule",
         [&o](const std::string& name) { o.schedule = *ism::pipeline::schedule_kind(name); },
         "Refinement schedule: thorough (2 level sweeps, relaxation gain 1e-4), fast (1 and "
         "1e-3), or auto: fast when both inputs together have " +
             std::to_string(ism::pipeline::kLargeMapFaces) + " faces or more (default auto)")
      ->check(CLI::IsMember(ism::pipeline::kScheduleNames))
      ->option_text(ism::pipeline::schedule_names("|"));
  app.add_option("--level-sweeps", o.level_sweeps,
                 "Sweeps over every vertex each time both sides have grown 1.5-fold (fewer once "
                 "a sweep gains under 0.1 %; default: the schedule's, 2 or 1)");
  app.add_option("--race-level-sweeps", o.race_level_sweeps,
                 "Level-sweep counts raced at the coarse levels: a copy of the map refined "
                 "with each until both sides have 500 faces (or a tenth of theirs), the lowest "
                 "energy goes on "
                 "(default 2,3)")
      ->delimiter(',');
  app.add_option("--relaxation-gain", o.relaxation_gain,
                 "After each level's sweeps, a vertex whose move gained more than this share of "
                 "the mean energy per vertex has its neighbours optimised again (default: the "
                 "schedule's, 1e-4 or 1e-3; larger is faster, and lands in another basin)");
  app.add_flag_callback(
      "--no-race", [&] { o.race_level_sweeps.clear(); },
      "Refine one map from the start (no coarse race)");
  app.add_option("--threads", o.threads,
                 "Threads planning the refinement's optimisations (0: all; the map is the same "
                 "for any number)")
      ->check(CLI::Range(0, 1024));
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  return ism::tool::run_main("ism-map", [&] {
    ism::tool::Run run("ism-map", common);
    ism::pipeline::map_surfaces(run, o);
    run.finish();
    return 0;
  });
}
