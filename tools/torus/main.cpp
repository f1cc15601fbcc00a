// torus-remesh MESH -o OUT: valence-4 remesh of a closed genus-1 surface
// (paper §6.4). Nine features (given, or chosen from the surface's flat-torus
// structure) are joined by a consistent path network with the connectivity
// of the flat 3×3 torus domain::torus_3x3(), the map from that torus (faces
// right isosceles, the unit square's metric) to the surface is optimised with
// the features released, and the unit square is sampled on a periodic U×V
// grid: a closed quad mesh in which every vertex has valence 4
// (layout in sample/torus_grid.hpp).
#include "domain/domain.hpp"
#include "io/draco_io.hpp"
#include "io/features.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "refine/network_choice.hpp"
#include "refine/refine.hpp"
#include "report/report.hpp"
#include "sample/geometry_image_file.hpp"
#include "sample/torus_grid.hpp"
#include "tool/cli.hpp"
#include "tool/failure.hpp"
#include "tool/map_stage.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <regex>

namespace {

using namespace ism;

// No disc re-embeddings during local relaxation: on the flat torus the
// global re-embedding (refine/flat_reembedding.hpp) already moves every
// vertex at once, and with the discs teapot's best fallback map folded one
// grid triangle, so a map of efficiency 0.416 was kept instead of 0.444.
constexpr int kLocalDiscEvery = 0;

struct Options {
  std::string input, output, features, image, dump_patches;
  std::string size = "128";
  bool triangulate = false;
  bool no_global_reembedding = false;
  int draco_bits = 14;
  // The one-way weight folds fewer grid triangles on most models (teapot
  // 49 -> 22) and the symmetric energy on others (rocker_arm 9 -> 0).
  // When one of them folds grid triangles, the same two with an anisotropy
  // penalty (ratio of singular values past 3) are refined too and compete:
  // the folds sit where a skinny image of the grid cells crosses a bend of
  // the surface (teapot 16 -> 0, mug 13 -> 0, cup 18 -> 0, rocker_arm's
  // one-way variant 6 -> 0); elsewhere the penalty would only cost stretch
  // (knot 0.251 -> 0.202).
  tool::MapSettings map{
      .variants = {{.inverse_stretch_weight = 0.1}, {}},
      .fallback_variants = {
          {.inverse_stretch_weight = 0.1, .anisotropy_weight = 0.1, .anisotropy_threshold = 3},
          {.anisotropy_weight = 0.1, .anisotropy_threshold = 3}}};
};

struct GridSize {
  int columns = 0, rows = 0;
};

// "N" (N×N) or "UxV" (also "UXV", "U×V").
GridSize parse_size(const std::string& text) {
  static const std::regex pattern(R"((\d{1,9})(?:(?:x|X|×)(\d{1,9}))?)");
  std::smatch m;
  GridSize size;
  if (std::regex_match(text, m, pattern)) {
    size.columns = std::stoi(m[1]);
    size.rows = m[2].matched ? std::stoi(m[2]) : size.columns;
  }
  if (!is_torus_grid_size(size.columns, size.rows))
    throw tool::Failure("torus-remesh: --size must be N or UxV with N, U, V >= 3 and U*V <= " +
                        std::to_string(1 << 26) + ", got '" + text + "'");
  return size;
}

// Refuses an output format that cannot hold what is asked for, before any work.
void check_formats(const Options& o) {
  const std::string ext = std::filesystem::path(o.output).extension().string();
  const bool quad_format = ext == ".obj" || ext == ".ply" || ext == ".off";
  if (!o.triangulate && (ext == ".drc" || ext == ".stl"))
    throw tool::Failure("torus-remesh: " + o.output + ": " + (ext == ".drc" ? "Draco" : "STL") +
                        " stores triangles only; add --triangulate, or write the quads as .obj, "
                        ".ply or .off");
  if (!quad_format && ext != ".drc" && ext != ".stl")
    throw tool::Failure("torus-remesh: " + o.output +
                        ": unsupported output format (use .obj, .ply or .off; .stl or .drc with "
                        "--triangulate)");
  if (!o.image.empty() && std::filesystem::path(o.image).extension() != ".exr")
    throw tool::Failure("torus-remesh: " + o.image + ": --image writes OpenEXR, name it .exr");
}

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

// The feature grid with rows and columns swapped: the same lattice, the
// other orientation.
std::vector<int> transposed(const std::vector<int>& features) {
  std::vector<int> out(features.size());
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) out[3 * col + row] = features[3 * row + col];
  return out;
}

