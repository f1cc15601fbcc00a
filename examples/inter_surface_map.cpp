// A map between two closed surfaces of the same genus with both sides
// refining (the symmetric map core): compatible path networks on both
// surfaces (from feature pairs, or features added automatically), both
// progressive meshes to their one base replayed together, the symmetric
// stretch optimised on both; validation from both sides and the measures.
//   inter_surface_map [A.obj B.obj [--pairs P.txt] [--decimate V]] [--faces N]
//                     [--validate-each-step] [--trace-energy] [--meta-mesh OUT.txt]
//                     [--level-sweeps N] [--final-sweeps N] [--block N] [--this-side-only]
//                     [--local-budget B] [--kinks RULE] [--threads N] [--split-batch K]
//                     [--release-at F] [--race S1,S2,...] [--race-faces N]
// --trace-energy computes the energy after every step and prints the steps
// that raise it tenfold or whose gain differs from the energy's drop.
// --decimate V simplifies both meshes towards V vertices first (with --pairs
// the paired vertices stay, and the simplification may stop above V). The
// last lines say how the energy is spread over B's faces.
// --block N refines one side N splits in a row (the paper's schedule);
// --this-side-only optimises after a split only the split side's new ring,
// not also the other side's vertices in it.
// --race S1,S2,... refines a copy of the map with each of these level-sweep
// counts until both sides have --race-faces faces (default 500, or a tenth
// of a side's faces if fewer) and goes on with the lowest energy
// (SurfaceRefineOptions::race_level_sweeps).
// --local-budget B runs the local relaxation queue after each level's sweeps
// (SurfaceRefineOptions::local_relaxation_budget; 0: never).
// --kinks RULE says where edges bend (InterSurfaceOptions::kinks):
// where_needed (default, the paper's: only where a straight segment would
// leave its cell) or follow_cells (wherever they cross a cell whose map is
// not affine).
// --threads N plans the sweeps' optimisations on N threads
// (SurfaceRefineOptions::threads; 0, the default: all; 1: none). The map is
// the same for every N. --split-batch K makes K splits in a row before
// optimising their new rings together (SurfaceRefineOptions::split_batch;
// default 1: after every split). --release-at F holds the features on each
// other until a fraction F of the splits (ism-map's default: 0.5); by
// default they move from the start.
// Without meshes: a generated sphere and a generated bumpy blob.
#include "map/inter_surface_map.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/compatible_networks.hpp"
#include "pm/pm.hpp"
#include "refine/refine_surfaces.hpp"
#include "shapes/shapes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines appear as stages end
  std::vector<std::string> files;
  std::string pairs_file, meta_file;
  int faces = 1000, threads = 0, split_batch = 0;
  std::size_t decimate = 0;
  bool each = false, trace = false;
  int level_sweeps = -1, final_sweeps = -1;
  std::size_t block = 1;
  double local_budget = -1;
  double release_at = 0;  // fraction of the splits; 0: features free from the start
  std::vector<int> race;
  std::size_t race_faces = 0;
  bool other_side = true;
  ism::InterSurfaceOptions map_options;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--validate-each-step") == 0)
      each = true;
    else if (std::strcmp(argv[i], "--trace-energy") == 0)
      trace = true;
    else if (std::strcmp(argv[i], "--level-sweeps") == 0 && i + 1 < argc)
      level_sweeps = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--final-sweeps") == 0 && i + 1 < argc)
      final_sweeps = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--local-budget") == 0 && i + 1 < argc)
      local_budget = std::atof(argv[++i]);
    else if (std::strcmp(argv[i], "--block") == 0 && i + 1 < argc)
      block = std::size_t(std::atol(argv[++i]));
    else if (std::strcmp(argv[i], "--this-side-only") == 0)
      other_side = false;
    else if (std::strcmp(argv[i], "--kinks") == 0 && i + 1 < argc) {
      const std::string rule = argv[++i];
      if (rule == "where_needed")
        map_options.kinks = ism::KinkRule::where_needed;
      else if (rule == "follow_cells")
        map_options.kinks = ism::KinkRule::follow_cells;
      else {
        std::fprintf(stderr, "error: --kinks takes where_needed or follow_cells\n");
        return 2;
      }
    } else if (std::strcmp(argv[i], "--faces") == 0 && i + 1 < argc)
      faces = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--pairs") == 0 && i + 1 < argc)
      pairs_file = argv[++i];
    else if (std::strcmp(argv[i], "--meta-mesh") == 0 && i + 1 < argc)
      meta_file = argv[++i];
    else if (std::strcmp(argv[i], "--split-batch") == 0 && i + 1 < argc)
      split_batch = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--decimate") == 0 && i + 1 < argc)
      decimate = std::size_t(std::atol(argv[++i]));
    else if (std::strcmp(argv[i], "--release-at") == 0 && i + 1 < argc)
      release_at = std::atof(argv[++i]);
    else if (std::strcmp(argv[i], "--race") == 0 && i + 1 < argc) {
      const std::string list = argv[++i];
      for (std::size_t at = 0; at < list.size();) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        race.push_back(std::atoi(list.substr(at, comma - at).c_str()));
        at = comma + 1;
      }
    } else if (std::strcmp(argv[i], "--race-faces") == 0 && i + 1 < argc)
      race_faces = std::size_t(std::atol(argv[++i]));
    else
      files.push_back(argv[i]);
  }
  if (!(files.empty() || files.size() == 2)) {
    std::fprintf(stderr,
                 "usage: inter_surface_map [A.obj B.obj [--pairs P] [--decimate V]] [--faces N] "
                 "[--validate-each-step] [--trace-energy] [--meta-mesh OUT.txt] [--level-sweeps N] "
                 "[--final-sweeps N] [--block N] [--this-side-only] [--local-budget B] "
                 "[--kinks where_needed|follow_cells] [--release-at F] [--race S1,S2,...] "
                 "[--race-faces N]\n");
    return 2;
  }
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  auto lap = [&](const char* what) {
    const auto now = Clock::now();
    std::printf("%-10s %7.2f s\n", what, std::chrono::duration<double>(now - t0).count());
    t0 = now;
  };
  ism::TriangleMesh a, b;
  if (files.empty()) {
    a = ism::shapes::sphere(faces);
    b = ism::shapes::blob(faces, 3);
  } else {
    a = ism::prepare_mesh(ism::io::read_polygon_soup(files[0])).mesh;
    b = ism::prepare_mesh(ism::io::read_polygon_soup(files[1])).mesh;
  }
  std::vector<std::array<int, 2>> pairs;
  if (!pairs_file.empty()) pairs = ism::io::read_feature_pairs(pairs_file, a, b).pairs;
  if (decimate > 0) {
    // Decimated with the landmarks kept (vertices that never collapse), the
    // pairs re-indexed into the decimated meshes.
    for (int s = 0; s < 2; ++s) {
      ism::TriangleMesh& m = s ? b : a;
      std::vector<int> keep;
      for (const auto& p : pairs) keep.push_back(p[s]);
      const ism::ProgressiveMesh pm = keep.empty() ? ism::simplify_to(m, decimate)
                                                   : ism::simplify_capped_to(m, {}, keep, decimate);
      std::vector<int> index(m.n_vertices(), -1);
      for (std::size_t i = 0; i < pm.base_vertices.size(); ++i) index[pm.base_vertices[i]] = int(i);
      for (auto& p : pairs) p[s] = index[p[s]];
      m = ism::base_mesh(pm);
    }
  }
  lap("input");
  const ism::CompatibleNetworks networks = ism::trace_compatible_networks(a, b, pairs);
  const auto pms = ism::simplify_compatible(networks);
  std::printf("base: %zu vertices (%zu features given), %zu faces; genus %d\n",
              networks.base.n_vertices(), pairs.size(), networks.base.n_faces(), networks.genus);
  lap("partition");
  // Features held until release_at of the splits (ism-map's default 0.5),
  // or released from the start.
  map_options.hold_features = release_at > 0;
  ism::InterSurfaceMap map(ism::side_from_pm(pms[0]), ism::side_from_pm(pms[1]), map_options);
  ism::SurfaceRefineOptions options;
  options.validate_each_step = each;
  options.block = block;
  options.threads = threads;
  if (split_batch > 0) options.split_batch = std::size_t(split_batch);
  if (local_budget >= 0) options.local_relaxation_budget = local_budget;
  options.optimise_other_side = other_side;
  if (level_sweeps >= 0) options.max_level_sweeps = level_sweeps;
  options.release_features_at = release_at;
  if (final_sweeps >= 0) options.max_final_sweeps = final_sweeps;
  options.race_level_sweeps = race;
  if (race_faces > 0) options.race_faces = race_faces;
  int shown = -5;  // progress on stderr, every 5 % of the splits
  options.progress = [&](double done) {
    const int percent = int(done * 100);
    if (percent / 5 == shown / 5) return;
    shown = percent;
    // Efficiency 2 / energy: the symmetric energy's terms are area-scaled.
    std::fprintf(stderr, "refine %3d %% (A %zu / B %zu faces), symmetric efficiency %.3f\n",
                 percent, map.n_faces(0), map.n_faces(1), 2 / map.energy());
  };
  double traced = trace ? map.energy() : 0;
  std::size_t steps = 0;
  if (trace)
    options.on_step = [&](const ism::SurfaceStep& step) {
      const double e = map.energy();
      ++steps;
      const bool split = step.kind == ism::SurfaceStep::split;
      const bool jump = e > 10 * traced;
      const bool mismatch = !split && std::abs((traced - e) - step.gain) > 1e-9 * traced;
      if (jump || mismatch)
        std::printf(
            "step %zu: %s vertex %d of side %d (A %zu / B %zu faces): energy %.6g -> "
            "%.6g, gain reported %.6g%s\n",
            steps, split ? "split, new" : "move of", step.vertex, step.side, map.n_faces(0),
            map.n_faces(1), traced, e, step.gain, mismatch ? " (not the drop)" : "");
      traced = e;
    };
  ism::SurfaceRefineStats stats;
  try {
    stats = ism::refine_surfaces(map, options);
  } catch (const std::exception& e) {
    // A split that cannot be placed is undone: the map is the one before it.
    std::fprintf(stderr, "inter_surface_map: %s\n", ism::describe_stop(map, e.what()).c_str());
    return 1;
  }
  lap("refine");
  const auto problem = map.validate();
  lap("validate");
  const ism::MapMeasures m = map.measures();
  const auto& st = map.stats();
  std::printf("A %zu faces, B %zu faces; valid from both sides: %s\n", map.n_faces(0),
              map.n_faces(1), problem ? problem->c_str() : "yes");
  std::printf(
      "symmetric efficiency %.4f (symmetric Dirichlet %.3f), one-way A->B %.4f, B->A %.4f\n",
      m.symmetric_efficiency, 4 / m.symmetric_efficiency, m.forward_efficiency,
      m.backward_efficiency);
  std::printf(
      "splits %zu, sweeps %zu + %zu final; optimisations %zu (moves %zu; charts: one face %zu, "
      "developed %zu, general %zu; refused by the check %zu); splits retried %zu, in place %zu "
      "(hard splits relaxed %zu)\n",
      stats.splits, stats.sweeps, stats.final_sweeps, st.optimizations, st.moves, st.fast_path,
      st.developed, st.general, st.rejected, st.split_retries, st.splits_in_place,
      stats.hard_splits);
  if (stats.race_winner >= 0) {
    std::printf("coarse race (%.2f s): level sweeps", stats.seconds_race);
    for (std::size_t k = 0; k < race.size(); ++k)
      std::printf(" %d: efficiency %.4f%s", race[k],
                  k < stats.race_energies.size() ? 2 / stats.race_energies[k] : 0.0,
                  int(k) == stats.race_winner ? " (kept)" : "");
    std::printf("\n");
  }
  std::printf("planned ahead: %zu plans held, %zu optimised anew (%.2f s planning)\n",
              st.plans_held, st.plans_stale, stats.seconds_planning);
  if (!problem) {
    // How the energy is spread: the share of its excess over the ideal
    // (2, an isometry) held by the worst 1 % and 10 % of side 1's faces.
    std::vector<double> per_face;
    for (std::size_t f = 0; f < map.n_faces(1); ++f)
      per_face.push_back(map.faces_energy(1, {int(f)}));
    const double total = map.energy();
    std::sort(per_face.rbegin(), per_face.rend());
    double top1 = 0, top10 = 0;
    for (std::size_t i = 0; i < per_face.size(); ++i) {
      if (i < (per_face.size() + 99) / 100) top1 += per_face[i];
      if (i < (per_face.size() + 9) / 10) top10 += per_face[i];
    }
    std::printf("energy %.4f; worst 1 %% of B's faces hold %.1f %%, worst 10 %% hold %.1f %%\n",
                total, 100 * top1 / total, 100 * top10 / total);
  }
  if (!problem) {
    const ism::MetaMeshSize size = ism::meta_mesh_size(map.meta());
    std::printf(
        "overlay: %zu pieces, %zu edge crossings, %zu kinks; %zu pieces triangulated (not a fan "
        "of their corners), %zu points added inside pieces\n",
        size.pieces, size.crossings, size.kinks, size.triangulated_pieces,
        size.points_inside_pieces);
    if (!meta_file.empty() && !ism::write_meta_mesh(map.meta(), meta_file)) {
      std::fprintf(stderr, "inter_surface_map: cannot write %s\n", meta_file.c_str());
      return 1;
    }
  }
  return problem ? 1 : 0;
}
