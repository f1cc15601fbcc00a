#pragma once
// Internal to partition: one surface on which a network of paths grows, for
// tracing compatible networks on two surfaces at once (compatible_networks.cpp).
//
// The surface is closed: each boundary loop of the input is capped by a fan
// around a new centre vertex (paper §4). Vertices are the input's, then one
// centre per loop, then Steiner vertices (edge midpoints) in order of
// creation. Paths run through free vertices of the input surface only: a
// path never passes a centre, and touches a loop's vertices only right next
// to that loop's centre (it enters the cap through one loop vertex), so that
// clipping the paths at the loops later leaves them disjoint.
#include "mesh/triangle_mesh.hpp"

#include "partition/region_count.hpp"
#include "partition/tracer_mesh.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_set>
#include <vector>

namespace ism::partition_detail {

enum class VertexClass : std::uint8_t { interior, boundary, centre };

/// Undirected edge keys (see patches.hpp) of the edges a closed curve crosses.
using EdgeSet = std::unordered_set<std::uint64_t>;

/// One end of a search: a feature vertex and the ring vertices through which
/// the path may leave (or enter) it, each with the sector it lies in.
struct SearchEnd {
  int vertex = -1;
  std::vector<int> ring;
  std::vector<int> sector;  // parallel to ring
};

/// Homology condition of a search: the path must cross `crossing` an odd
/// number of times when it enters the target through a sector flagged in
/// `odd`; through other sectors any path will do.
struct ParityRule {
  const EdgeSet* crossing = nullptr;
  std::vector<char> odd;  // per target sector
};

struct TracedPath {
  std::vector<int> vertices;  // source ... target
  std::vector<char> sheet;    // parity of the crossings so far, per vertex
  double length = 0;          // normalised (see NetworkSurface::scale)
  int leave_sector = -1, enter_sector = -1;
  bool simple = true;  // no vertex twice (always, unless repeats were allowed)
};

class NetworkSurface {
 public:
  /// `loops`: each boundary loop of `surface` as its vertices in the order of
  /// the boundary half-edges (the surface on the left). Throws PartitionError
  /// if the capped surface is not a closed manifold.
  NetworkSurface(const TriangleMesh& surface, const std::vector<std::vector<int>>& loops);

  std::size_t input_vertices() const { return input_vertices_; }
  std::size_t n_vertices() const { return mesh_.n_vertices(); }
  int centre(std::size_t loop) const { return int(input_vertices_ + loop); }
  VertexClass vertex_class(int v) const { return class_[v]; }
  const Vec3& position(int v) const { return positions_[v]; }
  /// 1 / sqrt(area of the input surface): lengths are measured in this unit,
  /// so that the lengths on two surfaces of different sizes add up fairly.
  double scale() const { return scale_; }

  bool on_network(int v) const { return on_network_[v] != 0; }
  bool is_network_edge(int a, int b) const;
  bool adjacent(int a, int b) const;
  /// Ring of v, counter-clockwise seen from outside.
  std::vector<int> ring(int v) const;
  /// Ring vertices strictly between `from` and `to` counter-clockwise; the
  /// whole ring without `from` when to == from; the whole ring when from < 0.
  std::vector<int> ring_between(int v, int from, int to) const;
  /// A free vertex through which a path may leave feature `feature`: the
  /// loop's vertices for a centre, interior vertices otherwise.
  bool may_leave_through(int feature, int w) const;

  void mark_feature(int v) { on_network_[v] = 1; }
  void unmark_feature(int v) { on_network_[v] = 0; }
  /// Puts a path's vertices and edges on the network (or takes them off,
  /// keeping its two ends, which are features).
  void add_path(const std::vector<int>& path);
  void remove_path(const std::vector<int>& path);
  /// Steiner vertices: splits every input edge off the network whose two
  /// ends are blocked for paths (on the network, or on a loop, unless the
  /// edge itself is a loop edge whose ends are free), so that every sector
  /// and every region keeps free vertices to trace through. Regions that
  /// take no more paths are left alone: those left of the directed edges
  /// `finished` (a, b). Returns the number of vertices added.
  std::size_t split_blocked_edges(const std::vector<std::array<int, 2>>& finished = {});

  /// Regions the network cuts the surface into (flood fill over faces).
  int count_regions() const;
  double length(const std::vector<int>& path) const;

  /// Shortest path (A*, normalised lengths) from `from` to `to` through free
  /// vertices, obeying the loop rules, a step onto a vertex next to the
  /// network counting twice its length (paths keep a vertex away from each
  /// other where they can, which spares Steiner vertices between them); with a parity rule, on the
  /// two-sheeted cover that counts crossings. Paths that visit a vertex twice (on both sheets) are
  /// refused unless `allow_repeats`. Nothing when none exists or none is shorter than `bound`.
  std::optional<TracedPath> shortest_path(const SearchEnd& from, const SearchEnd& to,
                                          const ParityRule* parity = nullptr,
                                          double bound = INFINITY, bool allow_repeats = false);

  /// Closed curves (as the edges each crosses) that span the first homology
  /// of the surface minus the network (tree-cotree on the complement): an
  /// arc between two sides of one region separates that region exactly when
  /// it crosses every curve an even number of times.
  std::vector<EdgeSet> complement_cycles() const;

  /// Which side of `path` each vertex of `vertices` lies on: +1 left, -1
  /// right, 0 when its shortest route (ignoring the network) meets the path
  /// at an end. One search from the path outwards.
  std::vector<int> sides_of(const std::vector<int>& path, const std::vector<int>& vertices);

  /// Positions and faces as they are now (Steiner vertices included).
  TriangleMesh triangle_mesh() const;

 private:
  using Mesh = TracerMesh;
  /// Fresh search marks for n vertices on two sheets.
  void next_search(std::size_t n);

  bool is_loop_edge(Mesh::EdgeHandle e) const;
  bool blocked(int v) const { return on_network_[v] || class_[v] != VertexClass::interior; }

  Mesh mesh_;
  std::vector<Vec3> positions_;
  std::vector<VertexClass> class_;
  std::vector<char> on_network_;
  std::vector<char> near_network_;  // a neighbour on the network (as of the last split)
  EdgeSet network_edges_;
  /// Per mesh edge, whether its key is in network_edges_ (the hot loops'
  /// test, without hashing; edges added by splits are off the network).
  std::vector<char> network_edge_;
  void flag_path(const std::vector<int>& path, char on);
  bool flagged(Mesh::EdgeHandle e) const {
    return std::size_t(e.idx()) < network_edge_.size() && network_edge_[std::size_t(e.idx())];
  }
  mutable RegionCount region_count_;  // remembers the regions between counts
  std::size_t input_vertices_ = 0;
  double scale_ = 1;
  // Search scratch, reused: two states (parity 0 and 1) per vertex.
  std::vector<double> distance_;
  std::vector<int> parent_;
  std::vector<unsigned> stamp_;
  unsigned search_ = 0;
};

}  // namespace ism::partition_detail
