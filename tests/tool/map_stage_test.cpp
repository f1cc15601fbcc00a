// The map stage's variants: each refined whole, the best by the front end's
// score kept and reported, failures of single variants tolerated.
#include "tool/map_stage.hpp"
#include "domain/domain.hpp"
#include "domain_candidates.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"
#include "tool/failure.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

namespace ism::tool {
namespace {

struct Blob {
  TriangleMesh octahedron = domain::octahedron();
  DomainGeometry geometry{octahedron,
                          octahedron_lengths(octahedron, DomainMetric::right_isosceles)};
  std::vector<PathNetwork> networks{trace_octahedral_network(shapes::blob(800, 4, 0.4))};
};

const MapSettings two_weights{
    .variants = {{.inverse_stretch_weight = 1.0}, {.inverse_stretch_weight = 0.1}}};

TEST(MapStage, KeepsTheVariantWithTheHighestScore) {
  Blob blob;
  const auto choose = [&](const MapOptions& options, std::size_t) {
    return only(choose_network(blob.networks, blob.geometry, options));
  };
  for (const bool prefer_one_way : {true, false}) {
    SCOPED_TRACE(prefer_one_way);
    tool::Run run("test", {.quiet = true});
    Progress& progress = run.stage("map");
    const MapScore score = [&](const SurfaceMap& map) {
      const MapMeasures m = map.measures();
      return prefer_one_way ? m.forward_efficiency : m.symmetric_efficiency;
    };
    const MapStageResult result =
        run_map_stage(run, progress, {.input = "blob"}, two_weights, choose, score);
    ASSERT_TRUE(result.setup && result.setup->map);
    EXPECT_EQ(result.setup->map->validate(), std::nullopt);
    EXPECT_EQ(result.setup->map->n_vertices(), blob.networks[0].surface.n_vertices());
    // The weight 0.1 map has the better one-way, the weight 1 map the better
    // symmetric stretch: each score keeps its own.
    EXPECT_EQ(result.setup->map->options().inverse_stretch_weight, prefer_one_way ? 0.1 : 1.0);
    const std::string report = report_text(run.report());
    EXPECT_NE(report.find("\"map_variants\""), std::string::npos);
    const std::size_t first = report.find("\"kept\": true");
    ASSERT_NE(first, std::string::npos);
    EXPECT_EQ(report.find("\"kept\": true", first + 1), std::string::npos) << "one variant kept";
  }
}

TEST(MapStage, OneFailingVariantIsDroppedAndAllFailingIsAFailure) {
  Blob blob;
  int calls = 0;
  const auto choose_second_fails = [&](const MapOptions& options, std::size_t) {
    ++calls;
    if (options.inverse_stretch_weight < 1) throw std::runtime_error("no coarse map");
    return only(choose_network(blob.networks, blob.geometry, options));
  };
  const MapScore score = [](const SurfaceMap& map) { return map.measures().forward_efficiency; };
  tool::Run run("test", {.quiet = true});
  Progress& progress = run.stage("map");
  const MapStageResult result =
      run_map_stage(run, progress, {.input = "blob"}, two_weights, choose_second_fails, score);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(result.setup->map->options().inverse_stretch_weight, 1.0);
  EXPECT_NE(report_text(run.report()).find("no coarse map"), std::string::npos);

  const auto choose_fails = [](const MapOptions&,
                               std::size_t) -> std::vector<std::unique_ptr<MapSetup>> {
    throw std::runtime_error("no coarse map");
  };
  try {
    run_map_stage(run, progress, {.input = "blob.obj", .hint = "try X"}, two_weights, choose_fails,
                  score);
    FAIL() << "no variant succeeded, yet no Failure";
  } catch (const Failure& e) {
    EXPECT_EQ(std::string(e.what()),
              "test: the map optimisation failed on blob.obj (no coarse map); try X");
  }
}

TEST(MapStage, FallbackVariantsRunOnlyBelowTheThresholdAndCompete) {
  Blob blob;
  std::atomic<int> calls{0};
  const auto choose = [&](const MapOptions& options, std::size_t) {
    ++calls;
    return only(choose_network(blob.networks, blob.geometry, options));
  };
  const MapScore score = [](const SurfaceMap& map) { return map.measures().forward_efficiency; };
  const MapSettings settings{.variants = {{.inverse_stretch_weight = 1.0}},
                             .fallback_variants = {{.inverse_stretch_weight = 0.1}}};
  for (const double retry_below : {0.0, 2.0}) {  // efficiencies lie in (0, 1]
    SCOPED_TRACE(retry_below);
    calls = 0;
    tool::Run run("test", {.quiet = true});
    Progress& progress = run.stage("map");
    const MapStageResult result = run_map_stage(
        run, progress, {.input = "blob", .retry_below = retry_below}, settings, choose, score);
    const bool retried = retry_below > 1;
    EXPECT_EQ(calls.load(), retried ? 2 : 1);
    const std::string report = report_text(run.report());
    EXPECT_EQ(report.find("\"fallback\": true") != std::string::npos, retried);
    // The one-way score prefers the fallback's weight 0.1 when it runs.
    EXPECT_EQ(result.setup->map->options().inverse_stretch_weight, retried ? 0.1 : 1.0);
  }
}

// Contenders: the best two coarse candidates of a variant both refined
// whole; the higher final score is kept, and both are reported.
TEST(MapStage, ContendersAreRefinedWholeAndCompete) {
  const TriangleMesh surface = shapes::blob(3000, 5, 0.4);
  const auto choose = [&](const MapOptions& options, std::size_t count) {
    return rank_domains(test::decimated_candidates(surface, 30), options, 300, {}, count);
  };
  const MapScore score = [](const SurfaceMap& map) { return map.measures().forward_efficiency; };
  tool::Run run("test", {.quiet = true});
  Progress& progress = run.stage("map");
  const MapStageResult result =
      run_map_stage(run, progress, {.input = "blob"}, {.contenders = 2}, choose, score);
  EXPECT_EQ(result.setup->map->validate(), std::nullopt);
  EXPECT_EQ(result.setup->map->n_vertices(), result.setup->network().surface.n_vertices());
  const Json& maps = run.report()["map_variants"];
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0]["contender"], 0);
  EXPECT_EQ(maps[1]["contender"], 1);
  EXPECT_NE(maps[0]["candidate"], maps[1]["candidate"]);
  const std::size_t kept = maps[0]["kept"] == true ? 0 : 1;
  EXPECT_EQ(maps[kept]["kept"], true);
  EXPECT_EQ(maps[1 - kept]["kept"], false);
  EXPECT_GE(maps[kept]["score"].get<double>(), maps[1 - kept]["score"].get<double>());
  EXPECT_EQ(maps[kept]["candidate"], result.setup->candidate);
  EXPECT_DOUBLE_EQ(score(*result.setup->map), maps[kept]["score"].get<double>());
}

}  // namespace
}  // namespace ism::tool
