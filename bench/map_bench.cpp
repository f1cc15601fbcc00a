// One row of the map benchmark: the whole octahedral pipeline on one model
// (partition, constrained progressive mesh, refinement, validation), with
// stage times, peak memory, efficiencies and the fast-path fraction.
//   map_bench MESH [equilateral|right_isosceles]
// Prints one Markdown table row; bench/map.sh runs it per model (one process
// per model, so peak memory is that model's).
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/network_choice.hpp"
#include "sample/sample.hpp"
#include "tool/tool.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  const bool equilateral = argc > 2 && std::strcmp(argv[2], "equilateral") == 0;
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  const auto t0 = Clock::now();
  const ism::TriangleMesh surface = ism::prepare_mesh(ism::io::read_polygon_soup(argv[1])).mesh;
  const auto t1 = Clock::now();
  std::vector<ism::PathNetwork> networks = ism::trace_octahedral_networks(surface);
  const auto t2 = Clock::now();
  const ism::TriangleMesh octahedron = ism::domain::octahedron();
  const ism::DomainGeometry domain(
      octahedron,
      ism::octahedron_lengths(octahedron, equilateral ? ism::DomainMetric::equilateral
                                                      : ism::DomainMetric::right_isosceles));
  const std::size_t candidates = networks.size();
  // Progressive meshes of every candidate and their coarse maps: the choice.
  const auto chosen = ism::choose_network(std::move(networks), domain, {});
  const auto t3 = Clock::now();
  const ism::PathNetwork& network = chosen->network();
  ism::SurfaceMap& map = *chosen->map;
  const ism::RefineStats stats = ism::refine(map);
  const auto t4 = Clock::now();
  const bool valid = !map.validate();
  const auto t5 = Clock::now();
  const ism::MapMeasures m = map.measures();
  // The symmetric meta-mesh: built, validated from both sides, measured.
  const auto t6 = Clock::now();
  const auto meta = ism::meta_mesh(map);
  const auto meta_pieces = meta ? ism::meta_pieces(*meta) : std::nullopt;
  const bool meta_valid = meta_pieces.has_value();
  const auto meta_measures = meta_valid ? std::optional(ism::measures(*meta_pieces)) : std::nullopt;
  const auto t7 = Clock::now();
  // Queries through it (indexed from its pieces): a 1025² octahedral
  // geometry image (domain -> surface, on the threads sample_octahedral
  // uses), then as many points back (surface -> domain, one thread), spread
  // over the faces of M².
  std::atomic<std::size_t> missed = 0;
  auto t8 = t7;
  if (meta_valid) {
    const ism::MetaMeshSampler sampler(*meta, *meta_pieces);
    ism::sample_octahedral(1025, [&](const ism::OctahedronPoint& q) {
      const auto s = sampler.map_point(0, q.face, q.bary);
      missed += !s;
      return ism::Vec3(s ? s->bary : Eigen::Vector3d::Zero());
    });
    t8 = Clock::now();
    const std::size_t n_back = 1025 * 1025;
    for (std::size_t i = 0; i < n_back; ++i) {
      const double a = double(i % 97) / 97.0, b = (1.0 - a) * double(i % 89) / 89.0;
      missed += !sampler.map_point(1, int(i % map.n_faces()), Eigen::Vector3d(a, b, 1 - a - b));
    }
  }
  const auto t9 = Clock::now();
  const std::size_t pieces = meta_valid ? meta_pieces->size() : 0;
  std::printf(
      "| %s | %zu | %zu | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %s | %.3f | %.3f | %.3f "
      "| %.1f%% | %zu / %zu | %.2f | %.2f%s | %zu | %.2f | %s |\n",
      std::filesystem::path(argv[1]).filename().c_str(), surface.n_faces(),
      network.steiner_vertices(), candidates, seconds(t1, t2), seconds(t2, t3), seconds(t3, t4),
      seconds(t4, t5), seconds(t0, t5), ism::tool::peak_memory_bytes() / 1048576.0,
      valid ? "yes" : "NO", m.forward_efficiency, m.backward_efficiency, m.symmetric_efficiency,
      100.0 * stats.single_face_rings / std::max<std::size_t>(1, stats.optimizations),
      stats.discs_applied, stats.discs, seconds(t7, t8), seconds(t8, t9), missed ? " (missed)" : "",
      pieces, seconds(t6, t7),
      !meta_valid ? "NO"
      : std::abs(meta_measures->symmetric_efficiency - m.symmetric_efficiency) < 1e-9
          ? "yes"
          : "measures differ");
  return valid && meta_valid ? 0 : 1;
}
