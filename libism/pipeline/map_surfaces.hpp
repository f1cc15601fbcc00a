#pragma once
// ism-map's pipeline (the paper's subject): a continuous bijective
// piecewise-linear map between two closed triangle meshes A and B of the same
// genus. Compatible path networks on both (from feature pairs, with features
// added where the topology needs them), both progressive meshes to their one
// base, the trivial map between the two bases, then both sides refined
// together to full resolution on the symmetric map core, optimising the
// symmetric stretch one vertex at a time (refine_surfaces); validated from
// both sides. The command-line tool runs it.
#include "io/io.hpp"
#include "map/common_refinement.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "metrics/metrics.hpp"
#include "pipeline/attribute_transfer.hpp"
#include "tool/tool.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace ism::pipeline {

struct MapSurfacesOptions {
  tool::InputMesh a, b;
  /// Feature pairs ('IA IB' vertex indices or 'XA YA ZA XB YB ZB' points per
  /// line, io::read_feature_pairs); empty: features chosen automatically.
  std::string features;
  /// The features (the pairs and those added) stay on each other until
  /// this fraction of the refinement's splits, then move like any vertex
  /// (the paper uses them to initialise the map and drops them during the
  /// refinement). 0.5 by default: released from the start (0) they slide
  /// while both sides are coarse (hand_plain ↔ hand_vulcan: symmetric
  /// Dirichlet 9.20 against 4.10; results-ism.md).
  double release_features_at = 0.5;
  /// Keep the features on each other throughout (release_features_at unused).
  bool hold_features = false;
  /// Files written when named (each complete or not at all):
  /// PREFIX_on_A.obj and PREFIX_on_B.obj (the common refinement placed on
  /// each surface: same vertex and face lists), PREFIX_A_to_B.txt and
  /// PREFIX_B_to_A.txt (per source vertex i, three rows `i j w`: the corners
  /// j of the target face holding its image and their weights, summing to 1).
  std::string output_prefix;
  std::string meta_mesh;  // the meta-mesh file (README, "Meta-mesh files")
  /// Morphs (need output_prefix): the overlay at (1 − t)·A + t·B for each t
  /// in `morph` (PREFIX_morph.obj for one, PREFIX_morph_K.obj for several),
  /// and morph_frames frames at t = k / (frames − 1) (PREFIX_frame_K.obj).
  std::vector<double> morph;
  int morph_frames = 0;
  /// Per-vertex fields (io::read_vertex_field; need output_prefix) carried
  /// through the map by barycentric interpolation: A's onto B's vertices
  /// (PREFIX_field_on_B.txt) and B's onto A's (PREFIX_field_on_A.txt).
  std::string transfer_field_a, transfer_field_b;
  /// A's texture coordinates (OBJ vt, per corner) carried onto B's vertices,
  /// written as B with a coordinate per vertex (PREFIX_B_uv.obj); and B's
  /// onto A (PREFIX_A_uv.obj). Coordinates are interpolated inside the face
  /// of the source holding each image; B triangles whose corners land in
  /// different texture charts of A are counted (report: seam_triangles).
  bool transfer_uv_a = false, transfer_uv_b = false;
  /// A's vertex colours (PLY red green blue, or OBJ 'v x y z r g b') carried
  /// onto B's vertices, written as B with 8-bit vertex colours
  /// (PREFIX_B_colors.ply); and B's onto A (PREFIX_A_colors.ply).
  bool transfer_colors_a = false, transfer_colors_b = false;
  /// The overlay on A with one morph target, the overlay on B, as glTF
  /// binary (PREFIX_morph.glb; weight 0: A, 1: B).
  bool morph_glb = false;
  /// Sweeps over every vertex of both sides each time the two have grown
  /// 1.5-fold (fewer when a sweep gains under 0.1 % of the energy):
  /// SurfaceRefineOptions::max_level_sweeps. Unset: the schedule's.
  std::optional<int> level_sweeps;
  /// Level-sweep counts raced at the coarse levels (each refines a copy of
  /// the map until both sides have 500 faces, or a tenth of their faces at
  /// full resolution if fewer; the lowest energy goes on):
  /// SurfaceRefineOptions::race_level_sweeps. Empty: no race.
  std::vector<int> race_level_sweeps{2, 3};
  /// The local relaxation after each level's sweeps and after the final
  /// ones: a vertex whose move gains more than this share of the mean
  /// energy per vertex queues its neighbours
  /// (SurfaceRefineOptions::local_relaxation_gain). Larger is faster and
  /// lands in another basin, better or worse by pair (docs/results-ism.md,
  /// stop 80). Unset: the schedule's.
  std::optional<double> relaxation_gain;
  /// The refinement schedule (map_schedule): thorough, fast, or by the
  /// inputs' size (automatic, the default).
  enum class ScheduleKind { automatic, thorough, fast };  // (kScheduleNames in this order)
  ScheduleKind schedule = ScheduleKind::automatic;
  int threads = 0;  // planning threads of the refinement (0: all)
};

