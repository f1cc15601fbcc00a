#include "pipeline/map_surfaces.hpp"

#include "io/features.hpp"
#include "io/io.hpp"
#include "map/inter_surface_map.hpp"
#include "partition/compatible_networks.hpp"
#include "pm/pm.hpp"
#include "refine/refine_surfaces.hpp"
#include "report/report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace ism::pipeline {
namespace {

const char* const kName[2] = {"A", "B"};
// Below this symmetric efficiency a map from automatic features gets a note.
constexpr double kPoorEfficiency = 0.2;

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

}  // namespace

std::array<std::vector<SurfacePoint>, 2> input_correspondence(
    const MetaMesh& meta, const std::array<const TriangleMesh*, 2>& input) {
  std::array<std::vector<SurfacePoint>, 2> result;
  for (int s = 0; s < 2; ++s) {
    const MetaSide& from = meta.side[std::size_t(s)];
    const MetaSide& to = meta.side[std::size_t(1 - s)];
    const TriangleMesh& target = *input[std::size_t(1 - s)];
    const std::size_t n = input[std::size_t(s)]->n_vertices();
    if (from.n_vertices() < n || to.positions.size() != to.n_vertices())
      throw std::invalid_argument("input_correspondence: a side is not a refinement of its input");
    // The image's point on the refined other side, then the input face of
    // the other surface holding it (the refined faces lie in the input's).
    std::vector<Vec3> points(n);
    for (std::size_t v = 0; v < n; ++v) points[v] = point_at(to, from.location[v]);
    const std::vector<NearestPoint> near = nearest_points(target, points);
    auto& out = result[std::size_t(s)];
    out.reserve(n);
    for (std::size_t v = 0; v < n; ++v) out.push_back({near[v].face, near[v].bary, points[v]});
  }
  return result;
}

void write_correspondence(const std::vector<SurfacePoint>& images, const TriangleMesh& target,
                          const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) throw io::FileError(path.string() + ": cannot be written");
  char line[96];
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Triangle& t = target.triangles[std::size_t(images[i].face)];
    for (int k = 0; k < 3; ++k) {
      std::snprintf(line, sizeof line, "%zu %d %.17g\n", i, t[std::size_t(k)], images[i].bary[k]);
      out << line;
    }
  }
  out.flush();
  if (!out) throw io::FileError(path.string() + ": write failed");
}

MapSchedule map_schedule(std::size_t faces, const MapSurfacesOptions& options) {
  using Kind = MapSurfacesOptions::ScheduleKind;
  MapSchedule schedule;
  schedule.fast = options.schedule == Kind::fast ||
                  (options.schedule == Kind::automatic && faces >= kLargeMapFaces);
  schedule.level_sweeps = options.level_sweeps.value_or(schedule.fast ? 1 : 2);
  schedule.relaxation_gain = options.relaxation_gain.value_or(schedule.fast ? 1e-3 : 1e-4);
  return schedule;
}

std::string schedule_names(const std::string& separator) {
  std::string out;
  for (const std::string& name : kScheduleNames) out += (out.empty() ? "" : separator) + name;
  return out;
}

std::optional<MapSurfacesOptions::ScheduleKind> schedule_kind(const std::string& name) {
  for (std::size_t k = 0; k < kScheduleNames.size(); ++k)
    if (name == kScheduleNames[k]) return MapSurfacesOptions::ScheduleKind(k);
  return std::nullopt;
}

