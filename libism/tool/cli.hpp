#pragma once
// The command-line side of the tool conventions. CLI11 is costly to compile:
// include this header only in a tool's main.cpp.
#include "io/draco_io.hpp"
#include "tool/limits.hpp"
#include "tool/map_stage.hpp"
#include "tool/tool.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace ism::tool {

/// --version, -q/--quiet, --report FILE and --max-memory SIZE, the same in
/// every tool; a refused command line printed in one line.
inline void add_common_options(CLI::App& app, CommonOptions& options) {
  // A refused command line is one line, as every other refusal (CLI11's
  // own message adds a second, "Run with --help for more information.").
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string(e.what()) + " (see --help)\n";
  });
  app.set_version_flag("--version", std::string(ISM_VERSION));
  app.add_flag("-q,--quiet", options.quiet, "No progress or notes on stderr");
  app.add_option("--report", options.report_path, "Write a JSON report (sizes, timings, measures)");
  app.add_option_function<std::string>(
         "--max-memory",
         [&options](const std::string& text) {
           const auto bytes = parse_memory_size(text);
           if (!bytes)
             throw CLI::ValidationError("--max-memory", "expected a size like 8G or 512M");
           options.max_memory = *bytes;
         },
         "Memory the run may take, e.g. 8G or 512M: outputs or inputs estimated to need more are "
         "refused before any work (default: half the machine's memory, " +
             format_bytes(double(default_memory_limit())) + ")")
      ->type_name("SIZE");
}

/// --draco-bits and --glb-draco, the same in every tool that writes meshes.
inline void add_mesh_file_options(CLI::App& app, io::MeshFileOptions& options) {
  app.add_option("--draco-bits", options.draco_bits,
                 "Draco position quantisation bits (.drc, and .glb with --glb-draco)")
      ->check(CLI::Range(8, 30));
  app.add_flag("--glb-draco", options.glb_draco,
               "Draco-compress .glb meshes (KHR_draco_mesh_compression; default: plain glTF)");
}

/// --hold-features, --final-sweeps, --inverse-weight, --contenders, --drop-behind and
/// --curvature-weight, the same
/// in every front end (each sets its own default variants in `settings`).
inline void add_map_options(CLI::App& app, MapSettings& settings) {
  app.add_option("--meta-mesh", settings.meta_mesh_path,
                 "The map as a meta-mesh: both meshes, each vertex located on the other, each "
                 "edge's crossings (text, README \"Meta-mesh files\")");
  app.add_flag("--hold-features", settings.hold_features,
               "Keep the features fixed during optimisation");
  app.add_option("--final-sweeps", settings.final_sweeps,
                 "Most optimisation sweeps at full resolution (more: lower stretch, longer run)")
      ->check(CLI::Range(0, 1000));
  app.add_option_function<double>(
         "--inverse-weight", [&settings](const double& w) { settings.set_inverse_weight(w); },
         "Weight of the inverse stretch (surface -> domain) in the optimised energy: 1 is the "
         "symmetric stretch, lower favours the one-way stretch domain -> surface (default: "
         "the tool's variants, each refined and the best kept)")
      ->check(CLI::Range(0.001, 1.0));
  app.add_option("--contenders", settings.contenders,
                 "How many of the best candidates at the coarse level (networks or bases) each "
                 "variant refines whole, the best final map kept: more can find a better map "
                 "where the coarse ranking misjudges, at that many times the map stage's work "
                 "(default 1; semireg on an open surface 2)")
      ->check(CLI::Range(1, 12));
  app.add_option("--drop-behind", settings.drop_behind,
                 "Symmetric core (gim-remesh, semireg): stop a variant or contender whose score "
                 "trails another's by more than this after each of the first two levels of its "
                 "refinement; the map kept is the same (default 0.01; negative: refine every one "
                 "whole)")
      ->check(CLI::Range(-1.0, 1.0));
  app.add_option("--curvature-weight", settings.curvature_weight,
                 "Weight the stretch by 1 + W * curvature / its RMS: more samples where the "
                 "surface bends, a closer remesh (PSNR) for a little stretch")
      ->check(CLI::Range(0.0, 100.0));
  // An energy setting given on the command line holds in every variant and
  // replaces the front end's fallbacks.
  app.add_option_function<double>(
         "--anisotropy-weight", [&settings](const double& w) { settings.set_anisotropy_weight(w); },
         "Weight of the penalty on faces whose map is more anisotropic "
         "than --anisotropy-threshold, in every variant (and no "
         "fallback variants)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option_function<double>(
         "--anisotropy-threshold",
         [&settings](const double& r) { settings.set_anisotropy_threshold(r); },
         "Ratio of the map's singular values above which the anisotropy penalty bites")
      ->check(CLI::Range(1.0, 1e6));
}

/// --core: which map core refines the chosen coarse map (MapSettings::core),
/// for the front ends that offer the symmetric one (semireg: closed surfaces), which
/// takes each coarse map over at `from_vertices` (MapStage::symmetric_from_vertices).
inline void add_core_option(CLI::App& app, MapSettings& settings,
                            std::size_t from_vertices = kSymmetricFromVertices) {
  app.add_option_function<std::string>(
         "--core",
         [&settings](const std::string& name) {
           settings.core = name == "symmetric" ? MapCore::symmetric : MapCore::surface_map;
         },
         "Map core: surface-map (default: every variant refined, the best kept) or "
         "symmetric (the one map both sides refine, paper §5, taking each coarse map "
         "over at " +
             std::to_string(from_vertices) + " surface vertices; closed surfaces)")
      ->check(CLI::IsMember({"surface-map", "symmetric"}))
      ->option_text("surface-map|symmetric");
}

}  // namespace ism::tool
