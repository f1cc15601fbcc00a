// The paper's Figure 9 claim, measured: a map between two surfaces built
// directly (both sides refined together, as ism-map) against the composition
// of two separate parametrizations over the same base domain (A over the
// base, B over the base, then A -> base -> B), both from the same compatible
// partition. Landmarks not used as features measure where each map sends
// them.
//   compose_bench A B --pairs PAIRS --landmarks LANDMARKS [--release-at F] [--threads N]
// PAIRS are the features (read_feature_pairs format); LANDMARKS further
// pairs, only measured. --release-at: the direct map holds its features
// until this fraction of the splits (default 0.5, as ism-map). The base
// domain's metric: each base face's edge lengths averaged over the two
// surfaces' base meshes, each scaled to unit area (neither surface's base
// favoured); the parametrizations keep the base vertices on the features
// (held throughout, as consistent parametrizations do) and, in a second
// row, release them half way as the direct map does.
// Prints a Markdown table: per map, landmark errors (distance from the image
// of a landmark to its partner, relative to the target's bounding-box
// diagonal) both ways, mean and largest, and the wall time.
#include "io/features.hpp"
#include "io/io.hpp"
#include "map/inter_surface_map.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/compatible_networks.hpp"
#include "pm/pm.hpp"
#include "refine/refine_surfaces.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace ism;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A location as a face and barycentric coordinates (a vertex: one of its faces).
MetaPoint as_point(const MetaSide& side, const MetaLocation& at) {
  if (at.vertex < 0) return {at.face, at.bary};
  for (std::size_t f = 0; f < side.faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (side.faces[f][std::size_t(k)] == at.vertex) {
        Eigen::Vector3d b = Eigen::Vector3d::Zero();
        b[k] = 1;
        return {int(f), b};
      }
  throw std::runtime_error("a vertex without a face");
}

struct Errors {
  double mean = 0, largest = 0;
  void add(double e, std::size_t n) {
    mean += e / double(n);
    largest = std::max(largest, e);
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::vector<std::string> files;
  std::string pairs_file, landmarks_file;
  double release_at = 0.5;
  int threads = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--pairs") == 0 && i + 1 < argc)
      pairs_file = argv[++i];
    else if (std::strcmp(argv[i], "--landmarks") == 0 && i + 1 < argc)
      landmarks_file = argv[++i];
    else if (std::strcmp(argv[i], "--release-at") == 0 && i + 1 < argc)
      release_at = std::atof(argv[++i]);
    else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      files.push_back(argv[i]);
  }
  if (files.size() != 2 || pairs_file.empty() || landmarks_file.empty()) {
    std::fprintf(stderr,
                 "usage: compose_bench A B --pairs PAIRS --landmarks LANDMARKS [--release-at F] "
                 "[--threads N]\n");
    return 2;
  }
  const std::array<TriangleMesh, 2> mesh{prepare_mesh(io::read_polygon_soup(files[0])).mesh,
                                         prepare_mesh(io::read_polygon_soup(files[1])).mesh};
  const auto pairs = io::read_feature_pairs(pairs_file, mesh[0], mesh[1]).pairs;
  const auto landmarks = io::read_feature_pairs(landmarks_file, mesh[0], mesh[1]).pairs;
  const std::array<double, 2> diagonal{bounding_box_diagonal(mesh[0]),
                                       bounding_box_diagonal(mesh[1])};

  auto start = Clock::now();
  const CompatibleNetworks networks = trace_compatible_networks(mesh[0], mesh[1], pairs);
  const std::array<ProgressiveMesh, 2> pms = simplify_compatible(networks);
  const double seconds_partition = since(start);
  std::printf("| map | landmark error A→B mean / max | B→A mean / max | seconds |\n");
  std::printf("|---|---|---|---|\n");
  std::printf("<!-- %s <-> %s: %zu features, %zu landmarks measured; partition %.1f s -->\n",
              files[0].c_str(), files[1].c_str(), pairs.size(), landmarks.size(),
              seconds_partition);

  // The direct map: both sides refined together.
  {
    start = Clock::now();
    InterSurfaceOptions options;
    options.hold_features = true;
    InterSurfaceMap map(side_from_pm(pms[0]), side_from_pm(pms[1]), options);
    SurfaceRefineOptions refine;
    refine.threads = threads;
    refine.release_features_at = release_at;
    refine_surfaces(map, refine);
    if (const auto problem = map.validate()) {
      std::fprintf(stderr, "compose_bench: the direct map does not validate: %s\n",
                   problem->c_str());
      return 1;
    }
    std::array<Errors, 2> e;
    for (const auto& l : landmarks)
      for (int s = 0; s < 2; ++s) {
        const MetaSide& from = map.meta().side[std::size_t(s)];
        const MetaSide& to = map.meta().side[std::size_t(1 - s)];
        const Vec3 image = point_at(to, from.location[std::size_t(l[std::size_t(s)])]);
        e[std::size_t(s)].add((image - to.positions[std::size_t(l[std::size_t(1 - s)])]).norm() /
                                  diagonal[std::size_t(1 - s)],
                              landmarks.size());
      }
    std::printf(
        "| direct (both refined, features released at %.2f), symmetric efficiency %.4f "
        "| %.4f / %.4f | %.4f / %.4f | %.0f |\n",
        release_at, map.measures().symmetric_efficiency, e[0].mean, e[0].largest, e[1].mean,
        e[1].largest, since(start));
  }

  // The base domain: the base faces (in base vertex numbers), each with its
  // edge lengths averaged over the two bases scaled to unit area.
  TriangleMesh domain;
  domain.positions.assign(pms[0].base_vertices.size(), Vec3::Zero());
  std::vector<FaceLengths> lengths(pms[0].base.triangles.size(), FaceLengths{0, 0, 0});
  for (int s = 0; s < 2; ++s) {
    const ProgressiveMesh& pm = pms[std::size_t(s)];
    std::vector<int> base_index(pm.base.n_vertices(), -1);
    for (std::size_t i = 0; i < pm.base_vertices.size(); ++i)
      base_index[std::size_t(pm.base_vertices[i])] = int(i);
    double area = 0;
    for (std::size_t f = 0; f < pm.base.triangles.size(); ++f) area += face_area(pm.base, f);
    for (std::size_t f = 0; f < pm.base.triangles.size(); ++f) {
      const Triangle& t = pm.base.triangles[f];
      const Triangle d{base_index[std::size_t(t[0])], base_index[std::size_t(t[1])],
                       base_index[std::size_t(t[2])]};
      if (s == 0)
        domain.triangles.push_back(d);
      else if (domain.triangles[f] != d) {
        std::fprintf(stderr, "compose_bench: the two base meshes' faces differ\n");
        return 1;
      }
      for (int k = 0; k < 3; ++k)
        lengths[f][std::size_t(k)] += 0.5 *
                                      (pm.base.positions[std::size_t(t[std::size_t((k + 1) % 3)])] -
                                       pm.base.positions[std::size_t(t[std::size_t(k)])])
                                          .norm() /
                                      std::sqrt(area);
    }
  }

  // The two parametrizations over it (domain side 0, surface side 1), and
  // their composition A -> base -> B (and back).
  for (const double release : {-1.0, release_at}) {
    start = Clock::now();
    std::array<std::unique_ptr<InterSurfaceMap>, 2> maps;
    for (int s = 0; s < 2; ++s) {
      InterSurfaceOptions options;
      options.hold_features = true;
      auto& map = maps[std::size_t(s)];
      map = std::make_unique<InterSurfaceMap>(side_from_domain(domain, lengths),
                                              side_from_pm(pms[std::size_t(s)]), options);
      SurfaceRefineOptions refine;
      refine.threads = threads;
      refine.release_features_at = release;
      refine_surfaces(*map, refine);
      if (const auto problem = map->validate()) {
        std::fprintf(stderr, "compose_bench: parametrization %d does not validate: %s\n", s,
                     problem->c_str());
        return 1;
      }
    }
    const MetaMeshSampler sampler0(maps[0]->meta()), sampler1(maps[1]->meta());
    const std::array<const MetaMeshSampler*, 2> sampler{&sampler0, &sampler1};
    std::array<Errors, 2> e;
    std::size_t lost = 0;
    for (const auto& l : landmarks)
      for (int s = 0; s < 2; ++s) {
        const MetaSide& from = maps[std::size_t(s)]->meta().side[1];
        const MetaPoint on_base = as_point(maps[std::size_t(s)]->meta().side[0],
                                           from.location[std::size_t(l[std::size_t(s)])]);
        const auto there = sampler[std::size_t(1 - s)]->map_point(0, on_base.face, on_base.bary);
        if (!there) {
          ++lost;
          continue;
        }
        const MetaSide& to = maps[std::size_t(1 - s)]->meta().side[1];
        const Vec3 image = point_at(to, {-1, there->face, there->bary});
        e[std::size_t(s)].add((image - to.positions[std::size_t(l[std::size_t(1 - s)])]).norm() /
                                  diagonal[std::size_t(1 - s)],
                              landmarks.size());
      }
    std::printf(
        "| composition over the base (features %s; each parametrization's symmetric "
        "efficiency %.4f, %.4f)%s "
        "| %.4f / %.4f | %.4f / %.4f | %.0f |\n",
        release < 0 ? "held" : "released half way", maps[0]->measures().symmetric_efficiency,
        maps[1]->measures().symmetric_efficiency, lost ? " (some landmarks not found)" : "",
        e[0].mean, e[0].largest, e[1].mean, e[1].largest, since(start));
  }
  return 0;
}
