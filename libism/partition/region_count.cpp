#include "partition/region_count.hpp"

#include <algorithm>
#include <utility>

namespace ism::partition_detail {

namespace {

// Calls f(edge index) for every edge between the two vertices of `key`.
template <class F>
void edges_of_key(const TracerMesh& mesh, std::uint64_t key, F&& f) {
  const int a = int(key >> 32), b = int(key & 0xffffffffu);
  if (a < 0 || a >= int(mesh.n_vertices())) return;
  for (auto h : mesh.voh_range(TracerMesh::VertexHandle(a)))
    if (mesh.to_vertex_handle(h).idx() == b) f(mesh.edge_handle(h).idx());
}

}  // namespace

int RegionCount::find(int g) {
  while (parent_[g] != g) g = parent_[g] = parent_[parent_[g]];
  return g;
}

int RegionCount::region(int f) {
  int l = label_[f];
  while (region_of_[l] != l) l = region_of_[l] = region_of_[region_of_[l]];
  return l;
}

int RegionCount::operator()(const TracerMesh& mesh, const std::unordered_set<std::uint64_t>& cuts) {
  const std::size_t old_faces = label_.size();
  bool recount = !known_;
  if (mesh.n_edges() < cut_.size() || mesh.n_faces() < old_faces) recount = true;  // not grown
  cut_.resize(mesh.n_edges(), 0);
  seen_.resize(mesh.n_edges(), 0);
  visit_stamp_.resize(mesh.n_faces(), 0);
  visit_.resize(mesh.n_faces(), 0);
  if (++stamp_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0);
    std::fill(visit_stamp_.begin(), visit_stamp_.end(), 0);
    stamp_ = 1;
  }
  // Faces split off since the last call join their regions, under the last
  // call's cuts (new edges uncut).
  if (!recount && mesh.n_faces() > old_faces) recount = !label_new_faces(mesh, old_faces);
  // The difference between the last call's cuts and these.
  thread_local std::vector<int> new_cuts, uncut;
  new_cuts.clear(), uncut.clear();
  for (const std::uint64_t key : cuts)
    edges_of_key(mesh, key, [&](int e) {
      seen_[e] = stamp_;
      if (!cut_[e]) {
        cut_[e] = 1;
        cut_edges_.push_back(e);
        new_cuts.push_back(e);
      }
    });
  std::size_t kept = 0;
  for (const int e : cut_edges_) {
    if (seen_[e] == stamp_) {
      cut_edges_[kept++] = e;
    } else {
      cut_[e] = 0;
      uncut.push_back(e);
    }
  }
  cut_edges_.resize(kept);
  known_ = true;
  if (recount) {
    count_all(mesh);
    return regions_;
  }
  for (const int e : uncut) join_across(mesh, e);
  if (!new_cuts.empty()) split_regions(mesh, new_cuts);
  return regions_;
}

void RegionCount::count_all(const TracerMesh& mesh) {
  label_.assign(mesh.n_faces(), -1);
  thread_local std::vector<int> stack;
  stack.clear();
  int count = 0;
  for (auto f0 : mesh.faces()) {
    if (label_[f0.idx()] >= 0) continue;
    label_[f0.idx()] = count;
    stack.push_back(f0.idx());
    while (!stack.empty()) {
      const auto f = TracerMesh::FaceHandle(stack.back());
      stack.pop_back();
      for (auto h : mesh.fh_range(f)) {
        if (cut_[mesh.edge_handle(h).idx()]) continue;
        const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
        if (g.is_valid() && label_[g.idx()] < 0) {
          label_[g.idx()] = count;
          stack.push_back(g.idx());
        }
      }
    }
    ++count;
  }
  regions_ = count;
  region_of_.resize(std::size_t(count));
  for (int l = 0; l < count; ++l) region_of_[std::size_t(l)] = l;
}

bool RegionCount::label_new_faces(const TracerMesh& mesh, std::size_t old_faces) {
  // A split leaves the old faces in place and adds faces joined to them
  // across new (uncut) edges: each new face takes the region it reaches
  // that way. Every new face's uncut neighbours must then agree, or a cut
  // edge was split and its halves join what it separated.
  const std::size_t n = mesh.n_faces();
  label_.resize(n, -1);
  bool labelled = true;
  while (labelled) {
    labelled = false;
    for (std::size_t f = old_faces; f < n; ++f) {
      if (label_[f] >= 0) continue;
      for (auto h : mesh.fh_range(TracerMesh::FaceHandle(int(f)))) {
        if (cut_[mesh.edge_handle(h).idx()]) continue;
        const auto g = mesh.opposite_face_handle(h);
        if (g.is_valid() && label_[g.idx()] >= 0) {
          label_[f] = label_[g.idx()];
          labelled = true;
          break;
        }
      }
    }
  }
  for (std::size_t f = old_faces; f < n; ++f) {
    if (label_[f] < 0) return false;
    for (auto h : mesh.fh_range(TracerMesh::FaceHandle(int(f)))) {
      if (cut_[mesh.edge_handle(h).idx()]) continue;
      const auto g = mesh.opposite_face_handle(h);
      if (g.is_valid() && region(g.idx()) != region(int(f))) return false;
    }
  }
  return true;
}

