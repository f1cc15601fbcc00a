#pragma once
// The map stage as every front end runs it once a network is chosen: the
// optional patch dump, then the refinement to full resolution with progress,
// a failure of the map core turned into one line a user can act on.
#include "partition/partition.hpp"
#include "refine/refine.hpp"
#include "tool/tool.hpp"

#include <string>

namespace ism::tool {

struct MapStage {
  std::string input;         // the surface's file, for messages
  std::string dump_patches;  // PLY of the network's patches; empty: none
  int final_sweeps = 8;      // RefineOptions::max_final_sweeps
  /// RefineOptions::global_flat_reembedding (only where it applies: a flat
  /// torus domain with released features).
  bool global_flat_reembedding = false;
  std::string hint;  // what to try when the optimisation fails
};

/// Writes the patch dump (if asked) and refines `map` to full resolution,
/// reporting on `progress`. Throws Failure "<tool>: the map optimisation
/// failed on <input> (<why>); <hint>" when the map core throws.
RefineStats run_map_stage(Run& run, const PathNetwork& network, SurfaceMap& map, Progress& progress,
                          const MapStage& stage);

}  // namespace ism::tool
