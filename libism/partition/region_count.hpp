#pragma once
// Internal to partition: how many regions a growing path network cuts a
// tracer mesh into, kept up to date as paths are laid and taken back.
#include "partition/tracer_mesh.hpp"

#include <cstdint>
#include <unordered_set>
#include <vector>

namespace ism::partition_detail {

/// Counts the regions the edges `cuts` (undirected vertex keys; a key names
/// every edge between its two vertices) cut `mesh` into: faces joined across
/// every other edge. Exact, as a flood fill over the whole mesh would count.
///
/// It remembers the last call's regions and works on the difference: edges
/// no longer cut join the regions on their two sides; new cut edges are
/// searched from both their sides at once, breadth first, and a region's
/// search stops as soon as all but one of its parts are closed (cost about
/// the smaller parts' size, not the mesh's). Between calls the mesh may only
/// grow by edge splits (TracerMesh keeps every handle); new faces take the
/// region of the faces they were split from, and where that is ambiguous (a
/// cut edge was split) everything is counted again.
class RegionCount {
 public:
  int operator()(const TracerMesh& mesh, const std::unordered_set<std::uint64_t>& cuts);

 private:
  void count_all(const TracerMesh& mesh);
  bool label_new_faces(const TracerMesh& mesh, std::size_t old_faces);
  void join_across(const TracerMesh& mesh, int edge);
  void split_regions(const TracerMesh& mesh, const std::vector<int>& new_cuts);
  int region(int f);
  int find(int g);

  bool known_ = false;
  int regions_ = 0;
  std::vector<char> cut_;            // per edge
  std::vector<int> cut_edges_;       // the edges flagged in cut_
  std::vector<std::uint32_t> seen_;  // per edge: the call that named it
  std::vector<int> label_;           // per face; its region is region_of_[label]'s root
  std::vector<int> region_of_;       // union-find over labels (regions joined)
  std::vector<std::uint32_t> visit_stamp_;
  std::vector<int> visit_;  // per face: the search that reached it
  std::uint32_t stamp_ = 0;
  // Searches of one call: union-find parents, faces reached, faces queued
  // (the first head_ of them expanded).
  std::vector<int> parent_;
  std::vector<std::vector<int>> reached_, queue_;
  std::vector<std::size_t> head_;
};

}  // namespace ism::partition_detail