// Candidate path networks, each in the homotopy class of the surface's
// harmonic map to the flat torus (trace_torus_network): automatic, or from
// the user's nine features. A feature grid oriented against the domain (its
// rows and columns swapped with respect to the surface's orientation) has
// no network in that class, and elsewhere only twisted ones whose maps stay
// far from the best, so the transposed grid is traced too and, when both
// can be, the coarse maps decide (choose_network). Without any network the
// error of the grid as given is reported.
struct Candidates {
  std::vector<PathNetwork> networks;
  std::vector<int> given_features;  // empty for automatic features
};

Candidates torus_networks(tool::Run& run, const Options& o, const TriangleMesh& surface,
                          const TriangleMesh& torus) {
  tool::Progress& progress = run.stage("partition");
  const PartitionOptions options{.progress = [&](double f) { progress.update(f); }};
  Candidates c;
  try {
    if (o.features.empty()) {
      c.networks = trace_torus_networks(surface, options);
      return c;
    }
    const auto entries = io::read_feature_file(o.features);
    if (entries.size() != torus.n_vertices())
      throw tool::Failure(o.features + ": " + std::to_string(entries.size()) +
                          " features, torus-remesh needs 9 (row-major in the 3x3 grid)");
    c.given_features = io::resolve_features(entries, surface, 3, o.features);
    std::optional<PartitionError> first_error;
    for (const auto& grid : {c.given_features, transposed(c.given_features)}) {
      try {
        c.networks.push_back(trace_torus_network(surface, grid, options));
      } catch (const PartitionError& e) {
        if (!first_error) first_error = e;
      }
    }
    if (c.networks.empty()) throw *first_error;
    return c;
  } catch (const PartitionError& e) {
    throw tool::Failure(o.input + ": " + e.what() +
                        (o.features.empty() ? "" : " (features from " + o.features + ")"));
  } catch (const io::FileError& e) {
    throw tool::Failure(e.what());
  }
}

