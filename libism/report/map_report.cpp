#include "report/report.hpp"

#include <algorithm>

namespace ism {

Json map_report(const SurfaceMap& map, const MapMeasures& m, const RefineStats& stats) {
  Json j = Json::object();
  j["valid"] = true;
  j["faces"] = map.n_faces();
  j["symmetric_efficiency"] = m.symmetric_efficiency;
  j["efficiency_domain_to_surface"] = m.forward_efficiency;
  j["efficiency_surface_to_domain"] = m.backward_efficiency;
  j["optimizations"] = stats.optimizations;
  j["fast_path_fraction"] =
      double(stats.single_face_rings) / double(std::max<std::size_t>(1, stats.optimizations));
  j["split_repairs"] = stats.split_repairs;
  if (stats.reembeddings > 0) {
    j["global_reembeddings"] = stats.reembeddings;
    j["global_reembeddings_applied"] = stats.reembeddings_applied;
  }
  return j;
}

Json refine_timing(const SurfaceRefineStats& s, const InterSurfaceMap* map) {
  Json j = Json::object();
  Json& t = j["seconds_by_operation"];
  for (std::size_t k = 0; k < kChartKinds; ++k)
    t[std::string(chart_kind_name(ChartKind(k))) + (k ? "_charts" : "")] = s.seconds_by_chart[k];
  t["splits"] = s.seconds_splits;
  t["discs"] = s.seconds_discs;
  t["planning"] = s.seconds_planning;
  Json& n = j["optimizations_by_stage"];
  for (std::size_t k = 0; k < kRefineStages; ++k)
    n[refine_stage_name(RefineStage(k))] = s.optimizations_by_stage[k];
  if (map) {
    const MapOperationStats& o = map->stats();
    j["plans"] = {{"held", o.plans_held},
                  {"held_untouched", o.plans_untouched},
                  {"optimised_anew", o.plans_stale}};
  }
  return j;
}

namespace {

// What the symmetric core's operations did.
void add_operations(Json& j, const InterSurfaceMap& map, const SurfaceRefineStats& stats) {
  const MapOperationStats& o = map.stats();
  const double n = double(std::max<std::size_t>(1, o.optimizations));
  j["optimizations"] = o.optimizations;
  j["moves"] = o.moves;
  j["evaluations_per_optimization"] = double(o.evaluations) / n;
  j["fast_path_fraction"] = double(o.fast_path) / n;
  j["developed_fraction"] = double(o.developed) / n;
  j["general_fraction"] = double(o.general) / n;
  j["split_evaluations_per_split"] =
      double(o.split_evaluations) / double(std::max<std::size_t>(1, o.splits));
  j["splits_in_place"] = o.splits_in_place;
  j["split_retries"] = o.split_retries;
  j["splits_placed_in_a_later_round"] = o.splits_later_round;
  j["splits_old_vertex_moved"] = o.splits_old_moved;
  j["moves_predicted_off_1pc"] = o.mispredicted;
  j["worst_prediction"] = o.worst_prediction;
  j["sweeps"] = stats.sweeps;
  j["final_sweeps"] = stats.final_sweeps;
  j["hard_splits"] = stats.hard_splits;
  if (stats.features_released_early_at >= 0)
    j["features_released_early_at"] = stats.features_released_early_at;
  j["split_deferrals"] = stats.split_deferrals;
  j["large_chart_skips"] = stats.large_chart_skips;
  j["discs"] = stats.discs;
  j["discs_applied"] = stats.discs_applied;
  j["global_steps"] = stats.global_steps;
  j["global_steps_applied"] = stats.global_steps_applied;
  j["local_moves"] = stats.local_moves;
  if (stats.race_winner >= 0) {
    // (Efficiency 2 / energy: the symmetric energy's terms are area-scaled.)
    Json race = Json::object();
    race["efficiencies"] = Json::array();
    for (double e : stats.race_energies) race["efficiencies"].push_back(2 / e);
    race["kept"] = stats.race_winner;
    race["seconds"] = stats.seconds_race;
    j["coarse_race"] = race;
  }
}

}  // namespace

Json map_report(const InterSurfaceMap& map, const MapMeasures& m, const SurfaceRefineStats& stats) {
  Json j = Json::object();
  j["valid"] = true;
  j["core"] = "symmetric";
  j["faces"] = map.n_faces(1);
  j["domain_faces"] = map.n_faces(0);
  j["symmetric_efficiency"] = m.symmetric_efficiency;
  j["efficiency_domain_to_surface"] = m.forward_efficiency;
  j["efficiency_surface_to_domain"] = m.backward_efficiency;
  add_operations(j, map, stats);
  return j;
}

Json two_surface_map_report(const InterSurfaceMap& map, const MapMeasures& m,
                            const SurfaceRefineStats& stats) {
  Json j = Json::object();
  j["valid"] = true;
  j["faces"] = Json::array({map.n_faces(0), map.n_faces(1)});
  j["symmetric_efficiency"] = m.symmetric_efficiency;
  j["symmetric_dirichlet"] = 4 / m.symmetric_efficiency;
  j["efficiency_a_to_b"] = m.forward_efficiency;
  j["efficiency_b_to_a"] = m.backward_efficiency;
  j["seconds_refine"] = stats.seconds;
  add_operations(j, map, stats);
  return j;
}

Json distance_report(const SurfaceDistance& distance) {
  Json j = Json::object();
  j["psnr_db"] = distance.psnr_db;
  j["rms"] = distance.rms;
  j["rms_input_to_remesh"] = distance.rms_a_to_b;
  j["rms_remesh_to_input"] = distance.rms_b_to_a;
  j["hausdorff"] = distance.hausdorff;
  return j;
}

}  // namespace ism