MapSurfacesResult map_surfaces(tool::Run& run, const MapSurfacesOptions& o) {
  const std::string tool = run.tool_name();
  for (const tool::InputMesh* in : {&o.a, &o.b})
    if (!in->soup) run.add_input(in->path);
  if (!o.features.empty()) run.add_input(o.features);
  std::vector<std::string> outputs;
  if (!o.output_prefix.empty())
    for (const char* suffix : {"_on_A.obj", "_on_B.obj", "_A_to_B.txt", "_B_to_A.txt"})
      outputs.push_back(o.output_prefix + suffix);
  const std::array<bool, 2> uv_from{o.transfer_uv_a, o.transfer_uv_b};
  const std::array<bool, 2> colors_from{o.transfer_colors_a, o.transfer_colors_b};
  const bool extras = !o.morph.empty() || o.morph_frames > 0 || o.morph_glb ||
                      !o.transfer_field_a.empty() || !o.transfer_field_b.empty() || uv_from[0] ||
                      uv_from[1] || colors_from[0] || colors_from[1];
  if (extras && o.output_prefix.empty())
    throw tool::Failure(tool +
                        ": morphs and transferred attributes need an output prefix (-o PREFIX)");
  if (o.level_sweeps && (*o.level_sweeps < 0 || *o.level_sweeps > 1000))
    throw tool::Failure(tool + ": --level-sweeps takes 0 to 1000 (got " +
                        std::to_string(*o.level_sweeps) + ")");
  for (int k : o.race_level_sweeps)
    if (k < 0 || k > 1000)
      throw tool::Failure(tool + ": --race-level-sweeps takes counts of 0 to 1000 (got " +
                          std::to_string(k) + ")");
  if (o.relaxation_gain && !(*o.relaxation_gain >= 0 && *o.relaxation_gain <= 1))
    throw tool::Failure(tool +
                        ": --relaxation-gain takes a share of the energy per vertex, 0 to 1");
  if (!(o.release_features_at >= 0 && o.release_features_at <= 1))
    throw tool::Failure(tool +
                        ": --release-features-at takes a fraction of the refinement, 0 to 1");
  for (double t : o.morph)
    if (!std::isfinite(t)) throw tool::Failure(tool + ": a morph time is not a finite number");
  if (o.morph_frames == 1 || o.morph_frames < 0 || o.morph_frames > 10000)
    throw tool::Failure(tool + ": --morph-frames takes 2 to 10000 frames (got " +
                        std::to_string(o.morph_frames) + ")");
  // Every morph as (t, file).
  std::vector<std::pair<double, std::string>> morphs;
  char number[32];
  for (std::size_t k = 0; k < o.morph.size(); ++k) {
    std::snprintf(number, sizeof number, "_%03zu", k);
    morphs.push_back({o.morph[k], o.output_prefix + "_morph" +
                                      (o.morph.size() == 1 ? std::string() : number) + ".obj"});
  }
  for (int k = 0; k < o.morph_frames; ++k) {
    std::snprintf(number, sizeof number, "_%03d", k);
    morphs.push_back(
        {double(k) / (o.morph_frames - 1), o.output_prefix + "_frame" + number + ".obj"});
  }
  for (const auto& [t, file] : morphs) outputs.push_back(file);
  const std::array<std::string, 2> field_in{o.transfer_field_a, o.transfer_field_b};
  std::array<std::string, 2> field_out;  // [s]: side s's field carried onto the other side
  for (int s = 0; s < 2; ++s)
    if (!field_in[std::size_t(s)].empty()) {
      run.add_input(field_in[std::size_t(s)]);
      field_out[std::size_t(s)] =
          o.output_prefix + (s == 0 ? "_field_on_B.txt" : "_field_on_A.txt");
      outputs.push_back(field_out[std::size_t(s)]);
    }
  // [s]: side s's texture coordinates / colours on the other side's mesh.
  std::array<std::string, 2> uv_out, colors_out;
  for (int s = 0; s < 2; ++s) {
    const std::string other = kName[1 - s];
    if (uv_from[std::size_t(s)])
      outputs.push_back(uv_out[std::size_t(s)] = o.output_prefix + "_" + other + "_uv.obj");
    if (colors_from[std::size_t(s)])
      outputs.push_back(colors_out[std::size_t(s)] = o.output_prefix + "_" + other + "_colors.ply");
  }
  const std::string glb_out = o.morph_glb ? o.output_prefix + "_morph.glb" : std::string();
  if (o.morph_glb) outputs.push_back(glb_out);
  if (!o.meta_mesh.empty()) outputs.push_back(o.meta_mesh);
  for (const std::string& out : outputs) run.check_output(out);

  const MeshRequirements needs{
      .tool = tool,
      .closed = true,
      .closed_advice = "maps between surfaces with boundary loops are not supported yet"};
  // (The soups kept where attributes are carried from.)
  std::array<PolygonSoup, 2> soup;
  std::array<PreparedMesh, 2> prepared;
  for (int s = 0; s < 2; ++s) {
    const bool attributes = uv_from[std::size_t(s)] || colors_from[std::size_t(s)];
    prepared[std::size_t(s)] =
        run.load_prepared(s == 0 ? o.a : o.b, needs, attributes ? &soup[std::size_t(s)] : nullptr);
  }
  // The attributes carried, read before the work.
  std::array<std::vector<std::array<Texcoord, 3>>, 2> corner_uv;
  std::array<io::VertexField, 2> colors;
  for (int s = 0; s < 2; ++s) {
    const std::string& from = (s == 0 ? o.a : o.b).path;
    try {
      if (uv_from[std::size_t(s)])
        corner_uv[std::size_t(s)] =
            corner_texcoords(soup[std::size_t(s)], prepared[std::size_t(s)]);
    } catch (const std::invalid_argument& e) {
      throw tool::Failure(from + ": cannot carry its texture coordinates: " + e.what());
    }
    try {
      if (colors_from[std::size_t(s)])
        colors[std::size_t(s)] = vertex_colors(soup[std::size_t(s)], prepared[std::size_t(s)]);
    } catch (const std::invalid_argument& e) {
      throw tool::Failure(from + ": cannot carry its colours: " + e.what());
    }
    soup[std::size_t(s)] = {};
  }
  const std::array<MeshCheck, 2> check{prepared[0].check, prepared[1].check};
  const std::array<TriangleMesh, 2> mesh{std::move(prepared[0].mesh), std::move(prepared[1].mesh)};
  const std::array<std::string, 2> names{o.a.path, o.b.path};
  auto renumbered = [&](int s) {
    return check[std::size_t(s)].welded_vertices || check[std::size_t(s)].unreferenced_vertices;
  };
  auto renumbering = [&](int s) {
    return names[std::size_t(s)] +
           ": reading renumbered its vertices (coincident vertices welded or unreferenced ones "
           "dropped)";
  };

  for (int s = 0; s < 2; ++s)
    if (!o.output_prefix.empty() && renumbered(s))
      run.note(renumbering(s) +
               "; the correspondences' vertex indices are those of the surface as read "
               "(ism-info --json describes it), not the file's");

  // The fields are read before the work, against the surfaces as read.
  std::array<io::VertexField, 2> field;
  for (int s = 0; s < 2; ++s)
    if (!field_in[std::size_t(s)].empty()) {
      if (renumbered(s))
        throw tool::Failure(renumbering(s) + ", so the rows of " + field_in[std::size_t(s)] +
                            " would belong to other vertices");
      try {
        field[std::size_t(s)] =
            io::read_vertex_field(field_in[std::size_t(s)], mesh[std::size_t(s)].n_vertices());
      } catch (const io::FileError& e) {
        throw tool::reading_failure(field_in[std::size_t(s)], e);
      }
    }

  run.stage("features");
  io::FeaturePairs pairs;
  if (!o.features.empty()) {
    try {
      pairs = io::read_feature_pairs(o.features, mesh[0], mesh[1], names);
    } catch (const io::FileError& e) {
      throw tool::reading_failure(o.features, e);
    }
    if (pairs.pairs.empty())
      throw tool::Failure(o.features + ": no feature pairs (omit --features for automatic ones)");
    for (int s = 0; s < 2 && pairs.by_index; ++s)
      if (renumbered(s))
        throw tool::Failure(renumbering(s) +
                            ", so the pairs' vertex indices would name other vertices; give the "
                            "pairs as points (X Y Z) instead");
  }

  tool::Progress& partition_progress = run.stage("partition");
  CompatibleOptions partition_options;
  partition_options.names = names;
  partition_options.progress = [&](double f) { partition_progress.update(f); };
  CompatibleNetworks networks;
  try {
    networks = trace_compatible_networks(mesh[0], mesh[1], pairs.pairs, partition_options);
  } catch (const PartitionError& e) {
    throw tool::Failure(tool + ": " + e.what());
  }

  tool::Progress& pm_progress = run.stage("progressive meshes");
  SimplifyOptions simplify;
  simplify.progress = [&](double f) { pm_progress.update(f); };
  const std::array<ProgressiveMesh, 2> pms = simplify_compatible(networks, simplify);
  Json& report = run.report();
  report["partition"] = compatible_partition_report(networks, pms);

  tool::Progress& refine_progress = run.stage("refine");
  InterSurfaceOptions map_options;
  map_options.hold_features = true;
  InterSurfaceMap map(side_from_pm(pms[0]), side_from_pm(pms[1]), map_options);
  SurfaceRefineOptions refine;
  refine.threads = o.threads;
  const MapSchedule schedule = map_schedule(mesh[0].n_faces() + mesh[1].n_faces(), o);
  refine.max_level_sweeps = schedule.level_sweeps;
  // (A level less than half a growth step from full resolution, in the
  // geometric sense, is left to the final sweeps.)
  refine.final_level_merge = std::sqrt(refine.sweep_growth);
  refine.race_level_sweeps = o.race_level_sweeps;
  refine.local_relaxation_gain = schedule.relaxation_gain;
  refine.release_features_at = o.hold_features ? -1 : o.release_features_at;
  use_fast_searches(refine);
  refine.relax_from_movers = true;
  // (A split that finds no place waits for the other side to grow by a
  // tenth: teapot <-> cup held maps so; docs/results-ism.md, stop 90.)
  refine.defer_growth = 0.1;
  refine.progress = [&](double f) { refine_progress.update(f); };
  SurfaceRefineStats stats;
  try {
    stats = refine_surfaces(map, refine);
  } catch (const std::exception& e) {
    throw tool::Failure(tool + ": " + describe_stop(map, e.what()), tool::Failure::Kind::internal);
  }

  run.stage("validate");
  if (const auto problem = map.validate())
    throw tool::Failure(tool + ": the refined map does not validate: " + *problem,
                        tool::Failure::Kind::internal);
  MapSurfacesResult result;
  result.meta = map.meta();
  auto pieces = meta_pieces(result.meta);
  if (!pieces)
    throw tool::Failure(tool + ": the map's meta-mesh does not validate from both sides",
                        tool::Failure::Kind::internal);
  result.measures = measures(*pieces);

  run.stage("overlay");
  result.overlay = common_refinement(result.meta, *pieces);
  result.correspondence = input_correspondence(result.meta, {&mesh[0], &mesh[1]});

  run.stage("write");
  if (!o.output_prefix.empty()) {
    for (int s = 0; s < 2; ++s)
      tool::write_output(run, outputs[std::size_t(s)], [&](const std::filesystem::path& p) {
        io::write_mesh(result.overlay.on_side(s), p);
      });
    for (int s = 0; s < 2; ++s)
      tool::write_output(run, outputs[std::size_t(2 + s)], [&](const std::filesystem::path& p) {
        write_correspondence(result.correspondence[std::size_t(s)], mesh[std::size_t(1 - s)], p);
      });
  }
  for (const auto& [t, file] : morphs) {
    TriangleMesh frame = result.overlay.on_side(0);
    for (std::size_t v = 0; v < frame.n_vertices(); ++v)
      frame.positions[v] =
          (1 - t) * result.overlay.positions[0][v] + t * result.overlay.positions[1][v];
    tool::write_output(run, file,
                       [&](const std::filesystem::path& p) { io::write_mesh(frame, p); });
  }
  for (int s = 0; s < 2; ++s)
    if (!field_out[std::size_t(s)].empty()) {
      const io::VertexField moved =
          transfer_field(field[std::size_t(s)], mesh[std::size_t(s)].triangles,
                         result.correspondence[std::size_t(1 - s)]);
      tool::write_output(run, field_out[std::size_t(s)],
                         [&](const std::filesystem::path& p) { io::write_vertex_field(moved, p); });
    }
  if (o.morph_glb)
    tool::write_output(run, glb_out, [&](const std::filesystem::path& p) {
      io::write_morph_glb(result.overlay.on_side(0), result.overlay.positions[1], p, "B");
    });
  Json transfer = Json::object();
  for (int s = 0; s < 2; ++s) {
    const std::size_t from = std::size_t(s), to = std::size_t(1 - s);
    if (uv_from[from]) {
      const TexcoordTransfer uv = transfer_texcoords(mesh[from].triangles, corner_uv[from],
                                                     result.correspondence[to], mesh[to].triangles);
      transfer[std::string("uv_seam_triangles_on_") + kName[to]] = uv.seam_triangles;
      if (uv.seam_triangles)
        run.note(std::to_string(uv.seam_triangles) + " of " + std::to_string(mesh[to].n_faces()) +
                 " triangles of " + names[to] + " span a texture seam of " + names[from] +
                 " (their corners lie in different charts): the texture is wrong inside them");
      tool::write_output(run, uv_out[from], [&](const std::filesystem::path& p) {
        io::write_textured_obj(mesh[to], uv.texcoords, p);
      });
    }
    if (colors_from[from]) {
      const io::VertexField moved =
          transfer_field(colors[from], mesh[from].triangles, result.correspondence[to]);
      tool::write_output(run, colors_out[from], [&](const std::filesystem::path& p) {
        io::write_colored_ply(mesh[to], to_rgb(moved), {}, p);
      });
    }
  }
  if (!o.meta_mesh.empty())
    tool::write_output(run, o.meta_mesh,
                       [&](const std::filesystem::path& p) { write_meta_mesh(result.meta, p); });

  // The report: the map, the overlay, and how far each feature pair's image
  // lies from its partner (relative to the target's bounding-box diagonal).
  const MapMeasures& m = result.measures;
  Json j = two_surface_map_report(map, m, stats);
  j["hold_features"] = o.hold_features;
  if (!o.hold_features) j["release_features_at"] = o.release_features_at;
  j["search"] = {
      {"coarse", {{"tolerance", refine.search.tolerance}, {"rounds", refine.search.rounds}}},
      {"fine",
       {{"tolerance", refine.fine_search.tolerance},
        {"rounds", refine.fine_search.rounds},
        {"split_first_halvings", refine.fine_split_placement.first_halvings}}},
      {"fine_from", refine.fine_search_from},
      {"model_seed", refine.fine_search.model_seed}};
  j["relaxation_gain"] = refine.local_relaxation_gain;
  j["relax_from_movers"] = refine.relax_from_movers;
  j["level_sweeps"] = refine.max_level_sweeps;
  j["final_level_merge"] = refine.final_level_merge;
  j["schedule"] = schedule.fast ? "fast" : "thorough";
  const MetaMeshSize size = meta_mesh_size(result.meta, *pieces);
  Json overlay = Json::object();
  overlay["vertices"] = result.overlay.positions[0].size();
  overlay["triangles"] = result.overlay.triangles.size();
  overlay["pieces"] = size.pieces;
  overlay["crossings"] = size.crossings;
  overlay["kinks"] = size.kinks;
  overlay["triangulated_pieces"] = size.triangulated_pieces;
  overlay["points_inside_pieces"] = size.points_inside_pieces;
  j["overlay"] = overlay;
  Json residuals = Json::array();
  double worst = 0;
  for (std::size_t k = 0; k < pairs.pairs.size(); ++k) {
    Json r = Json::object();
    r["a"] = pairs.pairs[k][0];
    r["b"] = pairs.pairs[k][1];
    for (int s = 0; s < 2; ++s) {
      const int v = pairs.pairs[k][std::size_t(s)];
      const TriangleMesh& other = mesh[std::size_t(1 - s)];
      const double d = (result.correspondence[std::size_t(s)][std::size_t(v)].position -
                        other.positions[std::size_t(pairs.pairs[k][std::size_t(1 - s)])])
                           .norm() /
                       bounding_box_diagonal(other);
      r[s == 0 ? "error_on_b" : "error_on_a"] = d;
      worst = std::max(worst, d);
    }
    residuals.push_back(r);
  }
  j["feature_residuals"] = residuals;
  if (!transfer.empty()) j["transfer"] = transfer;
  report["map"] = j;
  // (Wall seconds vary from run to run: beside the map's figures, not in them.)
  report["refine_timing"] = refine_timing(stats, &map);

  run.note(
      "A " + std::to_string(map.n_faces(0)) + " / B " + std::to_string(map.n_faces(1)) +
      " faces, valid from both sides; symmetric efficiency " + fixed(m.symmetric_efficiency, 4) +
      " (symmetric Dirichlet " + fixed(4 / m.symmetric_efficiency, 3) + "), A->B " +
      fixed(m.forward_efficiency, 4) + ", B->A " + fixed(m.backward_efficiency, 4) + "; overlay " +
      std::to_string(result.overlay.triangles.size()) + " triangles" +
      (pairs.pairs.empty() ? std::string()
                           : "; largest feature residual " + fixed(worst, 5) + " of the diagonal"));
  // Automatic features pair extreme points and cycles by topology alone: a
  // map this stretched has most likely paired different parts (teapot <->
  // cup: the spout with the cup's handle, 0.036; with 12 pairs 0.585).
  if (pairs.pairs.empty() && m.symmetric_efficiency < kPoorEfficiency)
    run.note("symmetric efficiency " + fixed(m.symmetric_efficiency, 4) +
             " is poor: the automatic features have probably paired different parts of the two "
             "surfaces; give a few corresponding points with --features");
  return result;
}

}  // namespace ism::pipeline
