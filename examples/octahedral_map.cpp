// The whole map pipeline on one surface with the octahedron as M¹:
// partition, constrained progressive mesh, coarse-to-fine refinement,
// validation and measures, with the time of each stage.
// With --symmetric the map is built on the symmetric core (InterSurfaceMap:
// the octahedron as side 0, never refining, its vertices released
// continuously; the surface as side 1, refined by refine_surfaces) instead
// of SurfaceMap, for comparison. Environment: ISM_HOLD holds the features
// (both cores); ISM_LEVEL_SWEEPS, ISM_FINAL_SWEEPS and ISM_LOCAL_BUDGET set
// the symmetric core's sweep counts and local relaxation budget,
// ISM_HARD_SPLIT_GROWTH its hard splits' threshold (hard_split_growth);
// ISM_KINKS=follow_cells bends its edges wherever they cross a cell whose
// map is not affine (InterSurfaceOptions::kinks; default where_needed, the
// paper's rule);
// ISM_NO_LOCAL, ISM_NO_DISC, ISM_FEW_SWEEPS (2 per level, 4 final, no
// coarse-level extra) and ISM_PLAIN (all three) strip SurfaceMap's
// refinement schedule.
// With --base BASE.obj (a closed mesh of the surface's genus whose vertices
// lie near the surface, e.g. semireg's --write-base) M¹ is that base with
// equilateral faces, semireg's domain, instead of the octahedron: its
// vertices snap to the nearest surface vertices and are the features.
//   octahedral_map MESH [--equilateral] [--validate-each-step] [--symmetric]
//                  [--base BASE.obj]
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "refine/refine_surfaces.hpp"
#include "tool/tool.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

