#include "tool/map_stage.hpp"

#include "io/io.hpp"
#include "report/report.hpp"
#include "tool/failure.hpp"
#include "tool/variant_race.hpp"

#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <functional>
#include <optional>
#include <stdexcept>

namespace ism::tool {

MapOptions MapSettings::map_options(std::size_t i) const {
  const MapVariant& v = variants.at(i);
  return {.release_features = !hold_features,
          .inverse_stretch_weight = v.inverse_stretch_weight,
          .cone_relaxation_rings = v.cone_relaxation_rings,
          .curvature_weight = curvature_weight,
          .anisotropy_weight = v.anisotropy_weight,
          .anisotropy_threshold = v.anisotropy_threshold};
}

void check_settings(const std::string& tool, const MapSettings& settings,
                    const io::MeshFileOptions& mesh_file) {
  auto in_range = [&](const char* option, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))  // NaN fails too
      throw Failure(tool + ": " + option + " must be in [" + Json(lo).dump() + ", " +
                    Json(hi).dump() + "], got " + Json(value).dump());
  };
  in_range("--final-sweeps", settings.final_sweeps, 0, 1000);
  in_range("--curvature-weight", settings.curvature_weight, 0, 100);
  in_range("--drop-behind", settings.drop_behind, -1, 1);
  in_range("--draco-bits", mesh_file.draco_bits, 8, 30);
  if (settings.variants.empty()) throw Failure(tool + ": no map variant to refine");
  for (const auto* list : {&settings.variants, &settings.fallback_variants})
    for (const MapVariant& v : *list) {
      in_range("--inverse-weight", v.inverse_stretch_weight, 0.001, 1.0);
      in_range("--anisotropy-weight", v.anisotropy_weight, 0, 1e6);
      in_range("--anisotropy-threshold", v.anisotropy_threshold, 1, 1e6);
    }
}

void MapSettings::set_inverse_weight(double w) {
  MapVariant v = variants.front();
  v.inverse_stretch_weight = w;
  variants = {v};
  fallback_variants.clear();
}

void MapSettings::set_anisotropy_weight(double w) {
  for (MapVariant& v : variants) v.anisotropy_weight = w;
  fallback_variants.clear();
}

void MapSettings::set_anisotropy_threshold(double ratio) {
  for (MapVariant& v : variants) v.anisotropy_threshold = ratio;
  fallback_variants.clear();
}

namespace {

// The symmetric core's refinement of a chosen coarse map (run_map_stage):
// the coarse map, refined by SurfaceMap to kSymmetricFromVertices surface
// vertices (as the network choice ranks candidates; there its discrete cone
// moves place the cones), is resumed as an InterSurfaceMap and refined on.
void refine_symmetric(MapStageResult& result, const MapVariant& variant,
                      const std::function<void(double)>& progress, const MapStage& stage,
                      const MapSettings& settings,
                      const std::function<bool(const InterSurfaceMap&)>& after_level) {
  SurfaceMap& coarse = *result.setup->map;
  if (coarse.n_vertices() < stage.symmetric_from_vertices) {
    RefineOptions options;
    options.stop_at_vertices = stage.symmetric_from_vertices;
    options.global_flat_reembedding = stage.global_flat_reembedding;
    options.local_disc_every = stage.local_disc_every;
    refine(coarse, options);
  }
  auto meta = meta_mesh(coarse);
  if (!meta) throw std::runtime_error("the coarse map does not validate");
  InterSurfaceOptions options;
  options.hold_features = settings.hold_features;
  options.inverse_weight = variant.inverse_stretch_weight;
  // The same curvature weight and anisotropy penalty.
  options.forward_density = coarse.forward_density();
  options.anisotropy_weight = coarse.options().anisotropy_weight;
  options.anisotropy_threshold = coarse.options().anisotropy_threshold;
  const ProgressiveMesh& pm = result.setup->pm();
  result.symmetric = std::make_unique<InterSurfaceMap>(
      std::move(*meta), side_from_domain(coarse.domain(), pm), side_from_pm(pm),
      std::array<std::size_t, 2>{0, coarse.splits_applied()}, options);
  SurfaceRefineOptions refine_options;
  refine_options.progress = progress;
  refine_options.max_final_sweeps = settings.final_sweeps;
  refine_options.local_disc_every = stage.symmetric_local_disc_every;
  // The cones are placed: their large charts are retried less and less.
  refine_options.large_chart_backoff = true;
  refine_options.before_final = stage.symmetric_before_final;
  // No optimisations planned ahead: over a static domain nearly every chart
  // is a fast one, whose plan saves less than a second thread slows the
  // commits down (semireg bunny --base-size 100: its refinement 19.9 and
  // 24.3 s planned, 16.1 and 16.4 s not; results-two-surfaces.md, stop 62).
  refine_options.threads = 1;
  refine_options.after_level = after_level;
  // ism-map's searches (docs/results-two-surfaces.md, stop 92).
  use_fast_searches(refine_options);
  try {
    result.symmetric_stats = refine_surfaces(*result.symmetric, refine_options);
  } catch (const std::exception& e) {
    throw std::runtime_error(describe_stop(*result.symmetric, e.what()));
  }
}

}  // namespace