int run_torus(const Options& o, const tool::CommonOptions& common) {
  tool::Run run("torus-remesh", common);
  run.add_input(o.input);
  if (!o.features.empty()) run.add_input(o.features);
  const GridSize size = parse_size(o.size);
  check_formats(o);
  tool::check_torus_grid(run, size.columns, size.rows);
  tool::require_extension(run, "--dump-patches", o.dump_patches, {".ply"}, "PLY");
  for (const std::string& out : {o.output, o.image, o.dump_patches})
    if (!out.empty()) run.check_output(out);

  const TriangleMesh surface =
      run.load_surface(o.input, {.tool = "torus-remesh",
                                 .closed = true,
                                 .genus = 1,
                                 .min_vertices = 9,
                                 .min_vertices_reason = "one per vertex of the 3x3 torus grid"});

  const TriangleMesh torus = domain::torus_3x3();
  Candidates candidates = torus_networks(run, o, surface, torus);
  const std::size_t n_candidates = candidates.networks.size();

  // The unit square's metric: the stretch optimised is the stretch the grid samples with.
  const DomainGeometry domain(torus, torus_3x3_lengths(torus));
  // Progressive meshes and coarse maps of the candidates, then the refinement.
  // The domain is flat: with the features released, global re-embeddings
  // (refine/flat_reembedding.hpp) open what single-vertex moves leave
  // squeezed, in the candidates' coarse maps as in the final refinement.
  tool::Progress& progress = run.stage("map");
  // The variant kept folds fewest grid triangles, then has the best one-way stretch.
  auto sample = [&](const SurfaceMap& map) {
    const MapSampler sampler(map);
    return sample_torus_grid(size.columns, size.rows, [&](const TorusPoint& q) {
      const auto s = sampler.surface_point(q.face, q.bary);
      if (!s) throw std::runtime_error("a sample fell outside the map");
      return s->position;
    });
  };
  const auto [chosen, stats] = tool::run_map_stage(
      run, progress,
      {.input = o.input,
       .dump_patches = o.dump_patches,
       .global_flat_reembedding = !o.no_global_reembedding,
       .local_disc_every = kLocalDiscEvery,
       .hint = "try --hold-features or other --features",
       .retry_below = 0.0},
      o.map,
      [&](const MapOptions& options) {
        RefineOptions coarse;
        coarse.global_flat_reembedding = !o.no_global_reembedding;
        coarse.local_disc_every = kLocalDiscEvery;
        return choose_network(candidates.networks, domain, options, 1000, coarse);
      },
      [&](const SurfaceMap& map) {
        const TorusGrid grid = sample(map);
        return torus_grid_efficiency(grid) - double(torus_grid_flipped_triangles(grid));
      });
  const SurfaceMap& map = *chosen->map;
  run.report()["partition"] = partition_report(chosen->network, torus, chosen->pm);
  run.report()["partition"]["candidate_networks"] = n_candidates;
  Json& fj = run.report()["features"];
  fj["source"] = o.features.empty() ? "automatic" : "file";
  if (!o.features.empty()) {
    fj["file"] = o.features;
    const bool was_transposed = chosen->network.features != candidates.given_features;
    fj["transposed"] = was_transposed;
    if (was_transposed)
      run.note(o.features + ": using the feature grid transposed (rows as columns); as given " +
               (n_candidates == 1 ? "it cannot be traced"
                                  : "it gives a worse, twisted map (oriented against the domain)"));
  }

  const MetaMesh meta = tool::validate_map(run, map);

  run.stage("sample");
  const TorusGrid grid = sample(map);
  const QuadMesh quads = torus_grid_mesh(grid);
  const TriangleMesh triangles = torus_grid_triangles(grid);

  run.stage("write");
  tool::write_meta_mesh_output(run, o.map, meta);
  tool::write_output(run, o.output, [&](const std::filesystem::path& p) {
    if (o.triangulate)
      io::write_mesh_file(triangles, p, o.draco_bits);
    else
      io::write_quad_mesh(quads, p);
  });
  tool::write_output(run, o.image,
                     [&](const std::filesystem::path& p) { write_torus_image(grid, p); });

  run.stage("measure");
  const MapMeasures m = map.measures();
  const SurfaceDistance distance = surface_distance(surface, triangles);
  const double grid_efficiency = torus_grid_efficiency(grid);
  const std::size_t flipped = torus_grid_flipped_triangles(grid);
  Json& r = run.report();
  r["metric"] = "right-isosceles";
  r["map"] = map_report(map, m, stats);
  Json& gj = r["grid"];
  gj["columns"] = size.columns;
  gj["rows"] = size.rows;
  gj["efficiency"] = grid_efficiency;
  gj["flipped_triangles"] = flipped;
  Json& sj = r["remesh"];
  sj["vertices"] = quads.n_vertices();
  sj["faces"] = o.triangulate ? triangles.n_faces() : quads.n_faces();
  sj["face_kind"] = o.triangulate ? "triangles" : "quads";
  r["distance"] = distance_report(distance);
  run.note(o.output + ": " + std::to_string(size.columns) + "x" + std::to_string(size.rows) +
           " torus grid, " + std::to_string(quads.n_faces()) + " quads; map efficiency " +
           fixed(m.forward_efficiency, 3) + " (symmetric " + fixed(m.symmetric_efficiency, 3) +
           "), grid efficiency " + fixed(grid_efficiency, 3) + ", " + std::to_string(flipped) +
           " flipped triangles, PSNR " + fixed(distance.psnr_db, 1) + " dB");
  run.finish();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"torus-remesh: valence-4 grid remesh of a closed genus-1 surface"};
  Options o;
  tool::CommonOptions common;
  app.add_option("mesh", o.input, "Closed genus-1 surface (.obj, .ply, .off, .stl)")->required();
  app.add_option("-o,--output", o.output,
                 "Grid remesh: quads as .obj, .ply, .off; with --triangulate also .stl, .drc")
      ->required();
  app.add_option("--features", o.features,
                 "9 features, row-major in the 3x3 torus grid: vertex indices, points (snapped), "
                 "or ROW COL INDEX X Y Z lines (default: automatic)");
  app.add_option("--size", o.size, "Grid size N (NxN) or UxV, at least 3x3")->capture_default_str();
  app.add_flag("--triangulate", o.triangulate, "Write two triangles per grid quad");
  app.add_option("--image", o.image, "Periodic geometry image (.exr, V rows x U columns)");
  app.add_option("--dump-patches", o.dump_patches, "PLY of the path network's patches");
  tool::add_map_options(app, o.map);
  app.add_flag("--no-global-reembedding", o.no_global_reembedding,
               "Optimise one vertex at a time only (no global flat-torus re-embeddings)");
  app.add_option("--draco-bits", o.draco_bits, "Draco position quantisation bits (.drc)")
      ->check(CLI::Range(8, 30));
  tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);
  return tool::run_main("torus-remesh", [&] { return run_torus(o, common); });
}