namespace {

template <class Lap>
int run_symmetric(const ism::DomainGeometry& domain, const ism::ProgressiveMesh& pm, bool each,
                  Lap& lap) {
  ism::InterSurfaceOptions map_options;
  map_options.hold_features = std::getenv("ISM_HOLD") != nullptr;
  if (const char* rule = std::getenv("ISM_KINKS"); rule && std::strcmp(rule, "follow_cells") == 0)
    map_options.kinks = ism::KinkRule::follow_cells;
  ism::InterSurfaceMap map(ism::side_from_domain(domain, pm), ism::side_from_pm(pm), map_options);
  ism::SurfaceRefineOptions options;
  options.validate_each_step = each;
  if (const char* n = std::getenv("ISM_LEVEL_SWEEPS")) options.max_level_sweeps = std::atoi(n);
  if (const char* n = std::getenv("ISM_FINAL_SWEEPS")) options.max_final_sweeps = std::atoi(n);
  if (const char* n = std::getenv("ISM_LOCAL_BUDGET"))
    options.local_relaxation_budget = std::atof(n);
  if (const char* n = std::getenv("ISM_HARD_SPLIT_GROWTH"))
    options.hard_split_growth = std::atof(n);
  int shown = -1;
  options.progress = [&](double f) {
    if (int(f * 10) > shown) std::fprintf(stderr, "refine %3d %%\n", (shown = int(f * 10)) * 10);
  };
  ism::SurfaceRefineStats stats;
  try {
    stats = ism::refine_surfaces(map, options);
  } catch (const std::exception& e) {
    // A split that cannot be placed is undone: the map is the one before it.
    std::fprintf(stderr, "octahedral_map: %s\n", ism::describe_stop(map, e.what()).c_str());
    return 1;
  }
  lap("refine");
  const auto problem = map.validate();
  lap("validate");
  const ism::MapMeasures m = map.measures();
  const ism::MapOperationStats& o = map.stats();
  std::printf("faces %zu, valid %s\n", map.n_faces(1), problem ? problem->c_str() : "yes");
  std::printf("efficiency: symmetric %.4f, domain->surface %.4f, surface->domain %.4f\n",
              m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency);
  std::printf(
      "optimisations %zu (moves %zu): one-ring in one face %.1f%%, developed %.1f%%, "
      "general %.1f%%; sweeps %zu + %zu final; hard splits %zu\n",
      o.optimizations, o.moves, 100.0 * o.fast_path / std::max<std::size_t>(1, o.optimizations),
      100.0 * o.developed / std::max<std::size_t>(1, o.optimizations),
      100.0 * o.general / std::max<std::size_t>(1, o.optimizations), stats.sweeps,
      stats.final_sweeps, stats.hard_splits);
  const ism::MetaMeshSize size = ism::meta_mesh_size(map.meta());
  std::printf("overlay: %zu pieces, %zu crossings, %zu kinks, %zu pieces triangulated\n",
              size.pieces, size.crossings, size.kinks, size.triangulated_pieces);
  std::printf("peak memory %.0f MB\n", ism::tool::peak_memory_bytes() / 1048576.0);
  return problem ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: octahedral_map MESH [--equilateral] [--validate-each-step] [--symmetric] "
                 "[--base BASE.obj]\n");
    return 2;
  }
  bool equilateral = false, each = false, symmetric = false;
  const char* base_file = nullptr;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--base") == 0 && i + 1 < argc) base_file = argv[++i];
    equilateral |= std::strcmp(argv[i], "--equilateral") == 0;
    each |= std::strcmp(argv[i], "--validate-each-step") == 0;
    symmetric |= std::strcmp(argv[i], "--symmetric") == 0;
  }
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  auto lap = [&](const char* what) {
    const auto now = Clock::now();
    std::printf("%-10s %7.2f s\n", what, std::chrono::duration<double>(now - t0).count());
    t0 = now;
  };
  const ism::TriangleMesh surface = ism::prepare_mesh(ism::io::read_polygon_soup(argv[1])).mesh;
  lap("read");
  ism::TriangleMesh octahedron = ism::domain::octahedron();
  std::vector<ism::FaceLengths> lengths;
  ism::PathNetwork network;
  if (base_file) {
    // semireg's domain: the base with equilateral faces, its vertices on
    // the nearest surface vertices.
    octahedron = ism::prepare_mesh(ism::io::read_polygon_soup(base_file)).mesh;
    std::vector<ism::io::FeatureEntry> points(octahedron.n_vertices());
    for (std::size_t i = 0; i < points.size(); ++i) points[i].point = octahedron.positions[i];
    network = ism::trace_path_network(surface, octahedron,
                                      ism::io::resolve_features(points, surface, 0, base_file));
    lengths = ism::equilateral_lengths(octahedron);
  } else {
    network = ism::trace_octahedral_network(surface);
    lengths = ism::octahedron_lengths(octahedron, equilateral ? ism::DomainMetric::equilateral
                                                              : ism::DomainMetric::right_isosceles);
  }
  lap("partition");
  const ism::ProgressiveMesh pm = ism::simplify_constrained(network, octahedron);
  lap("pm");
  const ism::DomainGeometry domain(octahedron, lengths);
  if (symmetric) return run_symmetric(domain, pm, each, lap);
  ism::MapOptions map_options;
  map_options.release_features = std::getenv("ISM_HOLD") == nullptr;
  ism::SurfaceMap map(domain, pm, map_options);
  ism::RefineOptions options;
  options.validate_each_step = each;
  const bool plain = std::getenv("ISM_PLAIN") != nullptr;
  if (plain || std::getenv("ISM_NO_LOCAL")) options.local_relaxation_budget = 0;
  if (plain || std::getenv("ISM_NO_DISC")) options.max_discs = 0, options.local_disc_every = 0;
  if (plain || std::getenv("ISM_FEW_SWEEPS"))
    options.coarse_vertices = 0, options.max_level_sweeps = 2, options.max_final_sweeps = 4;
  const ism::RefineStats stats = ism::refine(map, options);
  lap("refine");
  const auto problem = map.validate();
  lap("validate");
  const ism::MapMeasures m = map.measures();
  std::printf("faces %zu (steiner %zu), valid %s\n", map.n_faces(), network.steiner_vertices(),
              problem ? problem->c_str() : "yes");
  std::printf("efficiency: symmetric %.4f, domain->surface %.4f, surface->domain %.4f\n",
              m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency);
  std::printf("optimisations %zu, one-ring in one M¹ face %.1f%%, sweeps %zu + %zu final\n",
              stats.optimizations,
              100.0 * stats.single_face_rings / std::max<std::size_t>(1, stats.optimizations),
              stats.sweeps, stats.final_sweeps);
  std::printf("peak memory %.0f MB\n", ism::tool::peak_memory_bytes() / 1048576.0);
  return problem ? 1 : 0;
}
