// Cost of the foundation stages on the largest shared genus-0 model: reading
// and checking a mesh, the PSNR measure (two AABB trees, 2 x F samples) and
// the progressive mesh of a candidate network.
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"

#include <benchmark/benchmark.h>

#include <filesystem>

namespace {

const std::filesystem::path kBunny = std::filesystem::path(ISM_SHARED_DIR) / "models/bunny.obj";

void read_and_check_bunny(benchmark::State& state) {
  if (!std::filesystem::exists(kBunny)) return state.SkipWithError("../shared/models absent");
  for (auto _ : state) {
    auto prepared = ism::prepare_mesh(ism::io::read_polygon_soup(kBunny));
    benchmark::DoNotOptimize(prepared.check.genus);
  }
}
BENCHMARK(read_and_check_bunny)->Unit(benchmark::kMillisecond);

void psnr_bunny_against_scaled_copy(benchmark::State& state) {
  if (!std::filesystem::exists(kBunny)) return state.SkipWithError("../shared/models absent");
  const ism::TriangleMesh bunny = ism::prepare_mesh(ism::io::read_polygon_soup(kBunny)).mesh;
  ism::TriangleMesh scaled = bunny;
  for (auto& p : scaled.positions) p *= 1.001;
  double psnr = 0;
  for (auto _ : state) psnr = ism::surface_distance(bunny, scaled).psnr_db;
  state.counters["psnr_db"] = psnr;
}
BENCHMARK(psnr_bunny_against_scaled_copy)->Unit(benchmark::kMillisecond);

// The progressive mesh of one candidate network: gim-remesh builds twelve.
void simplify_bunny_octahedral_network(benchmark::State& state) {
  if (!std::filesystem::exists(kBunny)) return state.SkipWithError("../shared/models absent");
  const ism::TriangleMesh bunny = ism::prepare_mesh(ism::io::read_polygon_soup(kBunny)).mesh;
  const ism::PathNetwork network = ism::trace_octahedral_network(bunny);
  const ism::TriangleMesh octahedron = ism::domain::octahedron();
  std::size_t splits = 0;
  for (auto _ : state) splits = ism::simplify_constrained(network, octahedron).splits.size();
  state.counters["splits"] = double(splits);
}
BENCHMARK(simplify_bunny_octahedral_network)->Unit(benchmark::kMillisecond);

void generate_sphere(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ism::shapes::sphere(int(state.range(0))));
}
BENCHMARK(generate_sphere)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
