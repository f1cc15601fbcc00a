#include "mesh/boundary.hpp"
#include "mesh/face_adjacency.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ism {
std::vector<std::vector<int>> boundary_loops(const TriangleMesh& mesh) {
  const auto across = faces_across(mesh.triangles);
  // Boundary half-edges a -> b: a face holds b -> a, nothing holds a -> b.
  std::unordered_map<int, int> next;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Triangle& t = mesh.triangles[f];
      const int a = t[(k + 1) % 3], b = t[k];
      if (across[f][std::size_t(k)].face >= 0) continue;
      if (!next.emplace(a, b).second)
        throw std::invalid_argument(
            "vertex " + std::to_string(a) +
            " is on the boundary twice (the boundary is not a set of loops)");
    }
  std::vector<int> starts;
  for (const auto& [a, b] : next) starts.push_back(a);
  std::sort(starts.begin(), starts.end());
  std::set<int> done;
  std::vector<std::vector<int>> loops;
  for (int start : starts) {
    if (done.count(start)) continue;
    std::vector<int> loop;
    int v = start;
    do {
      loop.push_back(v);
      done.insert(v);
      auto it = next.find(v);
      if (it == next.end() || loop.size() > next.size())
        throw std::invalid_argument("the boundary through vertex " + std::to_string(start) +
                                    " does not close into a loop");
      v = it->second;
    } while (v != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

double loop_length(const TriangleMesh& mesh, const std::vector<int>& loop) {
  double length = 0;
  for (std::size_t k = 0; k < loop.size(); ++k)
    length += (mesh.positions[loop[(k + 1) % loop.size()]] - mesh.positions[loop[k]]).norm();
  return length;
}

CappedMesh cap_boundary_loops(const TriangleMesh& mesh, std::vector<std::vector<int>> loops,
                              const CapOptions& options) {
  CappedMesh out;
  out.mesh = mesh;
  out.input_vertices = mesh.n_vertices();
  out.input_faces = mesh.n_faces();
  const auto& p = mesh.positions;
  std::vector<Vec3> up(loops.size(), Vec3::Zero());  // dome direction, scaled
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const auto& loop = loops[l];
    Vec3 centroid = Vec3::Zero();
    for (int v : loop) centroid += p[v];
    centroid /= double(std::max<std::size_t>(1, loop.size()));
    // The fan (loop[k], loop[k+1], centre) is oriented like the surface, so
    // its summed normal points out of the closed surface.
    Vec3 normal = Vec3::Zero();
    double radius = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      normal += (p[loop[k]] - centroid).cross(p[loop[(k + 1) % loop.size()]] - centroid);
      radius += (p[loop[k]] - centroid).norm() / double(loop.size());
    }
    if (normal.norm() > 0) up[l] = options.height * radius * normal.normalized();
    out.mesh.positions.push_back(centroid + up[l]);
  }
  const int rings = std::max(0, options.rings);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const auto& loop = loops[l];
    const std::size_t m = loop.size();
    // ring[r][k]: ring 0 is the loop, ring rings+1 the centre alone.
    std::vector<std::vector<int>> ring{loop};
    const Vec3 centre = out.mesh.positions[out.centre(l)] - up[l];
    for (int r = 1; r <= rings; ++r) {
      const double t = double(r) / double(rings + 1);
      // A quarter ellipse from the loop (t = 0) up to the top (t = 1).
      const double lift = std::sqrt(1.0 - (1.0 - t) * (1.0 - t));
      std::vector<int> next;
      for (int v : loop) {
        next.push_back(int(out.mesh.positions.size()));
        out.mesh.positions.push_back((1 - t) * p[v] + t * centre + lift * up[l]);
      }
      ring.push_back(std::move(next));
    }
    for (std::size_t r = 0; r + 1 < ring.size(); ++r)
      for (std::size_t k = 0; k < m; ++k) {
        const int a = ring[r][k], b = ring[r][(k + 1) % m];
        const int c = ring[r + 1][k], d = ring[r + 1][(k + 1) % m];
        out.mesh.triangles.push_back({a, b, d});
        out.mesh.triangles.push_back({a, d, c});
      }
    for (std::size_t k = 0; k < m; ++k)
      out.mesh.triangles.push_back({ring.back()[k], ring.back()[(k + 1) % m], out.centre(l)});
  }
  out.loops = std::move(loops);
  return out;
}

}  // namespace ism