/// The refinement schedule as resolved (map_schedule).
struct MapSchedule {
  bool fast = false;  // the fast schedule (else the thorough one)
  int level_sweeps = 2;
  double relaxation_gain = 1e-4;
};
/// From this many faces of both inputs together, ScheduleKind::automatic
/// is the fast schedule — one level sweep and a relaxation gain of 1e-3 —
/// instead of the thorough one (2 and 1e-4): bunny ↔ dragon, 134 K faces,
/// maps in ~87 % of the time at 0.5 % more energy; the smaller pairs keep
/// the thorough schedule, which the vase needs (docs/results-ism.md, stops
/// 81 and 82).
inline constexpr std::size_t kLargeMapFaces = 80000;
/// The schedule for inputs of `faces` faces together: options.schedule's
/// (automatic: by size), with the level sweeps and the relaxation gain as
/// the options give them where they do.
MapSchedule map_schedule(std::size_t faces, const MapSurfacesOptions& options);
/// The schedules' names as the front ends spell them, in ScheduleKind's
/// order.
inline const std::vector<std::string> kScheduleNames{"auto", "thorough", "fast"};
/// kScheduleNames joined by `separator` (for help texts and messages).
std::string schedule_names(const std::string& separator);
/// The schedule named by one of kScheduleNames; nullopt for any other name.
std::optional<MapSurfacesOptions::ScheduleKind> schedule_kind(const std::string& name);

struct MapSurfacesResult {
  MetaMesh meta;  // side 0 is A, side 1 is B (both refined to full resolution)
  MapMeasures measures;
  CommonRefinement overlay;
  /// correspondence[0][i]: the image of A's vertex i on B (a face of B as
  /// read, barycentric coordinates there, position); [1] the same from B.
  std::array<std::vector<SurfacePoint>, 2> correspondence;
};

/// Runs the pipeline in `run` (stages, progress, report, the files named in
/// `options`; run.finish() is the caller's). Throws tool::Failure with one
/// line for unreadable or unusable meshes, surfaces of different topology,
/// bad pairs, or a refinement that stops; no file is left partial.
MapSurfacesResult map_surfaces(tool::Run& run, const MapSurfacesOptions& options);

/// The images of every vertex of side s of a meta-mesh whose sides are
/// refinements of `input[s]` (the input's vertices first, same indices;
/// further vertices on its faces), located on the input of the other side:
/// result[s][i] for vertex i of input[s].
std::array<std::vector<SurfacePoint>, 2> input_correspondence(
    const MetaMesh& meta, const std::array<const TriangleMesh*, 2>& input);

/// Writes correspondences (one side of input_correspondence) as rows `i j w`,
/// three per source vertex, the target face's corners in `target`.
void write_correspondence(const std::vector<SurfacePoint>& images, const TriangleMesh& target,
                          const std::filesystem::path& path);

}  // namespace ism::pipeline
