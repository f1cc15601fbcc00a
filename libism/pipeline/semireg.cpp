#include "pipeline/semireg.hpp"

#include "mesh/boundary.hpp"
#include "partition/bounded_base.hpp"
#include "pipeline/input_faces.hpp"

#include "io/io.hpp"
#include "map/map.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/network_choice.hpp"
#include "refine/refine.hpp"
#include "report/report.hpp"
#include "sample/semiregular.hpp"
#include "tool/limits.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

namespace ism::pipeline {
namespace {

// Genus of a connected manifold with b boundary loops: V - E + F = 2 - 2g - b.
int genus_of(const TriangleMesh& mesh) {
  return int((2 - euler_characteristic(mesh) - long(boundary_loops(mesh).size())) / 2);
}

std::string loops_word(std::size_t n) {
  return std::to_string(n) + (n == 1 ? " boundary loop" : " boundary loops");
}

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

// The user's base: checked, its vertices snapped to distinct surface vertices
// near them. Returns the base (on the surface) and the features.
std::pair<TriangleMesh, std::vector<int>> user_base(tool::Run& run, const SemiregOptions& o,
                                                    const TriangleMesh& surface,
                                                    const CappedMesh& capped) {
  const std::string& base_name = o.base.path;
  const std::string no_faces =
      base_name +
      ": the base has no faces; for base vertices alone (connectivity chosen by semireg) "
      "list them with --base-vertices FILE (vertex indices or X Y Z points, one per line)";
  if (o.base.soup) {
    if (o.base.soup->faces.empty()) throw tool::Failure(no_faces);
  } else {
    try {
      // The reader refuses a file without faces: say what that means here.
      if (io::read_polygon_soup(base_name).faces.empty()) throw tool::Failure(no_faces);
    } catch (const io::FileError& e) {
      const std::string what = e.what(), tail = "the file has no faces";
      if (what.size() >= tail.size() &&
          what.compare(what.size() - tail.size(), tail.size(), tail) == 0)
        throw tool::Failure(no_faces);
      throw tool::reading_failure(base_name, e);
    }
  }
  TriangleMesh base = run.load_surface(o.base, {.tool = "semireg (as a base mesh)"});
  run.stage("snap base");
  // An open surface wants a base with as many loops (each boundary vertex of
  // the base snaps onto the surface's boundary, each interior one inside).
  const std::vector<std::vector<int>> loops = boundary_loops(base);
  const std::size_t base_loops = loops.size();
  if (base_loops != capped.loops.size())
    throw tool::Failure(base_name + ": the base has " + loops_word(base_loops) + ", the surface " +
                        o.input.path + " has " + loops_word(capped.loops.size()));
  std::vector<char> surface_boundary(surface.n_vertices(), 0), base_boundary(base.n_vertices(), 0);
  for (const auto& loop : capped.loops)
    for (int v : loop) surface_boundary[v] = 1;
  for (const auto& loop : loops)
    for (int v : loop) base_boundary[v] = 1;
  const int surface_genus = genus_of(surface), base_genus = genus_of(base);
  if (base_genus != surface_genus)
    throw tool::Failure(base_name + ": genus " + std::to_string(base_genus) +
                        " base, the surface " + o.input.path + " has genus " +
                        std::to_string(surface_genus));
  const double diagonal = bounding_box_diagonal(surface);
  const double limit = 0.05 * diagonal;
  std::vector<int> features(base.n_vertices(), -1);
  std::vector<int> owner(surface.n_vertices(), -1);
  double worst = 0;
  for (std::size_t i = 0; i < base.n_vertices(); ++i) {
    const Vec3& p = base.positions[i];
    double best = INFINITY;
    int nearest = -1;
    for (std::size_t v = 0; v < surface.n_vertices(); ++v) {
      if (surface_boundary[v] != base_boundary[i]) continue;
      const double d = (surface.positions[v] - p).squaredNorm();
      if (d < best) best = d, nearest = int(v);
    }
    const double distance = std::sqrt(best);
    worst = std::max(worst, distance);
    if (distance > limit)
      throw tool::Failure(base_name + ": base vertex " + std::to_string(i) + " is " +
                          fixed(distance, 4) + " from the surface (limit " + fixed(limit, 4) +
                          ", 5% of the surface's bounding-box diagonal)");
    if (owner[nearest] >= 0)
      throw tool::Failure(base_name + ": base vertices " + std::to_string(owner[nearest]) +
                          " and " + std::to_string(i) + " both snap to surface vertex " +
                          std::to_string(nearest) + "; the base is too fine for the surface there");
    owner[nearest] = int(i);
    features[i] = nearest;
    base.positions[i] = surface.positions[nearest];
  }
  Json& bj = run.report()["base"];
  bj["source"] = "file";
  bj["file"] = base_name;
  bj["largest_snap_distance"] = worst;
  bj["largest_snap_distance_relative"] = diagonal > 0 ? worst / diagonal : 0.0;
  return {std::move(base), std::move(features)};
}

// On an open surface, no decimated base boundary edge spans more than this
// many boundary edges of the surface: bounded_base() fans the surface
// boundary vertices between its ends from an inner point, and long fans
// still crowd the paths (and squeeze the map) there. 8 kept 37 to 49 of
// venus_loop2's 50 base vertices on its loop; 16 maps every shared open
// model at base 50 and 100; 32 did as well at 100 but failed bunny_open at
// 50 (docs/results-open-surfaces.md).
constexpr std::size_t kMaxBoundarySpan = 16;

struct BaseCandidate {
  std::string name;
  TriangleMesh mesh;
  std::vector<int> features;  // base vertex i is surface vertex features[i]
};

// Bases of about o.base_size vertices decimated from the surface: the
// quadric error keeps the shape but leaves long triangles on flat parts;
// isotropic priorities give even, well-shaped faces, more or less bent
// towards valence 6. Each decimation's vertices also compete with the
// connectivity of their Voronoi regions (delaunay_base) where that is valid.
std::vector<BaseCandidate> decimated_bases(tool::Run& run, const SemiregOptions& o,
                                           const TriangleMesh& surface, const CappedMesh& capped) {
  const bool open = !capped.loops.empty();
  std::vector<int> centres;
  for (std::size_t j = 0; j < capped.loops.size(); ++j) centres.push_back(capped.centre(j));
  const std::pair<const char*, SimplifyOptions> priorities[] = {
      {"isotropic", {.priority = SimplifyPriority::isotropic}},
      {"isotropic, valence 0.01",
       {.priority = SimplifyPriority::isotropic, .valence_weight = 0.01}},
      {"isotropic, valence from curvature",
       {.priority = SimplifyPriority::isotropic,
        .valence_weight = 0.01,
        .valence_from_curvature = true}},
      {"quadric", {.priority = SimplifyPriority::quadric}},
  };
  tool::Progress& progress = run.stage("base");
  // The decimations (and their duals) are independent: built side by side,
  // then taken in order, so the candidates and the messages are the same as
  // one after the other. Only the first reports progress (Progress is not
  // shared between threads), counting the others as they finish.
  constexpr std::size_t n = std::size(priorities);
  struct Built {
    BaseCandidate base;
    std::optional<BaseCandidate> dual;
    std::exception_ptr error;
  };
  std::array<Built, n> built;
  std::atomic<int> finished = 0;
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const auto& [name, priority] = priorities[i];
    SimplifyOptions options = priority;
    if (i == 0)
      options.progress = [&](double f) { progress.update((finished.load() + f) / double(n)); };
    try {
      // An open surface is decimated capped, its loops kept as closed paths
      // and its centres kept; the caps are then dropped from the base.
      const ProgressiveMesh decimated =
          open ? simplify_capped_to(capped.mesh, capped.loops, centres,
                                    o.base_size + centres.size(), options, kMaxBoundarySpan)
               : simplify_to(surface, o.base_size, options);
      // The centres are the last base vertices (their indices follow the input's).
      auto [base, vertices] = open ? uncapped_base(decimated, centres.size())
                                   : UncappedBase{base_mesh(decimated), decimated.base_vertices};
      built[i].base = {name, std::move(base), vertices};
      // The same vertices with the intrinsic connectivity of their Voronoi
      // regions, when that is a valid base: often better shaped faces (the
      // Voronoi dual is built for closed surfaces).
      if (!open) try {
          TriangleMesh dual = delaunay_base(surface, vertices);
          built[i].dual = {std::string(name) + ", Voronoi dual", std::move(dual), vertices};
        } catch (const PartitionError&) {
          // Too sparse for a disc per region here: the decimation alone competes.
        }
    } catch (const std::runtime_error&) {
      built[i].error = std::current_exception();
    }
    ++finished;
  });
  std::vector<BaseCandidate> bases, dual_bases;
  for (Built& b : built) {
    if (b.error) try {
        std::rethrow_exception(b.error);
      } catch (const std::runtime_error& e) {
        throw tool::Failure(o.input.path + ": cannot decimate to a base mesh: " + e.what());
      }
    if (b.base.features.size() != o.base_size && bases.empty())
      run.note(o.input.path + ": the base has " + std::to_string(b.base.features.size()) +
               " vertices, not " + std::to_string(o.base_size) + " (no legal collapse left)");
    bases.push_back(std::move(b.base));
    if (b.dual) dual_bases.push_back(std::move(*b.dual));
  }
  for (BaseCandidate& dual : dual_bases) bases.push_back(std::move(dual));
  Json& bj = run.report()["base"];
  bj["source"] = "decimation";
  bj["requested_vertices"] = o.base_size;
  return bases;
}