MapStageResult run_map_stage(Run& run, Progress& progress, const MapStage& stage,
                             const MapSettings& settings, const ChooseMap& choose,
                             const MapScore& score) {
  // Both rounds' variants, in order: the first round, then the fallbacks.
  std::vector<MapVariant> all = settings.variants;
  const std::size_t contenders = std::max<std::size_t>(settings.contenders, 1);
  // Outcome i * contenders + k: variant i's coarse candidate of rank k.
  struct Outcome {
    MapStageResult result;
    std::exception_ptr error;
    bool used = false;  // false: the variant had fewer candidates
    double score = 0;
    MapMeasures measures;  // of the refined map (the symmetric core's: its pieces cut once)
    double seconds = 0;
    // Its scores after the levels the race judged (surface vertices, score).
    std::vector<std::pair<std::size_t, double>> levels;
    std::optional<VariantRace::Drop> dropped;  // stopped by the race
  };
  std::vector<Outcome> outcomes;
  // Races decide after the symmetric refinement's second level.
  constexpr std::size_t kDecideAtLevel = 1;
  const bool racing = settings.core == MapCore::symmetric && stage.symmetric_level_score;
  auto run_round = [&](std::size_t first, std::size_t last) {
    outcomes.resize(last * contenders);
    const std::size_t base = first * contenders;
    VariantRace race(outcomes.size() - base, kDecideAtLevel, racing ? settings.drop_behind : -1.0);
    // Two phases, each on every core: every variant's choice of coarse
    // maps, then every contender's refinement side by side (a variant whose
    // choice ends first would otherwise refine alone while the others
    // still choose, and the last one's refinement run alone at the end).
    std::vector<std::vector<std::unique_ptr<MapSetup>>> chosen(last - first);
    // (A contender's seconds: its variant's choice, then its refinement.)
    std::vector<double> choice_seconds(last - first);
    tbb::task_group choices;
    for (std::size_t i = first; i < last; ++i)
      choices.run([&, i] {
        const auto start = std::chrono::steady_clock::now();
        std::vector<std::unique_ptr<MapSetup>>& setups = chosen[i - first];
        try {
          MapSettings one = settings;
          one.variants = {all[i]};
          setups = choose(one.map_options(0), contenders);
          if (setups.empty()) throw std::logic_error("the map stage's choice returned no map");
        } catch (...) {
          setups.clear();
          Outcome& out = outcomes[i * contenders];
          out.used = true;
          out.error = std::current_exception();
          out.seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          for (std::size_t k = 0; k < contenders; ++k) race.finish(i * contenders + k - base);
          return;
        }
        for (std::size_t k = setups.size(); k < contenders; ++k)
          race.finish(i * contenders + k - base);
        choice_seconds[i - first] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      });
    choices.wait();
    // Each contender refined whole, side by side.
    tbb::task_group refinements;
    for (std::size_t i = first; i < last; ++i)
      for (std::size_t k = 0; k < std::min(contenders, chosen[i - first].size()); ++k)
        refinements.run([&, i, k] {
          const auto start = std::chrono::steady_clock::now();
          auto seconds = [&] {
            return choice_seconds[i - first] +
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          };
          std::vector<std::unique_ptr<MapSetup>>& setups = chosen[i - first];
          const std::size_t racer = i * contenders + k - base;
          Outcome& out = outcomes[i * contenders + k];
          out.used = true;
          out.result.setup = std::move(setups[k]);
          try {
            std::function<void(double)> report_progress;
            if (i == first && k == 0) report_progress = [&](double f) { progress.update(f); };
            if (settings.core == MapCore::symmetric) {
              std::function<bool(const InterSurfaceMap&)> after_level;
              if (racing)
                after_level = [&](const InterSurfaceMap& map) {
                  if (!race.scoring()) return !race.dropped(racer);
                  const double level_score = stage.symmetric_level_score(map);
                  out.levels.push_back({map.n_vertices(1), level_score});
                  return race.report(racer, level_score);
                };
              refine_symmetric(out.result, all[i], report_progress, stage, settings, after_level);
              race.finish(racer);
              if (race.dropped(racer)) {
                out.result.symmetric.reset();  // (its memory freed for the others)
              } else {
                const InterSurfaceMap& map = *out.result.symmetric;
                out.measures = map.measures();
                out.score = stage.symmetric_score ? stage.symmetric_score(map)
                                                  : out.measures.forward_efficiency;
              }
            } else {
              RefineOptions options;
              options.max_final_sweeps = settings.final_sweeps;
              options.global_flat_reembedding = stage.global_flat_reembedding;
              options.local_disc_every = stage.local_disc_every;
              options.progress = report_progress;
              out.result.stats = refine(*out.result.setup->map, options);
              out.score = score(*out.result.setup->map);
              out.measures = out.result.setup->map->measures();
            }
          } catch (...) {
            out.error = std::current_exception();
            race.finish(racer);
          }
          out.seconds = seconds();
        });
    refinements.wait();
    // Every map the race dropped is out, also one that finished before the
    // race was decided: the map kept does not depend on timing.
    for (std::size_t r = base; r < outcomes.size(); ++r)
      if ((outcomes[r].dropped = race.drop(r - base))) outcomes[r].result.symmetric.reset();
  };
  run_round(0, all.size());
  bool retry = false;
  auto competes = [](const Outcome& out) { return out.used && !out.error && !out.dropped; };
  for (const Outcome& out : outcomes) retry |= competes(out) && out.score < stage.retry_below;
  if (retry && !settings.fallback_variants.empty()) {
    const std::size_t first = all.size();
    all.insert(all.end(), settings.fallback_variants.begin(), settings.fallback_variants.end());
    run_round(first, all.size());
  }
  const std::size_t n = outcomes.size();

  std::optional<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
    if (competes(outcomes[i]) && (!kept || outcomes[i].score > outcomes[*kept].score)) kept = i;
  if (!kept) {
    // (The map leading the race is never dropped: here every map that was
    // not dropped failed.)
    std::exception_ptr first_error;
    for (const Outcome& out : outcomes)
      if (!first_error && out.error) first_error = out.error;
    try {
      std::rethrow_exception(first_error);
    } catch (const Failure&) {
      throw;
    } catch (const std::exception& e) {
      throw Failure(run.tool_name() + ": the map optimisation failed on " + stage.input + " (" +
                        e.what() + "); " + stage.hint,
                    Failure::Kind::internal);
    }
  }

  Json& r = run.report();
  r["map_core"] = settings.core == MapCore::symmetric ? "symmetric" : "surface_map";
  r["features_released"] = !settings.hold_features;
  r["curvature_weight"] = settings.curvature_weight;
  Json& variants = r["map_variants"] = Json::array();
  std::size_t used = 0, kept_position = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!outcomes[i].used) continue;
    ++used;
    if (i == *kept) kept_position = used;
    const MapVariant& variant = all[i / contenders];
    Json v = Json::object();
    v["inverse_stretch_weight"] = variant.inverse_stretch_weight;
    v["cone_relaxation_rings"] = variant.cone_relaxation_rings;
    v["anisotropy_weight"] = variant.anisotropy_weight;
    v["anisotropy_threshold"] = variant.anisotropy_threshold;
    v["fallback"] = i / contenders >= settings.variants.size();
    v["contender"] = i % contenders;
    if (outcomes[i].error) {
      try {
        std::rethrow_exception(outcomes[i].error);
      } catch (const std::exception& e) {
        v["error"] = e.what();
      }
    } else {
      const MapStageResult& result = outcomes[i].result;
      const MapMeasures& m = outcomes[i].measures;
      v["candidate"] = outcomes[i].result.setup->candidate;
      if (const auto& d = outcomes[i].dropped) {
        v["dropped"] = {{"after_level", d->checkpoint + 1},
                        {"surface_vertices", outcomes[i].levels.at(d->checkpoint).first},
                        {"score", d->score},
                        {"leader_score", d->leader}};
      } else {
        v["score"] = outcomes[i].score;
        v["efficiency_domain_to_surface"] = m.forward_efficiency;
        v["symmetric_efficiency"] = m.symmetric_efficiency;
      }
      // The scores the race judged it by, after its refinement's first levels.
      if (racing) {
        Json& levels = v["level_scores"] = Json::array();
        for (const auto& [vertices, score] : outcomes[i].levels)
          levels.push_back({{"surface_vertices", vertices}, {"score", score}});
      }
      v["seconds"] = outcomes[i].seconds;
      // Its refinement to full resolution (on the symmetric core from the
      // takeover), and there the parts that time went to.
      if (settings.core == MapCore::symmetric) {
        const SurfaceRefineStats& s = result.symmetric_stats;
        v["seconds_refine"] = s.seconds;
        v.update(refine_timing(s, result.symmetric.get()));
      } else {
        v["seconds_refine"] = result.stats.seconds;
      }
    }
    v["kept"] = i == *kept;
    variants.push_back(v);
  }
  std::size_t dropped = 0;
  for (const Outcome& out : outcomes) dropped += out.dropped.has_value();
  if (used > 1)
    run.note("kept map " + std::to_string(kept_position) + " of " + std::to_string(used) +
             " (inverse-stretch weight " +
             std::to_string(all[*kept / contenders].inverse_stretch_weight) + ", candidate " +
             std::to_string(outcomes[*kept].result.setup->candidate) + ")" +
             (dropped ? "; " + std::to_string(dropped) + " dropped, clearly behind after two levels"
                      : ""));
  MapStageResult kept_result = std::move(outcomes[*kept].result);
  if (!stage.dump_patches.empty())
    write_output(run, stage.dump_patches, [&](const std::filesystem::path& p) {
      write_patch_dump(kept_result.setup->network(), p);
    });
  return kept_result;
}

