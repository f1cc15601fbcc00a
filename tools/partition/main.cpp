// ism-partition A B [--features PAIRS | --landmarks LA LB]: consistent
// partition of two surfaces of the same topology into corresponding
// triangular patches, and the two progressive meshes to their one base
// (paper §3 steps 1-2, §4). Writes the patches of both for looking at them,
// the base mesh, and a report.
#include "io/features.hpp"
#include "io/io.hpp"
#include "partition/compatible_networks.hpp"
#include "pm/pm.hpp"
#include "report/report.hpp"
#include "tool/cli.hpp"
#include "tool/failure.hpp"

#include <cstdio>

namespace {

using namespace ism;

struct Options {
  std::string a, b, features, dump_patches, write_base;
  std::vector<std::string> landmarks;
  bool no_swirl = false;
};

int run_partition(const Options& o, const tool::CommonOptions& common) {
  tool::Run run("ism-partition", common);
  run.add_input(o.a);
  run.add_input(o.b);
  if (!o.features.empty()) run.add_input(o.features);
  for (const auto& l : o.landmarks) run.add_input(l);
  const std::string dump_a = o.dump_patches.empty() ? "" : o.dump_patches + "_A.ply";
  const std::string dump_b = o.dump_patches.empty() ? "" : o.dump_patches + "_B.ply";
  for (const std::string& out : {dump_a, dump_b, o.write_base})
    if (!out.empty()) run.check_output(out);

  std::array<MeshCheck, 2> check;
  const TriangleMesh a = run.load_surface(o.a, {.tool = "ism-partition"}, &check[0]);
  const TriangleMesh b = run.load_surface(o.b, {.tool = "ism-partition"}, &check[1]);

  run.stage("features");
  io::FeaturePairs pairs;
  try {
    if (!o.features.empty()) {
      pairs = io::read_feature_pairs(o.features, a, b, {o.a, o.b});
      if (pairs.pairs.empty())
        throw tool::Failure(o.features +
                            ": no feature pairs (omit --features for automatic features)");
    } else if (!o.landmarks.empty()) {
      pairs = io::read_landmark_pairs(o.landmarks[0], a, o.landmarks[1], b, {o.a, o.b});
      if (pairs.pairs.empty())
        throw tool::Failure(o.landmarks[0] + ", " + o.landmarks[1] +
                            ": no landmark pairs (omit --landmarks for automatic features)");
    }
  } catch (const io::FileError& e) {
    throw tool::Failure(e.what());
  }
  // Vertex indices refer to the files; reading must not have renumbered them.
  for (int s = 0; s < 2 && pairs.by_index; ++s)
    if (check[s].welded_vertices || check[s].unreferenced_vertices)
      throw tool::Failure((s ? o.b : o.a) +
                          ": reading renumbered its vertices (coincident vertices welded or "
                          "unreferenced ones dropped), so vertex indices of the pairs would name "
                          "other vertices; give the pairs as points (X Y Z) instead");
  if (pairs.unmatched)
    run.note(std::to_string(pairs.unmatched) + " landmarks have an id in one list only (skipped)");

  tool::Progress& progress = run.stage("partition");
  CompatibleOptions options;
  options.swirl_heuristics = !o.no_swirl;
  options.names = {o.a, o.b};
  options.progress = [&](double f) { progress.update(f); };
  CompatibleNetworks networks;
  try {
    networks = trace_compatible_networks(a, b, pairs.pairs, options);
  } catch (const PartitionError& e) {
    throw tool::Failure(std::string("ism-partition: ") + e.what());
  }

  tool::Progress& pm_progress = run.stage("progressive meshes");
  SimplifyOptions simplify;
  simplify.progress = [&](double f) { pm_progress.update(f); };
  const std::array<ProgressiveMesh, 2> pms = simplify_compatible(networks, simplify);

  run.stage("validate");
  const char* const name[2] = {"A", "B"};
  Json& r = run.report();
  r["partition"] = compatible_partition_report(networks, pms);
  Json& checks = r["partition"]["checks"];
  // trace_compatible_networks() returns only networks that validate_compatible() accepts.
  checks["networks_valid"] = true;
  for (int s = 0; s < 2; ++s) {
    const auto mismatch = replay_mismatch(pms[s], networks.networks[s].surface);
    checks[std::string("replay_exact_") + name[s]] = !mismatch;
    if (mismatch) throw std::runtime_error(std::string("replay of ") + name[s] + ": " + *mismatch);
    const TriangleMesh base = base_mesh(pms[s]);
    const bool same = base.triangles == networks.base.triangles;
    checks[std::string("base_identical_") + name[s]] = same;
    if (!same) throw std::runtime_error(std::string("the base of ") + name[s] + " differs");
  }

  run.stage("write");
  tool::write_output(run, dump_a, [&](const std::filesystem::path& p) {
    write_patch_dump(networks.networks[0], p);
  });
  tool::write_output(run, dump_b, [&](const std::filesystem::path& p) {
    write_patch_dump(networks.networks[1], p);
  });
  tool::write_output(run, o.write_base,
                     [&](const std::filesystem::path& p) { io::write_mesh(networks.base, p); });

  std::size_t added = 0;
  for (const FeaturePair& f : networks.features) added += f.origin != FeatureOrigin::given;
  run.note("base: " + std::to_string(networks.base.n_vertices()) + " vertices (" +
           std::to_string(networks.features.size() - added) + " given, " + std::to_string(added) +
           " added), " + std::to_string(networks.base.n_faces()) + " faces; Steiner vertices " +
           std::to_string(networks.networks[0].steiner_vertices()) + " on A, " +
           std::to_string(networks.networks[1].steiner_vertices()) +
           " on B; both progressive meshes replay exactly");
  run.finish();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ism-partition: corresponding triangular patches on two surfaces of the same topology, "
      "and their progressive meshes to one base"};
  Options o;
  ism::tool::CommonOptions common;
  app.add_option("a", o.a, "Surface A (.obj, .ply, .off, .stl)")->required();
  app.add_option("b", o.b, "Surface B, same genus and boundary loops as A")->required();
  auto* features = app.add_option(
      "--features", o.features,
      "Feature pairs: 'IA IB' (0-based vertex indices) or 'XA YA ZA XB YB ZB' per line; "
      "default: automatic features");
  auto* landmarks =
      app.add_option("--landmarks", o.landmarks,
                     "Two landmark lists LA LB, one per surface: 'INDEX' or 'X Y Z' per line "
                     "(paired by line order) or 'ID X Y Z' (paired by id)")
          ->expected(2);
  features->excludes(landmarks);
  landmarks->excludes(features);
  app.add_option("--dump-patches", o.dump_patches,
                 "Write PREFIX_A.ply and PREFIX_B.ply, patches coloured alike on both");
  app.add_option("--write-base", o.write_base, "Write the common base mesh (positions on A)");
  app.add_flag("--no-swirl-heuristics", o.no_swirl,
               "Plain shortest pairs of paths, without the paper's heuristics against swirls");
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  return ism::tool::run_main("ism-partition", [&] { return run_partition(o, common); });
}