// Base vertices without faces: the connectivity is the dual of their
// geodesic Voronoi regions on the surface (free connectivity).
BaseCandidate vertex_base(tool::Run& run, const SemiregOptions& o, const TriangleMesh& surface,
                          const CappedMesh& capped) {
  run.stage("base");
  const std::string& name = o.base_vertices.path;
  if (!capped.loops.empty())
    throw tool::Failure(o.input.path + ": " + loops_word(capped.loops.size()) +
                        "; --base-vertices needs a closed surface (give --base or --base-size)");
  std::vector<int> sites;
  try {
    const auto entries = o.base_vertices.read();
    sites = io::resolve_features(entries, surface, int(entries.size()), name);
  } catch (const io::FileError& e) {
    throw o.base_vertices.entries ? tool::Failure(e.what()) : tool::reading_failure(name, e);
  }
  if (sites.size() < 4)
    throw tool::Failure(name + ": " + std::to_string(sites.size()) +
                        " base vertices, a base needs at least 4");
  TriangleMesh base;
  try {
    base = delaunay_base(surface, sites);
  } catch (const PartitionError& e) {
    throw tool::Failure(name + ": " + e.what());
  }
  Json& bj = run.report()["base"];
  bj["source"] = "vertices";
  bj["file"] = name;
  bj["connectivity"] = "geodesic Voronoi dual";
  return {"vertices", std::move(base), std::move(sites)};
}

