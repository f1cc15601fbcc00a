// The re-sampling loop shared by the remeshers' unfold steps (unfold.hpp).
#include "sample/unfold.hpp"

#include "metrics/metrics.hpp"

#include <algorithm>

namespace ism {

UnfoldReport unfold_samples(TriangleMesh& mesh,
                            const std::function<void(int v, std::vector<Vec3>& out)>& candidates,
                            const UnfoldOptions& options, std::vector<int>* chosen) {
  FoldTest test(mesh);
  UnfoldReport report;
  std::vector<std::size_t> scratch, around;
  // The folds among `faces`: their number, then (options.by_depth) their depth.
  struct Folds {
    std::size_t count = 0;
    double depth = 0;
    bool operator<(const Folds& o) const {
      return count < o.count || (count == o.count && depth < o.depth);
    }
  };
  auto count_folds = [&](const std::vector<std::size_t>& faces) {
    Folds c;
    for (std::size_t f : faces) {
      if (options.by_depth) {
        const double d = test.fold_depth(f, scratch);
        c.count += d > 0;
        c.depth += d;
      } else {
        c.count += test.folded(f, scratch);
      }
    }
    return c;
  };
  auto all_folded = [&] {
    std::vector<std::size_t> out;
    for (std::size_t f = 0; f < mesh.n_faces(); ++f)
      if (test.folded(f, scratch)) out.push_back(f);
    return out;
  };
  const std::vector<Vec3> given = mesh.positions;
  std::vector<std::size_t> folded = all_folded();
  report.folds_before = folded.size();
  std::vector<Vec3> tries;
  if (chosen) chosen->assign(mesh.n_vertices(), -1);
  for (int round = 0; round < options.max_rounds && !folded.empty(); ++round) {
    std::vector<int> vertices;
    for (std::size_t f : folded)
      for (int v : mesh.triangles[f]) vertices.push_back(v);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    bool kept = false;
    for (int v : vertices) {
      tries.clear();
      candidates(v, tries);
      test.influenced(v, around);
      Folds best = count_folds(around);
      const Vec3 original = mesh.positions[std::size_t(v)];
      Vec3 best_position = original;
      int best_index = -1;
      for (std::size_t k = 0; k < tries.size(); ++k) {
        const Vec3& p = tries[k];
        // Never onto a neighbour (two vertices moved towards each other by
        // half a step would meet): the mesh would weld there.
        bool on_neighbour = false;
        for (std::size_t f : test.faces_of(v))
          for (int w : mesh.triangles[f])
            on_neighbour |= w != v && mesh.positions[std::size_t(w)] == p;
        if (on_neighbour) continue;
        mesh.positions[std::size_t(v)] = p;
        test.update_around(v);
        const Folds c = count_folds(around);
        if (c < best) best = c, best_position = p, best_index = int(k);
      }
      mesh.positions[std::size_t(v)] = best_position;
      test.update_around(v);
      if (best_position != original) {
        kept = true;
        if (chosen) (*chosen)[std::size_t(v)] = best_index;
      }
    }
    if (!kept) break;
    folded = all_folded();
  }
  report.folds_after = folded.size();
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    report.moved_vertices += mesh.positions[v] != given[v];
  return report;
}

}  // namespace ism
