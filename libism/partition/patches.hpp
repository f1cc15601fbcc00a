#pragma once
// Internal to partition: faces of a surface grouped into the regions that a
// set of cut edges separates, and the directed-edge lookup both the tracer
// and the validator use.
#include "mesh/edge_key.hpp"
#include "mesh/triangle_mesh.hpp"

#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace ism::partition_detail {

/// The face that holds each directed edge a -> b (counter-clockwise) of a
/// triangle mesh, looked up by its two vertices: per vertex its outgoing
/// edges sorted by head (built by counting, no hashing). Where a directed
/// edge is in several faces (a non-manifold input), the last face holds it.
class DirectedEdgeFaces {
 public:
  explicit DirectedEdgeFaces(const TriangleMesh& mesh);
  /// The face holding a -> b, or -1 where no face does.
  int operator()(int a, int b) const;
  /// Calls f(a, b, face) for every directed edge, by a then b.
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t a = 0; a + 1 < first_.size(); ++a)
      for (std::size_t i = first_[a]; i < first_[a + 1]; ++i)
        if (i + 1 == first_[a + 1] || out_[i + 1].first != out_[i].first)
          f(int(a), out_[i].first, out_[i].second);
  }

 private:
  std::vector<std::size_t> first_;        // per vertex, and one past the last
  std::vector<std::pair<int, int>> out_;  // (head, face), by tail then head then face
};

/// Region id of each face: faces joined across edges not in `cuts`
/// (undirected keys). Regions are numbered in order of their lowest face.
std::vector<int> regions(const TriangleMesh& mesh, const std::unordered_set<std::uint64_t>& cuts,
                         int* region_count);

}  // namespace ism::partition_detail