namespace {

// The report's "meta_mesh" of a meta-mesh whose pieces are `pieces`.
void report_meta_mesh(Run& run, const MetaMesh& meta, const std::vector<MetaPiece>& pieces) {
  const MetaMeshSize size = meta_mesh_size(meta, pieces);
  Json& j = run.report()["meta_mesh"];
  j["valid"] = true;
  j["pieces"] = size.pieces;
  j["crossings"] = size.crossings;
  j["vertices_inside_faces"] = size.vertices_inside;
  j["shared_vertices"] = size.shared_vertices;
  j["kinks"] = size.kinks;
  j["triangulated_pieces"] = size.triangulated_pieces;
  j["points_inside_pieces"] = size.points_inside_pieces;
}

}  // namespace

FinishedMap finish_map(Run& run, const MapStageResult& staged, const DomainGeometry& domain,
                       const std::function<std::vector<char>(const MetaSide&)>& counted) {
  run.stage("validate");
  const std::string invalid = run.tool_name() + ": internal error, the map is invalid: ";
  FinishedMap out;
  const SurfaceMap* map = staged.symmetric ? nullptr : staged.setup->map.get();
  if (map) {
    // SurfaceMap's own invariants (meta_mesh checks them first), then the
    // same map from both sides, independently of how SurfaceMap stores it.
    std::optional<MetaMesh> meta = meta_mesh(*map);
    if (!meta)
      throw Failure(invalid + map->validate().value_or("it has no meta-mesh"),
                    Failure::Kind::internal);
    out.meta = std::move(*meta);
  } else {
    out.meta = staged.symmetric->meta();  // (InterSurfaceMap::validate is validate(meta))
  }
  // Cut and validated from both sides at once.
  auto pieces = meta_pieces(out.meta);
  if (!pieces)
    throw Failure(invalid + (map ? "meta-mesh: " : "") + validate(out.meta).value_or("?"),
                  Failure::Kind::internal);
  report_meta_mesh(run, out.meta, *pieces);
  if (counted) out.counted = counted(out.meta.side[1]);
  out.measures = measures(*pieces, out.counted);
  out.report = map ? map_report(*map, out.measures, staged.stats)
                   : map_report(*staged.symmetric, out.measures, staged.symmetric_stats);
  run.stage("sample");
  out.sampler = std::make_unique<DomainSurfaceSampler>(out.meta, std::move(*pieces), domain);
  return out;
}

void write_meta_mesh_output(const Run& run, const MapSettings& settings, const MetaMesh& meta) {
  write_output(run, settings.meta_mesh_path, [&](const std::filesystem::path& p) {
    if (!write_meta_mesh(meta, p)) throw io::FileError("cannot write " + p.string());
  });
}

}  // namespace ism::tool