void RegionCount::join_across(const TracerMesh& mesh, int edge) {
  const auto e = TracerMesh::EdgeHandle(edge);
  const auto f = mesh.face_handle(mesh.halfedge_handle(e, 0));
  const auto g = mesh.face_handle(mesh.halfedge_handle(e, 1));
  if (!f.is_valid() || !g.is_valid()) return;
  const int a = region(f.idx()), b = region(g.idx());
  if (a == b) return;
  region_of_[std::size_t(std::max(a, b))] = std::min(a, b);
  --regions_;
}

void RegionCount::split_regions(const TracerMesh& mesh, const std::vector<int>& new_cuts) {
  // One breadth-first search from each face beside a new cut edge. A new
  // edge lies inside one region (its faces were joined across it), and
  // every part of a region it splits borders a new edge, so these searches
  // reach every face of the parts. Searches that meet are joined; one that
  // runs out of faces has closed a part, which takes a new label. A region
  // is done when at most one of its searches is open; the faces of that one
  // keep their labels.
  parent_.clear();
  std::size_t searches = 0;
  auto start = [&](int f) {
    if (visit_stamp_[f] == stamp_) return;
    visit_stamp_[f] = stamp_;
    visit_[f] = int(searches);
    parent_.push_back(int(searches));
    if (reached_.size() <= searches)
      reached_.emplace_back(), queue_.emplace_back(), head_.emplace_back();
    reached_[searches].assign(1, f);
    queue_[searches].assign(1, f);
    head_[searches] = 0;
    ++searches;
  };
  for (const int e : new_cuts) {
    const auto eh = TracerMesh::EdgeHandle(e);
    for (int side = 0; side < 2; ++side) {
      const auto f = mesh.face_handle(mesh.halfedge_handle(eh, side));
      if (f.is_valid()) start(f.idx());
    }
  }
  auto open = [&](int g) { return head_[g] < queue_[g].size(); };
  thread_local std::vector<std::pair<int, int>> by_region;  // (region, search)
  by_region.clear();
  for (std::size_t g = 0; g < searches; ++g) by_region.emplace_back(region(reached_[g][0]), int(g));
  std::sort(by_region.begin(), by_region.end());
  thread_local std::vector<int> live;
  for (std::size_t i = 0; i < by_region.size();) {
    std::size_t j = i;
    while (j < by_region.size() && by_region[j].first == by_region[i].first) ++j;
    live.clear();
    for (std::size_t k = i; k < j; ++k) live.push_back(by_region[k].second);
    int parts = 0;  // closed parts
    while (true) {
      // Drop joined and closed searches; stop when at most one is open.
      std::size_t n = 0;
      for (const int g : live) {
        if (find(g) != g) continue;
        if (!open(g)) {
          ++parts;
          const int fresh = int(region_of_.size());
          region_of_.push_back(fresh);
          for (const int f : reached_[g]) label_[f] = fresh;
          continue;
        }
        live[n++] = g;
      }
      live.resize(n);
      if (live.size() <= 1) break;
      // Each open search takes one face off its queue.
      for (const int g0 : live) {
        int g = find(g0);
        if (g != g0 || !open(g)) continue;
        const auto f = TracerMesh::FaceHandle(queue_[g][head_[g]++]);
        for (auto h : mesh.fh_range(f)) {
          if (cut_[mesh.edge_handle(h).idx()]) continue;
          const auto o = mesh.opposite_face_handle(h);
          if (!o.is_valid()) continue;
          const int of = o.idx();
          if (visit_stamp_[of] != stamp_) {
            visit_stamp_[of] = stamp_;
            visit_[of] = g;
            reached_[g].push_back(of);
            queue_[g].push_back(of);
            continue;
          }
          const int other = find(visit_[of]);
          if (other == g) continue;
          // Join the search with fewer faces into the other: its faces
          // and its still queued ones are appended.
          int big = g, small = other;
          if (reached_[big].size() < reached_[small].size()) std::swap(big, small);
          parent_[small] = big;
          reached_[big].insert(reached_[big].end(), reached_[small].begin(), reached_[small].end());
          queue_[big].insert(queue_[big].end(),
                             queue_[small].begin() + std::ptrdiff_t(head_[small]),
                             queue_[small].end());
          reached_[small].clear(), queue_[small].clear();
          head_[small] = 0;
          g = big;  // f's other neighbours join the search that lives on
        }
      }
    }
    regions_ += parts + int(live.size()) - 1;
    i = j;
  }
}

}  // namespace ism::partition_detail
