// The whole map pipeline on one surface with the octahedron as M¹:
// partition, constrained progressive mesh, coarse-to-fine refinement,
// validation and measures, with the time of each stage.
//   octahedral_map MESH [--equilateral] [--validate-each-step]
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "tool/tool.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: octahedral_map MESH [--equilateral] [--validate-each-step]\n");
    return 2;
  }
  bool equilateral = false, each = false;
  for (int i = 2; i < argc; ++i) {
    equilateral |= std::strcmp(argv[i], "--equilateral") == 0;
    each |= std::strcmp(argv[i], "--validate-each-step") == 0;
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
  const ism::PathNetwork network = ism::trace_octahedral_network(surface);
  lap("partition");
  const ism::TriangleMesh octahedron = ism::domain::octahedron();
  const ism::ProgressiveMesh pm = ism::simplify_constrained(network, octahedron);
  lap("pm");
  const ism::DomainGeometry domain(
      octahedron,
      ism::octahedron_lengths(octahedron, equilateral ? ism::DomainMetric::equilateral
                                                      : ism::DomainMetric::right_isosceles));
  ism::MapOptions map_options;
  map_options.release_features = std::getenv("ISM_HOLD") == nullptr;
  ism::SurfaceMap map(domain, pm, map_options);
  ism::RefineOptions options;
  options.validate_each_step = each;
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
