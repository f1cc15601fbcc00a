#include "tool/map_stage.hpp"

#include "tool/failure.hpp"

#include <stdexcept>

namespace ism::tool {

RefineStats run_map_stage(Run& run, const PathNetwork& network, SurfaceMap& map, Progress& progress,
                          const MapStage& stage) {
  if (!stage.dump_patches.empty())
    write_output(run, stage.dump_patches,
                 [&](const std::filesystem::path& p) { write_patch_dump(network, p); });
  RefineOptions options;
  options.max_final_sweeps = stage.final_sweeps;
  options.global_flat_reembedding = stage.global_flat_reembedding;
  options.progress = [&](double f) { progress.update(f); };
  try {
    return refine(map, options);
  } catch (const std::runtime_error& e) {
    throw Failure(run.tool_name() + ": the map optimisation failed on " + stage.input + " (" +
                  e.what() + "); " + stage.hint);
  }
}

}  // namespace ism::tool
