// RegionCount, which the path tracers call after every path they lay, gives
// the same count as a flood fill over the whole mesh through any sequence of
// paths laid, paths taken back and edges split, on surfaces of genus 0 and 1.
#include "partition/region_count.hpp"
#include "partition/patches.hpp"
#include "shapes/shapes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <unordered_set>
#include <vector>

namespace ism::partition_detail {
namespace {

using Cuts = std::unordered_set<std::uint64_t>;

TracerMesh tracer_mesh(const TriangleMesh& surface) {
  TracerMesh mesh;
  for (const Vec3& p : surface.positions) mesh.add_vertex({p.x(), p.y(), p.z()});
  for (const Triangle& t : surface.triangles)
    mesh.add_face(TracerMesh::VertexHandle(t[0]), TracerMesh::VertexHandle(t[1]),
                  TracerMesh::VertexHandle(t[2]));
  return mesh;
}

// The reference: a flood fill over faces, each half-edge looked up by its key.
int flood_regions(const TracerMesh& mesh, const Cuts& cuts) {
  std::vector<int> region(mesh.n_faces(), -1);
  int count = 0;
  for (auto f0 : mesh.faces()) {
    if (region[f0.idx()] >= 0) continue;
    std::vector<TracerMesh::FaceHandle> stack{f0};
    region[f0.idx()] = count;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (auto h : mesh.fh_range(f)) {
        if (cuts.count(undirected_edge_key(mesh.from_vertex_handle(h).idx(),
                                           mesh.to_vertex_handle(h).idx())))
          continue;
        const auto g = mesh.opposite_face_handle(h);
        if (g.is_valid() && region[g.idx()] < 0) {
          region[g.idx()] = count;
          stack.push_back(g);
        }
      }
    }
    ++count;
  }
  return count;
}

// A random walk of up to `length` edges from a random vertex, as keys.
std::vector<std::uint64_t> random_path(const TracerMesh& mesh, std::mt19937& rng, int length) {
  auto v = TracerMesh::VertexHandle(int(rng() % mesh.n_vertices()));
  std::vector<std::uint64_t> path;
  for (int k = 0; k < length; ++k) {
    std::vector<TracerMesh::VertexHandle> next;
    for (auto w : mesh.vv_range(v)) next.push_back(w);
    const auto w = next[rng() % next.size()];
    path.push_back(undirected_edge_key(v.idx(), w.idx()));
    v = w;
  }
  return path;
}

void run_sequence(const TriangleMesh& surface, std::uint32_t seed, int* splits_seen,
                  int* cut_splits, int* max_regions) {
  TracerMesh mesh = tracer_mesh(surface);
  std::mt19937 rng(seed);
  RegionCount count;
  Cuts cuts;
  std::vector<std::vector<std::uint64_t>> paths;
  for (int step = 0; step < 160; ++step) {
    const unsigned what = rng() % 10;
    if (what < 7 || paths.empty()) {  // lay a path
      paths.push_back(random_path(mesh, rng, 1 + int(rng() % 40)));
      cuts.insert(paths.back().begin(), paths.back().end());
    } else if (what < 9) {  // take a path back
      const std::size_t k = rng() % paths.size();
      for (const auto key : paths[k]) cuts.erase(key);
      paths.erase(paths.begin() + std::ptrdiff_t(k));
      for (const auto& p : paths) cuts.insert(p.begin(), p.end());
    } else {
      // Split an edge. A cut edge's key then names no edge; half of the
      // time its halves are cut instead (the new faces beside them must not
      // join the regions the edge kept apart).
      const auto e = TracerMesh::EdgeHandle(int(rng() % mesh.n_edges()));
      const auto h = mesh.halfedge_handle(e, 0);
      const int a = mesh.from_vertex_handle(h).idx(), b = mesh.to_vertex_handle(h).idx();
      const auto m = mesh.add_vertex(
          (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h))) * 0.5);
      mesh.split_copy(e, m);
      ++*splits_seen;
      if (cuts.count(undirected_edge_key(a, b)) && rng() % 2) {
        for (auto& p : paths)
          if (std::find(p.begin(), p.end(), undirected_edge_key(a, b)) != p.end()) {
            p.push_back(undirected_edge_key(a, m.idx()));
            p.push_back(undirected_edge_key(m.idx(), b));
          }
        cuts.insert(undirected_edge_key(a, m.idx()));
        cuts.insert(undirected_edge_key(m.idx(), b));
        ++*cut_splits;
      }
    }
    const int expected = flood_regions(mesh, cuts);
    ASSERT_EQ(count(mesh, cuts), expected) << "seed " << seed << ", step " << step;
    *max_regions = std::max(*max_regions, expected);
    // Asking again with nothing changed gives the same answer.
    if (step % 17 == 0) ASSERT_EQ(count(mesh, cuts), expected);
  }
}

TEST(RegionCount, AgreesWithAFloodFillThroughPathsUndoneAndSplits) {
  int splits = 0, cut_splits = 0, most = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    run_sequence(shapes::blob(1500, seed, 0.3), seed, &splits, &cut_splits, &most);
    run_sequence(shapes::torus(1500, 2.0, 0.7), 100 + seed, &splits, &cut_splits, &most);
  }
  // The sequences did what they are for: splits happened and paths cut the
  // surfaces into many regions.
  EXPECT_GT(splits, 40);
  EXPECT_GT(cut_splits, 3);
  EXPECT_GT(most, 30);
}

TEST(RegionCount, CountsPartsClosedOffFromBothSidesOfAPath) {
  // A closed loop of edges around one vertex cuts its fan off; laying the
  // loop edge by edge only splits at the last edge.
  TracerMesh mesh = tracer_mesh(shapes::sphere(800));
  RegionCount count;
  Cuts cuts;
  const auto v = TracerMesh::VertexHandle(0);
  std::vector<int> ring;
  for (auto w : mesh.vv_range(v)) ring.push_back(w.idx());
  for (std::size_t k = 0; k < ring.size(); ++k) {
    cuts.insert(undirected_edge_key(ring[k], ring[(k + 1) % ring.size()]));
    EXPECT_EQ(count(mesh, cuts), k + 1 < ring.size() ? 1 : 2);
  }
  // Every spoke cut too: the fan falls apart into its triangles.
  for (int w : ring) cuts.insert(undirected_edge_key(v.idx(), w));
  EXPECT_EQ(count(mesh, cuts), int(ring.size()) + 1);
  EXPECT_EQ(count(mesh, cuts), flood_regions(mesh, cuts));
}

}  // namespace
}  // namespace ism::partition_detail
