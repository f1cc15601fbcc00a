#include "pipeline/torus_remesh.hpp"

#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "refine/flat_reembedding.hpp"
#include "refine/network_choice.hpp"
#include "refine/refine.hpp"
#include "report/report.hpp"
#include "sample/geometry_image_file.hpp"
#include "tool/limits.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <regex>

namespace ism::pipeline {
namespace {

// No disc re-embeddings during local relaxation: on the flat torus the
// global re-embedding (refine/flat_reembedding.hpp) already moves every
// vertex at once, and with the discs teapot's best fallback map folded one
// grid triangle, so a map of efficiency 0.416 was kept instead of 0.444.
constexpr int kLocalDiscEvery = 0;

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
void check_formats(const TorusRemeshOptions& o) {
  const std::string ext = std::filesystem::path(o.output).extension().string();
  const bool quad_format = ext == ".obj" || ext == ".ply" || ext == ".off";
  if (!o.output.empty() && !o.triangulate && (ext == ".drc" || ext == ".stl"))
    throw tool::Failure("torus-remesh: " + o.output + ": " + (ext == ".drc" ? "Draco" : "STL") +
                        " stores triangles only; add --triangulate, or write the quads as .obj, "
                        ".ply or .off");
  if (!o.output.empty() && !quad_format && ext != ".drc" && ext != ".stl" && ext != ".glb")
    throw tool::Failure("torus-remesh: " + o.output +
                        ": unsupported output format (use .obj, .ply or .off; .stl or .drc with "
                        "--triangulate; .glb, triangles)");
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

Candidates torus_networks(tool::Run& run, const TorusRemeshOptions& o, const TriangleMesh& surface,
                          const TriangleMesh& torus) {
  tool::Progress& progress = run.stage("partition");
  const PartitionOptions options{.progress = [&](double f) { progress.update(f); }};
  Candidates c;
  try {
    if (o.features.empty()) {
      c.networks = trace_torus_networks(surface, options);
      return c;
    }
    const auto entries = o.features.read();
    if (entries.size() != torus.n_vertices())
      throw tool::Failure(o.features.path + ": " + std::to_string(entries.size()) +
                          " features, torus-remesh needs 9 (row-major in the 3x3 grid)");
    c.given_features = io::resolve_features(entries, surface, 3, o.features.path);
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
    throw tool::Failure(o.input.path + ": " + e.what() +
                        (o.features.empty() ? "" : " (features from " + o.features.path + ")"));
  } catch (const io::FileError& e) {
    throw o.features.entries ? tool::Failure(e.what()) : tool::reading_failure(o.features.path, e);
  }
}

}  // namespace

TorusRemeshResult torus_remesh(tool::Run& run, const TorusRemeshOptions& o) {
  const std::string& input = o.input.path;
  if (!o.input.soup) run.add_input(input);
  if (!o.features.empty() && !o.features.entries) run.add_input(o.features.path);
  const GridSize size = parse_size(o.size);
  check_formats(o);
  tool::check_settings("torus-remesh", o.map, o.mesh_file);
  tool::check_torus_grid(run, size.columns, size.rows);
  tool::require_extension(run, "--dump-patches", o.dump_patches, {".ply"}, "PLY");
  for (const std::string& out : {o.output, o.image, o.dump_patches})
    if (!out.empty()) run.check_output(out);

  const TriangleMesh surface =
      run.load_surface(o.input, {.tool = "torus-remesh",
                                 .closed = true,
                                 .closed_advice = "fill its holes first (e.g. MeshLab's "
                                                  "Close Holes)",
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
  // Folded triangles are re-sampled nearby (unless o.unfold is off) before
  // a grid is scored or written.
  struct Sampled {
    TorusGrid grid;
    UnfoldReport unfolded;  // folds_after: the grid's flipped triangles
  };
  auto sample_with = [&](const auto& sampler) {
    auto at = [&](const TorusPoint& q) {
      const auto s = sampler.surface_point(q.face, q.bary);
      if (!s) throw std::runtime_error("a sample fell outside the map");
      return s->position;
    };
    Sampled out{sample_torus_grid(size.columns, size.rows, at), {}};
    if (o.unfold) {
      out.unfolded = unfold_torus_grid(out.grid, at);
    } else {
      out.unfolded.folds_before = out.unfolded.folds_after = torus_grid_flipped_triangles(out.grid);
    }
    return out;
  };
  auto sample_meta = [&](const MetaMesh& meta) {
    return sample_with(DomainSurfaceSampler(meta, domain));
  };
  // (A variant's map that does not validate scores lowest; the epilogue
  // says why if it is kept.)
  auto sample = [&](const SurfaceMap& map) -> std::optional<Sampled> {
    const std::optional<MetaMesh> meta = meta_mesh(map);
    if (!meta) return std::nullopt;
    return sample_meta(*meta);
  };
  // The variant kept folds fewest grid triangles, then has the best one-way stretch.
  auto grid_score = [](const Sampled& s) {
    return torus_grid_efficiency(s.grid) - double(s.unfolded.folds_after);
  };
  // Every variant ranks the same networks: their progressive meshes are
  // built once.
  NetworkCandidates shared(std::move(candidates.networks), domain, o.map.variants.size());
  const tool::MapStageResult staged = tool::run_map_stage(
      run, progress,
      {.input = input,
       .dump_patches = o.dump_patches,
       .global_flat_reembedding = !o.no_global_reembedding,
       .local_disc_every = kLocalDiscEvery,
       .hint = "try --hold-features or other --features",
       .retry_below = 0.0,
       // After the coarse levels' global re-embeddings (RefineOptions::reembed_max_vertices).
       .symmetric_from_vertices = RefineOptions{}.reembed_max_vertices,
       .symmetric_local_disc_every = kLocalDiscEvery,
       .symmetric_before_final =
           [&](InterSurfaceMap& map) {
             if (o.no_global_reembedding) return 0.0;
             const FlatReembeddingStats s = global_flat_reembedding(map, domain);
             return s.energy_before - s.energy_after;
           },
       .symmetric_score =
           [&](const InterSurfaceMap& map) { return grid_score(sample_meta(map.meta())); }},
      o.map,
      [&](const MapOptions& options, std::size_t count) {
        RefineOptions coarse;
        coarse.global_flat_reembedding = !o.no_global_reembedding;
        coarse.local_disc_every = kLocalDiscEvery;
        return rank_networks(shared, options, 1000, coarse, count);
      },
      [&](const SurfaceMap& map) {
        const std::optional<Sampled> sampled = sample(map);
        return sampled ? grid_score(*sampled) : -HUGE_VAL;
      });
  const auto& chosen = staged.setup;
  run.report()["partition"] = partition_report(chosen->network(), torus, chosen->pm());
  run.report()["partition"]["candidate_networks"] = n_candidates;
  Json& fj = run.report()["features"];
  fj["source"] = o.features.empty() ? "automatic" : "file";
  if (!o.features.empty()) {
    fj["file"] = o.features.path;
    const bool was_transposed = chosen->network().features != candidates.given_features;
    fj["transposed"] = was_transposed;
    if (was_transposed)
      run.note(o.features.path +
               ": using the feature grid transposed (rows as columns); as given " +
               (n_candidates == 1 ? "it cannot be traced"
                                  : "it gives a worse, twisted map (oriented against the domain)"));
  }

  // The map, from either core, validated, measured and sampled.
  tool::FinishedMap finished = tool::finish_map(run, staged, domain);
  const MetaMesh& meta = finished.meta;
  const MapMeasures& m = finished.measures;
  TorusRemeshResult result;
  Sampled sampled = sample_with(*finished.sampler);
  const UnfoldReport unfolded = sampled.unfolded;
  result.grid = std::move(sampled.grid);
  finished.sampler.reset();  // (its index is not needed from here on)
  const TorusGrid& grid = result.grid;
  const QuadMesh& quads = result.quads = torus_grid_mesh(grid);
  const TriangleMesh& triangles = result.triangles = torus_grid_triangles(grid);
  // glTF has no quads: a .glb grid is written as triangles.
  const bool triangulate = o.triangulate || std::filesystem::path(o.output).extension() == ".glb";

  run.stage("write");
  tool::write_meta_mesh_output(run, o.map, meta);
  tool::write_output(run, o.output, [&](const std::filesystem::path& p) {
    if (triangulate)
      io::write_mesh_file(triangles, p, o.mesh_file);
    else
      io::write_quad_mesh(quads, p);
  });
  tool::write_output(run, o.image,
                     [&](const std::filesystem::path& p) { write_torus_image(grid, p); });

  run.stage("measure");
  const SurfaceDistance distance = surface_distance(surface, triangles);
  const double grid_efficiency = torus_grid_efficiency(grid);
  const std::size_t flipped = unfolded.folds_after;
  Json& r = run.report();
  r["metric"] = "right-isosceles";
  r["map"] = finished.report;
  Json& gj = r["grid"];
  gj["columns"] = size.columns;
  gj["rows"] = size.rows;
  gj["efficiency"] = grid_efficiency;
  gj["flipped_triangles"] = flipped;
  gj["flipped_triangles_at_grid_points"] = unfolded.folds_before;
  gj["resampled_vertices"] = unfolded.moved_vertices;
  Json& sj = r["remesh"];
  sj["vertices"] = quads.n_vertices();
  sj["faces"] = triangulate ? triangles.n_faces() : quads.n_faces();
  sj["face_kind"] = triangulate ? "triangles" : "quads";
  r["distance"] = distance_report(distance);
  run.note((o.output.empty() ? input : o.output) + ": " + std::to_string(size.columns) + "x" +
           std::to_string(size.rows) + " torus grid, " + std::to_string(quads.n_faces()) +
           " quads; map efficiency " + fixed(m.forward_efficiency, 3) + " (symmetric " +
           fixed(m.symmetric_efficiency, 3) + "), grid efficiency " + fixed(grid_efficiency, 3) +
           ", " + std::to_string(flipped) + " flipped triangles, PSNR " +
           fixed(distance.psnr_db, 1) + " dB");
  return result;
}

}  // namespace ism::pipeline
