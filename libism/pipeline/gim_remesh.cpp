#include "pipeline/gim_remesh.hpp"

#include "pipeline/input_faces.hpp"

#include "domain/domain.hpp"
#include "io/image_io.hpp"
#include "io/io.hpp"
#include "map/map.hpp"
#include "mesh/boundary.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "refine/network_choice.hpp"
#include "report/report.hpp"
#include "sample/geometry_image_file.hpp"
#include "tool/limits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>

namespace ism::pipeline {
namespace {

// Area-weighted vertex normals of the map's surface.
std::vector<Vec3> vertex_normals(const std::vector<Triangle>& faces, const std::vector<Vec3>& p) {
  std::vector<Vec3> n(p.size(), Vec3::Zero());
  for (const Triangle& t : faces) {
    const Vec3 fn = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    for (int v : t) n[v] += fn;
  }
  for (Vec3& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

// The preview: the geometry image (positions normalised to the bounding box)
// beside the normal map shaded by a light, so both read at a glance.
std::vector<std::array<unsigned char, 3>> preview_pixels(const GeometryImage& image,
                                                         const std::vector<Vec3>& normals) {
  const int n = image.n;
  Vec3 lo = image.pixels.front(), hi = lo;
  for (const Vec3& p : image.pixels) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 extent = (hi - lo).cwiseMax(1e-300);
  std::vector<std::array<unsigned char, 3>> out(std::size_t(2 * n) * n);
  const Vec3 light = Vec3(0.3, 0.4, 1.0).normalized();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Vec3 c = (image.pixels[std::size_t(i) * n + j] - lo).cwiseQuotient(extent);
      auto& left = out[std::size_t(i) * 2 * n + j];
      for (int k = 0; k < 3; ++k) left[k] = static_cast<unsigned char>(std::lround(255 * c[k]));
      // Two antipodal lights, as the paper's figures: every side reads.
      const double shade = 0.15 + 0.85 * std::abs(normals[std::size_t(i) * n + j].dot(light));
      auto& right = out[std::size_t(i) * 2 * n + n + j];
      right.fill(static_cast<unsigned char>(std::lround(255 * shade)));
    }
  return out;
}

}  // namespace

GimRemeshResult gim_remesh(tool::Run& run, const GimRemeshOptions& o) {
  const std::string& input = o.input.path;
  if (!o.input.soup) run.add_input(input);
  if (!o.features.entries && !o.features.path.empty()) run.add_input(o.features.path);
  for (const std::string& out : {o.output, o.normals, o.mesh, o.preview, o.mask, o.dump_patches})
    if (!out.empty()) run.check_output(out);
  tool::check_geometry_image(run, o.size);
  for (const std::string& exr : {o.output, o.normals})
    tool::require_extension(run, exr == o.output ? "-o" : "--normals", exr, {".exr"}, "OpenEXR");
  tool::require_mesh_extension(run, "--mesh", o.mesh);
  tool::require_extension(run, "--preview", o.preview, {".png"}, "PNG");
  tool::require_extension(run, "--mask", o.mask, {".png"}, "PNG");
  tool::require_extension(run, "--dump-patches", o.dump_patches, {".ply"}, "PLY");
  if (o.metric != "right-isosceles" && o.metric != "equilateral")
    throw tool::Failure("gim-remesh: --metric must be right-isosceles or equilateral, got '" +
                        o.metric + "'");
  tool::check_settings("gim-remesh", o.map, o.mesh_file);

  const TriangleMesh surface =
      run.load_surface(o.input, {.tool = "gim-remesh",
                                 .genus = 0,
                                 .min_vertices = 6,
                                 .min_vertices_reason = "one per octahedron vertex"});

  // Holes are closed by caps the map treats as surface (paper §4: a fan
  // around each loop's centre, here cut by rings); the image samples the
  // closed surface and its alpha tells which samples fell on a cap.
  CappedMesh capped;
  try {
    capped = cap_boundary_loops(surface, boundary_loops(surface), o.cap);
  } catch (const std::invalid_argument& e) {
    throw tool::Failure(input + ": " + e.what());
  }
  const bool open = !capped.loops.empty();
  const TriangleMesh& closed = capped.mesh;

  run.stage("partition");
  std::vector<PathNetwork> networks;
  try {
    if (o.features.empty()) {
      networks =
          trace_octahedral_networks(closed, {.distinguish_poles = o.metric != "equilateral"});
    } else {
      const auto entries = o.features.read();
      const auto features = io::resolve_features(entries, surface, 0, o.features.path);
      networks.push_back(trace_path_network(closed, domain::octahedron(), features));
    }
  } catch (const PartitionError& e) {
    throw tool::Failure(input + ": " + e.what());
  } catch (const io::FileError& e) {
    throw o.features.entries ? tool::Failure(e.what()) : tool::reading_failure(o.features.path, e);
  }

  const TriangleMesh octahedron = domain::octahedron();
  const DomainMetric metric =
      o.metric == "equilateral" ? DomainMetric::equilateral : DomainMetric::right_isosceles;
  const DomainGeometry domain(octahedron, octahedron_lengths(octahedron, metric));
  const std::size_t candidates = networks.size();
  InputFaces input_faces;
  if (open)
    for (const PathNetwork& network : networks) input_faces.add(network, capped);
  tool::Progress& progress = run.stage("map");
  // Judged on the input surface: what the caps take does not count.
  const auto judge = [&](const SurfaceMap& m) {
    return m.measures(input_faces.of(m)).forward_efficiency;
  };
  // The same on the symmetric core, from the map's pieces.
  const auto judge_symmetric = [&](const InterSurfaceMap& m) {
    const MetaSide& s = m.meta().side[1];
    const auto pieces = meta_pieces(m.meta());
    return pieces ? measures(*pieces, input_faces.of(s.faces, s.positions)).forward_efficiency
                  : 0.0;
  };
  // Part-way refined (the variants' race), a face with a corner the caps
  // added is a cap's.
  const auto judge_level = [&](const InterSurfaceMap& m) {
    if (!open) return m.measures().forward_efficiency;
    const MetaSide& s = m.meta().side[1];
    const auto pieces = meta_pieces(m.meta());
    return pieces ? measures(*pieces, input_faces.of_any_level(s.faces, s.positions))
                        .forward_efficiency
                  : 0.0;
  };
  // Every variant ranks the same networks: their progressive meshes are
  // built once.
  NetworkCandidates shared(std::move(networks), domain, o.map.variants.size());
  // Ranked by the measure the final map is kept by (caps excluded).
  const tool::MapStageResult staged = tool::run_map_stage(
      run, progress,
      {.input = input,
       .dump_patches = o.dump_patches,
       .hint = "try --hold-features or other --features",
       .symmetric_score = open ? tool::SymmetricScore(judge_symmetric) : nullptr,
       .symmetric_level_score = judge_level},
      o.map,
      [&](const MapOptions& options, std::size_t count) {
        return rank_networks(shared, options, 1000, {}, count, [&](const SurfaceMap& m) {
          return m.measures(input_faces.of_any_level(m)).forward_efficiency;
        });
      },
      judge);
  // The map, from either core, validated, measured on the input and sampled.
  tool::FinishedMap finished = tool::finish_map(
      run, staged, domain, [&](const MetaSide& s) { return input_faces.of(s.faces, s.positions); });
  const MetaMesh& meta = finished.meta;
  const MapMeasures& m = finished.measures;
  const std::vector<char>& on_input = finished.counted;  // (empty on a closed surface)
  const std::vector<Triangle>& surface_faces = meta.side[1].faces;
  const std::vector<Vec3>& surface_positions = meta.side[1].positions;
  auto locate = [&](int f, const Eigen::Vector3d& b) {
    return finished.sampler->surface_point(f, b);
  };
  run.report()["partition"] =
      partition_report(staged.setup->network(), octahedron, staged.setup->pm());
  run.report()["partition"]["candidate_networks"] = candidates;

  const std::vector<Vec3> normals = vertex_normals(surface_faces, surface_positions);
  GimRemeshResult result;
  // Metric and layout agree: the right-isosceles octahedron is the square.
  auto position_at = [&](const OctahedronPoint& q) {
    const auto s = locate(q.face, q.bary);
    if (!s) throw std::runtime_error("a sample fell outside the map");
    return s->position;
  };
  result.image = sample_octahedral(o.size, position_at);
  // Folded grid triangles re-sampled nearby; the normals follow the samples.
  std::vector<OctahedronPoint> moved_to;
  UnfoldReport unfolded;
  if (o.unfold) {
    unfolded = unfold_geometry_image(result.image, position_at, &moved_to);
  } else {
    unfolded.folds_before = unfolded.folds_after = flipped_triangles(result.image);
  }
  if (open) {
    // The pixel's alpha: 1 on the input surface, 0 on a cap (mirrored
    // pixels are the same octahedron point, so they agree).
    const GeometryImage on = sample_octahedral(o.size, [&](const OctahedronPoint& q) {
      const auto s = locate(q.face, q.bary);
      return Vec3(on_input[s->face] ? 1.0 : 0.0, 0.0, 0.0);
    });
    result.image.alpha.resize(on.pixels.size());
    for (std::size_t p = 0; p < on.pixels.size(); ++p)
      result.image.alpha[p] = float(on.pixels[p].x());
  }
  auto normal_at = [&](const OctahedronPoint& q) {
    const auto s = locate(q.face, q.bary);
    if (!s) throw std::runtime_error("a sample fell outside the map");
    const Triangle& t = surface_faces[s->face];
    return Vec3(
        (s->bary[0] * normals[t[0]] + s->bary[1] * normals[t[1]] + s->bary[2] * normals[t[2]])
            .normalized());
  };
  result.normals = sample_octahedral(o.size, normal_at);
  for (std::size_t p = 0; p < moved_to.size(); ++p)
    if (moved_to[p].face >= 0) result.normals.pixels[p] = normal_at(moved_to[p]);
  const GeometryImage& image = result.image;
  finished.sampler.reset();  // (its index is not needed from here on)

  run.stage("write");
  tool::write_meta_mesh_output(run, o.map, meta);
  tool::write_output(run, o.output,
                     [&](const std::filesystem::path& p) { write_geometry_image(image, p); });
  tool::write_output(run, o.normals, [&](const std::filesystem::path& p) {
    write_geometry_image(result.normals, p);
  });
  result.remesh = image_to_surface_mesh(image);
  tool::write_output(run, o.mesh, [&](const std::filesystem::path& p) {
    io::write_mesh_file(result.remesh, p, o.mesh_file);
  });
  tool::write_output(run, o.preview, [&](const std::filesystem::path& p) {
    io::write_png_preview(p, 2 * o.size, o.size, preview_pixels(image, result.normals.pixels));
  });
  tool::write_output(run, o.mask, [&](const std::filesystem::path& p) {
    std::vector<unsigned char> mask(image.pixels.size(), 255);
    for (std::size_t i = 0; i < image.alpha.size(); ++i) mask[i] = image.alpha[i] > 0.5f ? 255 : 0;
    io::write_png_grey(p, o.size, o.size, mask);
  });

  run.stage("measure");
  const SurfaceDistance distance = surface_distance(surface, result.remesh);
  Json& r = run.report();
  r["size"] = o.size;
  r["metric"] = o.metric;
  r["map"] = finished.report;
  const double square_efficiency = image_efficiency(image, ImageDomain::square);
  Json& ij = r["image"];
  ij["efficiency_square"] = square_efficiency;
  ij["efficiency_octahedron"] = image_efficiency(image, ImageDomain::octahedron);
  ij["flipped_triangles"] = unfolded.folds_after;
  ij["flipped_triangles_at_grid_points"] = unfolded.folds_before;
  ij["resampled_vertices"] = unfolded.moved_vertices;
  ij["remesh_vertices"] = result.remesh.n_vertices();
  ij["remesh_faces"] = result.remesh.n_faces();
  r["distance"] = distance_report(distance);
  if (open) {
    // What the caps take: of the closed surface's area, and of the image.
    double cap_area = 0, total_area = 0;
    for (std::size_t f = 0; f < closed.n_faces(); ++f) {
      const double a = face_area(closed, f);
      total_area += a;
      if (capped.is_cap_face(f)) cap_area += a;
    }
    std::size_t cap_pixels = 0;
    for (float a : image.alpha) cap_pixels += a < 0.5f;
    Json& b = r["boundary"];
    b["loops"] = capped.loops.size();
    b["cap_rings"] = o.cap.rings;
    b["cap_height"] = o.cap.height;
    b["cap_area_fraction"] = cap_area / total_area;
    b["cap_pixel_fraction"] = double(cap_pixels) / double(image.alpha.size());
    try {
      b["remesh_loops"] = boundary_loops(result.remesh).size();
    } catch (const std::invalid_argument& e) {
      b["remesh_loops"] = Json();
      b["remesh_boundary_problem"] = e.what();
    }
  }
  run.note((o.output.empty() ? input : o.output) + ": " + std::to_string(o.size) + "x" +
           std::to_string(o.size) + " geometry image; map efficiency " +
           std::to_string(m.forward_efficiency) + " (symmetric " +
           std::to_string(m.symmetric_efficiency) + "), image efficiency " +
           std::to_string(square_efficiency) + ", PSNR " + std::to_string(distance.psnr_db) +
           " dB");
  return result;
}

}  // namespace ism::pipeline