// The map keeps the surface's boundary on the base's only if the network's
// paths of the caps' edges are the surface's own cap edges; the tracer finds
// them as the shortest paths, this checks that it did.
void check_boundary_paths(const PathNetwork& network, const BoundedBase& bounded) {
  std::set<std::pair<int, int>> cap_edges;
  for (std::size_t f = 0; f < bounded.domain.n_faces(); ++f)
    if (bounded.cap_face[f]) {
      const Triangle& t = bounded.domain.triangles[f];
      for (int k = 0; k < 3; ++k)
        cap_edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
    }
  for (std::size_t e = 0; e < network.domain_edges.size(); ++e) {
    const auto [a, b] = network.domain_edges[e];
    if (cap_edges.count({a, b}) && network.paths[e].size() != 2)
      throw PartitionError("the path along the boundary between surface vertices " +
                           std::to_string(bounded.features[a]) + " and " +
                           std::to_string(bounded.features[b]) + " is not the boundary edge");
  }
}

}  // namespace

SemiregResult semireg(tool::Run& run, const SemiregOptions& o) {
  const std::string& input = o.input.path;
  if (!o.input.soup) run.add_input(input);
  if (!o.base.empty() && !o.base.soup) run.add_input(o.base.path);
  if (!o.base_vertices.empty() && !o.base_vertices.entries) run.add_input(o.base_vertices.path);
  for (const std::string& out : {o.output, o.write_base, o.dump_patches})
    if (!out.empty()) run.check_output(out);
  if (int(!o.base.empty()) + int(!o.base_vertices.empty()) + int(o.base_size != 0) != 1)
    throw tool::Failure(
        "semireg: give exactly one of --base BASE, --base-vertices FILE and --base-size N");
  if (o.levels < 0 || o.levels > 8)
    throw tool::Failure("semireg: --levels must be 0..8, got " + std::to_string(o.levels));
  if (o.base_size != 0 && (o.base_size < 4 || o.base_size > (std::size_t(1) << 24)))
    throw tool::Failure("semireg: --base-size must be 4.." + std::to_string(1 << 24) + ", got " +
                        std::to_string(o.base_size));
  tool::check_settings("semireg", o.map, o.mesh_file);
  tool::require_mesh_extension(run, "-o", o.output);
  tool::require_mesh_extension(run, "--write-base", o.write_base);
  tool::require_extension(run, "--dump-patches", o.dump_patches, {".ply"}, "PLY");
  if (o.base_size) {
    if (!o.input.soup) tool::check_base_size(run, o.base_size, input);
    tool::check_semiregular(run, 2 * o.base_size, o.levels,
                            "--base-size " + std::to_string(o.base_size));
  }

  const TriangleMesh surface = run.load_surface(o.input, {.tool = "semireg"});
  // An open surface is mapped closed: each loop capped by a fan (paper §4),
  // and the base's loops by fans over points at the surface's boundary
  // vertices (bounded_base), so that the boundary maps onto the base's.
  CappedMesh capped;
  try {
    capped = cap_boundary_loops(surface, boundary_loops(surface));
  } catch (const std::invalid_argument& e) {
    throw tool::Failure(input + ": " + e.what());
  }
  const bool open = !capped.loops.empty();
  if (open && o.map.core == tool::MapCore::symmetric)
    throw tool::Failure("semireg: " + input + " has " + loops_word(capped.loops.size()) +
                        "; --core symmetric maps closed surfaces only (the default core maps "
                        "open ones)");
  if (o.base_size) tool::check_base_size(run, o.base_size, surface.n_vertices(), input);

  // Candidate bases: the user's, or decimations with different priorities
  // (which one suits a surface best is not predictable: each is mapped to a
  // coarse level and the lowest energy wins).
  std::vector<BaseCandidate> bases;
  if (!o.base.empty()) {
    auto [base, features] = user_base(run, o, surface, capped);
    bases.push_back({"file", std::move(base), std::move(features)});
  } else if (!o.base_vertices.empty()) {
    bases.push_back(vertex_base(run, o, surface, capped));
  } else {
    bases = decimated_bases(run, o, surface, capped);
  }

  tool::check_semiregular(run, bases.front().mesh.n_faces(), o.levels, "the base");
  // Each base traced on its own core; progress follows the first.
  tool::Progress& partition_progress = run.stage("partition");
  std::vector<std::optional<PathNetwork>> networks(bases.size());
  std::vector<std::optional<BoundedBase>> bounded(bases.size());
  std::vector<std::string> errors(bases.size());
  tbb::parallel_for(std::size_t(0), bases.size(), [&](std::size_t i) {
    PartitionOptions options;
    if (i == 0) options.progress = [&](double f) { partition_progress.update(f); };
    try {
      if (open) {
        BoundedBase bb = bounded_base(bases[i].mesh, bases[i].features, capped);
        options.direct_edges = bb.cap_edges();
        PathNetwork network = trace_path_network(capped.mesh, bb.domain, bb.features, options);
        check_boundary_paths(network, bb);
        bounded[i] = std::move(bb);
        networks[i] = std::move(network);
      } else {
        networks[i] = trace_path_network(surface, bases[i].mesh, bases[i].features, options);
      }
    } catch (const PartitionError& e) {
      errors[i] = e.what();
    }
  });
  std::vector<std::size_t> candidate_base;  // the base of each candidate
  std::string first_error;
  for (std::size_t i = 0; i < bases.size(); ++i) {
    if (networks[i])
      candidate_base.push_back(i);
    else if (first_error.empty())
      first_error = errors[i];
  }
  if (candidate_base.empty()) throw tool::Failure(input + ": " + first_error);

  InputFaces input_faces;
  if (open)
    for (std::size_t i : candidate_base) input_faces.add(*networks[i], capped);
  // An open surface's decimated bases rank differently at the coarse level
  // than at full resolution (bunny_open, head_3holes: neither the coarse
  // energy nor the coarse efficiency picked the best every time), so the
  // two best are refined side by side, each on its own core, and the final
  // score keeps one.
  tool::MapSettings settings = o.map;
  if (open && settings.contenders == 0) settings.contenders = 2;
  // The remesh a map gives over base i (on an open surface: the base face's
  // pieces of its closed domain), the map's surface point of a domain point
  // from `locate`.
  using Locate = std::function<std::optional<SurfacePoint>(int, const Eigen::Vector3d&)>;
  auto sample_remesh = [&](const Locate& locate, std::size_t i) {
    const auto point = [&](int f, const Eigen::Vector3d& bary) {
      const auto [face, at] =
          open ? bounded[i]->locate(f, bary) : std::pair<int, Eigen::Vector3d>{f, bary};
      const auto s = locate(face, at);
      if (!s) throw std::runtime_error("a sample fell outside the map");
      return s->position;
    };
    std::pair<TriangleMesh, UnfoldReport> out{semiregular_mesh(bases[i].mesh, o.levels, point),
                                              UnfoldReport{}};
    if (o.unfold)
      out.second = unfold_semiregular(bases[i].mesh, o.levels, point, out.first);
    else
      out.second.folds_before = out.second.folds_after = flipped_faces(out.first);
    return out;
  };
  // Which base each candidate's domain is (for the score).
  std::mutex domains_mutex;
  std::map<const DomainGeometry*, std::size_t> base_of_domain;
  tool::Progress& progress = run.stage("map");
  const tool::MapStageResult staged = tool::run_map_stage(
      run, progress,
      {.input = input,
       .dump_patches = o.dump_patches,
       .hint = "try --hold-features or another base",
       // (Contenders on the symmetric core race by the measure they are kept by.)
       .symmetric_level_score =
           [](const InterSurfaceMap& m) { return m.measures().forward_efficiency; }},
      settings,
      [&](const MapOptions& options, std::size_t count) {
        std::vector<DomainCandidate> candidates;
        for (std::size_t i : candidate_base) {
          if (!open) {
            candidates.push_back({std::make_unique<DomainGeometry>(
                                      bases[i].mesh, equilateral_lengths(bases[i].mesh)),
                                  *networks[i]});
            continue;
          }
          auto domain = std::make_unique<DomainGeometry>(bounded[i]->domain, bounded[i]->lengths);
          domain->set_fixed(bounded[i]->fixed);
          {
            const std::lock_guard<std::mutex> lock(domains_mutex);
            base_of_domain[domain.get()] = i;
          }
          candidates.push_back({std::move(domain), *networks[i]});
        }
        // An open surface's bases are ranked as the final map is judged
        // (the one-way efficiency domain -> surface): their symmetric
        // energies at the coarse level, dominated by the surface -> domain
        // term and the caps, ranked bunny_open's worst base first at base
        // 100 (docs/results-open-surfaces.md).
        if (open)
          return rank_domains(
              std::move(candidates), options, 5000,
              [](const SurfaceMap& m) { return m.measures().forward_efficiency; }, count);
        return rank_domains(std::move(candidates), options, 5000, {}, count);
      },
      // Judged on the input surface: what the caps take does not count. On
      // an open surface each folded remesh triangle costs a whole unit of
      // efficiency (as torus-remesh's grid folds do): bunny_open's more
      // efficient base 50 folded 54 triangles, the other 4.
      [&](const SurfaceMap& m) {
        const double efficiency = m.measures(input_faces.of(m)).forward_efficiency;
        if (!open) return efficiency;
        std::size_t i;
        {
          const std::lock_guard<std::mutex> lock(domains_mutex);
          i = base_of_domain.at(&m.domain());
        }
        const std::optional<MetaMesh> meta = meta_mesh(m);
        if (!meta) return -HUGE_VAL;  // (the epilogue says why, if it is kept)
        const DomainSurfaceSampler sampler(*meta, m.domain());
        const Locate locate = [&](int f, const Eigen::Vector3d& b) {
          return sampler.surface_point(f, b);
        };
        return efficiency - double(sample_remesh(locate, i).second.folds_after);
      });
  const auto& chosen = staged.setup;
  const BaseCandidate& chosen_base = bases[candidate_base[chosen->candidate]];
  const std::optional<BoundedBase>& chosen_bounded = bounded[candidate_base[chosen->candidate]];
  const TriangleMesh& base = chosen_base.mesh;
  {
    Json& bj = run.report()["base"];
    bj["vertices"] = base.n_vertices();
    bj["faces"] = base.n_faces();
    bj["candidates"] = bases.size();
    bj["chosen"] = chosen_base.name;
  }
  run.report()["partition"] =
      partition_report(chosen->network(), open ? chosen_bounded->domain : base, chosen->pm());

  // The map, from either core, validated, measured on the input and sampled.
  tool::FinishedMap finished =
      tool::finish_map(run, staged, chosen->map->domain(),
                       [&](const MetaSide& s) { return input_faces.of(s.faces, s.positions); });
  const MetaMesh& meta = finished.meta;
  const MapMeasures& m = finished.measures;
  const Locate locate = [&](int f, const Eigen::Vector3d& b) {
    return finished.sampler->surface_point(f, b);
  };

  SemiregResult result;
  TriangleMesh& remesh = result.remesh;
  UnfoldReport unfolded;
  std::tie(remesh, unfolded) = sample_remesh(locate, candidate_base[chosen->candidate]);
  finished.sampler.reset();  // (its index is not needed from here on)
  // The base actually used: its vertices where the remesh has them (the
  // map's images of the base vertices, unless a fold re-sampled one).
  TriangleMesh& used_base = result.base;
  used_base = base;
  for (std::size_t v = 0; v < used_base.n_vertices(); ++v)
    used_base.positions[v] = remesh.positions[v];

  run.stage("write");
  tool::write_meta_mesh_output(run, o.map, meta);
  tool::write_output(run, o.output, [&](const std::filesystem::path& p) {
    io::write_mesh_file(remesh, p, o.mesh_file);
  });
  tool::write_output(run, o.write_base, [&](const std::filesystem::path& p) {
    io::write_mesh_file(used_base, p, o.mesh_file);
  });

  run.stage("measure");
  const SurfaceDistance distance = surface_distance(surface, remesh);
  Json& r = run.report();
  r["levels"] = o.levels;
  r["metric"] = "equilateral";
  r["map"] = finished.report;
  Json& sj = r["remesh"];
  sj["vertices"] = remesh.n_vertices();
  sj["faces"] = remesh.n_faces();
  const std::size_t flipped = unfolded.folds_after;
  sj["flipped_triangles"] = flipped;
  // Before the folds were re-sampled, and how many vertices that moved.
  sj["flipped_triangles_at_grid_points"] = unfolded.folds_before;
  sj["resampled_vertices"] = unfolded.moved_vertices;
  // The same measure on the input: folds the remesh inherits from creases.
  sj["input_flipped_triangles"] = flipped_faces(surface);
  r["distance"] = distance_report(distance);
  if (open) {
    Json& b = r["boundary"];
    b["loops"] = capped.loops.size();
    b["base_boundary_points"] = chosen_bounded->boundary_points;
    b["base_inner_points"] = chosen_bounded->inner_points;
    double cap_area = 0, total_area = 0;
    for (std::size_t f = 0; f < capped.mesh.n_faces(); ++f) {
      const Triangle& t = capped.mesh.triangles[f];
      const double a = 0.5 * (capped.mesh.positions[t[1]] - capped.mesh.positions[t[0]])
                                 .cross(capped.mesh.positions[t[2]] - capped.mesh.positions[t[0]])
                                 .norm();
      total_area += a;
      if (capped.is_cap_face(f)) cap_area += a;
    }
    b["cap_area_fraction"] = total_area > 0 ? cap_area / total_area : 0.0;
    b["remesh_loops"] = boundary_loops(remesh).size();
  }
  run.note((o.output.empty() ? input : o.output) + ": " + std::to_string(remesh.n_faces()) +
           " faces (" + std::to_string(base.n_faces()) + " base faces, level " +
           std::to_string(o.levels) + "); map efficiency " + fixed(m.forward_efficiency, 3) +
           " (symmetric " + fixed(m.symmetric_efficiency, 3) + "), " + std::to_string(flipped) +
           " flipped triangles, PSNR " + fixed(distance.psnr_db, 1) + " dB");
  return result;
}

}  // namespace ism::pipeline
