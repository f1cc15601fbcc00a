// Cost of the foundation stages on the largest shared genus-0 model: reading
// and checking a mesh, and the PSNR measure (two AABB trees, 2 x F samples).
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"
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

void generate_sphere(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ism::shapes::sphere(int(state.range(0))));
}
BENCHMARK(generate_sphere)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
