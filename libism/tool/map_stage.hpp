#pragma once
// The map stage as every front end runs it once its candidate networks are
// traced: choice of network and coarse map, refinement to full resolution
// with progress, the optional patch dump, a failure of the map core turned
// into one line a user can act on.
//
// It runs in several variants of the optimised energy at once (one per
// core), the front end's score keeping one: which energy
// reaches the better map depends on the surface (a low inverse-stretch weight
// lifts the one-way efficiency of most models but traps flat-faced ones such
// as cube.obj in folds the symmetric energy avoids).
#include "io/draco_io.hpp"
#include "map/meta_mesh.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "partition/partition.hpp"
#include "refine/network_choice.hpp"
#include "refine/refine.hpp"
#include "refine/refine_surfaces.hpp"
#include "tool/tool.hpp"

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ism::tool {

/// How one variant of the map differs: MapOptions' energy settings.
struct MapVariant {
  double inverse_stretch_weight = 1.0;
  int cone_relaxation_rings = 2;
  double anisotropy_weight = 0.0;  // MapOptions::anisotropy_weight
  double anisotropy_threshold = 10.0;
};

/// Which map core refines the chosen coarse map: SurfaceMap (the remeshers'
/// own) or the symmetric core (InterSurfaceMap: the domain as side 0, cones
/// released continuously; semireg, closed surfaces only). The symmetric
/// core takes over the coarse map at MapStage::symmetric_from_vertices
/// surface vertices (by default kSymmetricFromVertices, where SurfaceMap's
/// discrete cone moves have placed the cones).
enum class MapCore { surface_map, symmetric };
inline constexpr std::size_t kSymmetricFromVertices = 1000;

/// The map options every front end offers (tool/cli.hpp: add_map_options).
struct MapSettings {
  MapCore core = MapCore::surface_map;  // --core (gim-remesh, semireg)
  bool hold_features = false;
  int final_sweeps = 8;  // RefineOptions::max_final_sweeps
  /// Refined side by side; --inverse-weight W replaces them by {W, 2}.
  std::vector<MapVariant> variants{MapVariant{}};
  /// How many of each variant's best coarse candidates (networks or bases,
  /// ChooseMap's count) are refined whole and compete: 1 trusts the coarse
  /// ranking; 0 is the front end's default (1; semireg on an open surface 2).
  std::size_t contenders = 0;
  /// MapOptions::curvature_weight of every variant (--curvature-weight).
  double curvature_weight = 0.0;
  /// Refined side by side after `variants` when one of those scored below
  /// MapStage::retry_below, and compared with them (none: no second round).
  std::vector<MapVariant> fallback_variants;
  /// On the symmetric core: a map whose score trails another's, refined
  /// side by side with it, by more than this at the first two levels of its
  /// refinement is stopped there (tool/variant_race.hpp; --drop-behind).
  /// Negative: every map is refined whole.
  double drop_behind = 0.01;
  /// The options of variant i.
  MapOptions map_options(std::size_t i) const;
  /// --inverse-weight W: the single variant W (the first variant's other
  /// settings, e.g. its anisotropy penalty, kept), no fallbacks.
  void set_inverse_weight(double w);
  /// --anisotropy-weight and --anisotropy-threshold: the value in every
  /// variant, no fallbacks.
  void set_anisotropy_weight(double w);
  void set_anisotropy_threshold(double ratio);
  /// --meta-mesh: the map written as a meta-mesh (map/meta_mesh.hpp); empty: none.
  std::string meta_mesh_path;
};

/// Throws Failure naming the option when a setting is outside the range the
/// command line accepts (tool/cli.hpp), for front ends that do not parse
/// options with CLI11 (the Python module): final sweeps 0..1000, inverse
/// weight 0.001..1, drop-behind -1..1, curvature weight 0..100, anisotropy weight 0..1e6 and
/// threshold 1..1e6, at least one variant, Draco bits 8..30.
void check_settings(const std::string& tool, const MapSettings& settings,
                    const io::MeshFileOptions& mesh_file = {});

/// Scores a refined map; the variant with the highest score is kept.
using MapScore = std::function<double(const SurfaceMap&)>;
using SymmetricScore = std::function<double(const InterSurfaceMap&)>;

struct MapStage {
  std::string input;         // the surface's file, for messages
  std::string dump_patches;  // PLY of the network's patches; empty: none
  /// RefineOptions::global_flat_reembedding (only where it applies: a flat
  /// torus domain with released features).
  bool global_flat_reembedding = false;
  /// RefineOptions::local_disc_every (0: local relaxation moves one vertex
  /// at a time only).
  int local_disc_every = RefineOptions{}.local_disc_every;
  std::string hint;  // what to try when the optimisation fails
  /// A variant scoring below this sends MapSettings::fallback_variants in.
  double retry_below = -HUGE_VAL;
  /// The symmetric core takes over each coarse map at this many surface
  /// vertices (SurfaceMap refines it that far, with the options above).
  std::size_t symmetric_from_vertices = kSymmetricFromVertices;
  /// SurfaceRefineOptions::local_disc_every of the symmetric core (0:
  /// none). After every gaining move by default: its discs must lie over
  /// one or two faces of the domain, so fewer would be tried than the
  /// default core's every 10th (results-two-surfaces.md, stop 56).
  int symmetric_local_disc_every = 1;
  /// SurfaceRefineOptions::before_final of the symmetric core's refinement
  /// (e.g. the flat torus's global re-embedding); empty: none.
  std::function<double(InterSurfaceMap&)> symmetric_before_final;
  /// The symmetric core's score of a refined map (the variant with the
  /// highest is kept); empty: its one-way efficiency domain -> surface.
  SymmetricScore symmetric_score;
  /// The same for a map part-way refined, by which the maps refined side by
  /// side race (MapSettings::drop_behind); empty: no race, every map refined
  /// whole (e.g. where the final score, such as a grid's folds, is not
  /// foreseen part-way).
  SymmetricScore symmetric_level_score;
};

/// Chooses the network (or domain) and builds its coarse map with the given
/// options: the best `count` candidates, best first (fewer when fewer map;
/// count is MapSettings::contenders), e.g. choose_network() or
/// rank_domains() over the front end's candidates.
using ChooseMap =
    std::function<std::vector<std::unique_ptr<MapSetup>>(const MapOptions&, std::size_t count)>;

/// A chosen map as ChooseMap's result.
inline std::vector<std::unique_ptr<MapSetup>> only(std::unique_ptr<MapSetup> setup) {
  std::vector<std::unique_ptr<MapSetup>> out;
  out.push_back(std::move(setup));
  return out;
}

struct MapStageResult {
  /// The variant kept: its network, progressive mesh and SurfaceMap, refined
  /// to full resolution on the surface_map core, left at the coarse level of
  /// the choice on the symmetric one.
  std::unique_ptr<MapSetup> setup;
  RefineStats stats;
  /// The symmetric core: the map refined to full resolution (null otherwise).
  std::unique_ptr<InterSurfaceMap> symmetric;
  SurfaceRefineStats symmetric_stats;
};

/// Runs every variant of `settings` in parallel, each deterministic and
/// whole — its own choice of network and coarse map, since the large-scale
/// shape of a map is decided at its coarsest levels — then its refinement to
/// full resolution (progress on `progress` from the first variant), its
/// best settings.contenders coarse maps each refined side by side. Keeps
/// the map with the highest score (the first among equals) and writes
/// its patch dump if asked. If a variant scores below stage.retry_below,
/// settings.fallback_variants are then refined the same way and compete too. The report gets
/// "features_released" and "map_variants" (per map refined: its variant's settings, contender rank
/// and candidate, score, efficiencies and whether it was kept). When every variant fails, rethrows
/// the first variant's Failure, or throws Failure "<tool>: the map optimisation failed on <input>
/// (<why>); <hint>". On the symmetric core (settings.core) each variant's chosen coarse map is
/// refined by SurfaceMap to stage.symmetric_from_vertices surface vertices (with the stage's
/// global re-embedding and disc settings; the network choice has usually done so already), resumed
/// as an InterSurfaceMap (side 0 the domain, never refining; side 1 the surface, refined by the
/// rest of its splits; features released unless settings.hold_features; the variant's
/// inverse-stretch weight and the curvature weight, as a forward density; its other energy settings
/// not applied from there on) and refined by refine_surfaces (at most settings.final_sweeps final
/// sweeps; SurfaceRefineOptions::large_chart_backoff on); it is scored by stage.symmetric_score, by
/// default its domain -> surface efficiency; a stopped refinement's why is describe_stop's line.
/// There the maps of a round race (settings.drop_behind): one clearly behind after two levels is
/// dropped (stopped, or, if it had finished by the decision, just not kept; its "map_variants"
/// entry says "dropped", with the scores it was judged by). Which maps are dropped depends on
/// their scores only, so the map kept is the same in every run; it differs from the one kept
/// with every map refined whole only if a dropped map would have overtaken the leader later.
/// The report also gets "map_core".
MapStageResult run_map_stage(Run& run, Progress& progress, const MapStage& stage,
                             const MapSettings& settings, const ChooseMap& choose,
                             const MapScore& score);

/// The chosen map as the rest of a remesher uses it, whichever core made it.
struct FinishedMap {
  /// Its meta-mesh (side 0 the domain, side 1 the surface), valid from both
  /// sides: for write_meta_mesh_output.
  MetaMesh meta;
  /// The surface point of a domain point (on side 1 of meta).
  std::unique_ptr<DomainSurfaceSampler> sampler;
  /// Per face of side 1, whether the measures count it (empty: every face).
  std::vector<char> counted;
  /// The measures over the counted faces, and the report's "map" section.
  MapMeasures measures;
  Json report;
};

/// The epilogue of the map stage, written once for every front end and
/// core. Stage "validate": SurfaceMap's own invariants (SurfaceMap::validate;
/// InterSurfaceMap's are its meta-mesh's), then the meta-mesh cut into
/// pieces and validated from both sides, once; a violation throws Failure "<tool>: internal
/// error, the map is invalid: <why>"; the report gets "meta_mesh" (valid,
/// sizes). The measures are taken from those pieces over the faces f of side
/// 1 with counted(side 1)[f] set (every face when `counted` is empty or
/// returns an empty list). Then stage "sample" begins: the sampler is built
/// from the same pieces (not cut again).
FinishedMap finish_map(Run& run, const MapStageResult& staged, const DomainGeometry& domain,
                       const std::function<std::vector<char>(const MetaSide&)>& counted = {});
/// Writes the meta-mesh to settings.meta_mesh_path, if given (write_output).
void write_meta_mesh_output(const Run& run, const MapSettings& settings, const MetaMesh& meta);

}  // namespace ism::tool
