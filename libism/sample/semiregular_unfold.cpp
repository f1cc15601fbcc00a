// Folded triangles of a semi-regular remesh re-sampled at nearby points of
// their base face or edge (unfold_semiregular(), semiregular.hpp).
#include "metrics/metrics.hpp"
#include "sample/semiregular.hpp"

#include <algorithm>
#include <exception>
#include <span>
#include <stdexcept>

namespace ism {

namespace {

// Faces around each vertex (compressed rows) and the fold test of
// flipped_faces() on the current positions, evaluated face by face.
class FoldTest {
 public:
  explicit FoldTest(const TriangleMesh& mesh) : mesh_(mesh) {
    const std::size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
    start_.assign(nv + 1, 0);
    for (const Triangle& t : mesh.triangles)
      for (int v : t) ++start_[std::size_t(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) start_[v + 1] += start_[v];
    faces_.resize(start_[nv]);
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (int v : mesh.triangles[f]) faces_[fill[std::size_t(v)]++] = f;
    normal_.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) normal_[f] = face_normal_scaled(mesh, f);
  }

  std::span<const std::size_t> faces_of(int v) const {
    return {faces_.data() + start_[std::size_t(v)], faces_.data() + start_[std::size_t(v) + 1]};
  }

  // Faces sharing a vertex with f (f included), sorted.
  void ring(std::size_t f, std::vector<std::size_t>& out) const {
    out.clear();
    for (int v : mesh_.triangles[f]) {
      const auto around = faces_of(v);
      out.insert(out.end(), around.begin(), around.end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  bool folded(std::size_t f, std::vector<std::size_t>& scratch) const {
    ring(f, scratch);
    Vec3 sum = Vec3::Zero();
    for (std::size_t g : scratch) sum += normal_[g];
    return normal_[f].dot(sum) < 0.0;
  }

  // The faces whose fold test depends on where v is: those sharing a vertex
  // with a face around v.
  void influenced(int v, std::vector<std::size_t>& out) const {
    out.clear();
    std::vector<std::size_t> r;
    for (std::size_t f : faces_of(v)) {
      ring(f, r);
      out.insert(out.end(), r.begin(), r.end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  void update_around(int v) {
    for (std::size_t f : faces_of(v)) normal_[f] = face_normal_scaled(mesh_, f);
  }

 private:
  const TriangleMesh& mesh_;
  std::vector<std::size_t> start_, faces_;
  std::vector<Vec3> normal_;
};

}  // namespace

UnfoldReport unfold_semiregular(
    const TriangleMesh& base, int levels,
    const std::function<Vec3(int face, const Eigen::Vector3d& bary)>& point, TriangleMesh& mesh,
    int max_rounds) {
  const SemiregularLayout layout = semiregular_layout(base, levels);
  if (layout.sites.size() != mesh.n_vertices() || layout.triangles.size() != mesh.n_faces())
    throw std::invalid_argument(
        "unfold_semiregular: the mesh is not the semi-regular mesh of the base at this level");
  const int n = 1 << levels;
  FoldTest test(mesh);
  UnfoldReport report;
  std::vector<std::size_t> scratch, around;
  auto count_folds = [&](const std::vector<std::size_t>& faces) {
    std::size_t c = 0;
    for (std::size_t f : faces) c += test.folded(f, scratch);
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
  // Grid directions (di, dj): the six neighbours of an interior grid point.
  static constexpr int kDirections[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
  static constexpr double kSteps[3] = {0.25, 0.5, 0.75};
  for (int round = 0; round < max_rounds && !folded.empty(); ++round) {
    std::vector<int> vertices;
    for (std::size_t f : folded)
      for (int v : mesh.triangles[f])
        if (std::size_t(v) >= base.n_vertices()) vertices.push_back(v);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    bool kept = false;
    for (int v : vertices) {
      // The vertex's grid point on each base face holding it (two for a
      // vertex inside a base edge between two faces).
      const SemiregularSite sites[2] = {layout.sites[std::size_t(v)],
                                        layout.second_sites[std::size_t(v)]};
      if (sites[0].face < 0) continue;
      const SemiregularSite& s0 = sites[0];
      const bool on_boundary = (s0.j == 0 || s0.i == 0 || s0.i + s0.j == n) && sites[1].face < 0;
      test.influenced(v, around);
      std::size_t best = count_folds(around);
      const Vec3 original = mesh.positions[std::size_t(v)];
      Vec3 best_position = original;
      for (double step : kSteps)
        for (const SemiregularSite& s : sites) {
          if (s.face < 0) continue;
          for (const auto& d : kDirections) {
            const double i = s.i + step * d[0], j = s.j + step * d[1];
            if (i < 0 || j < 0 || i + j > n) continue;  // outside the face
            // On a boundary edge (j = 0, i = 0 or i + j = n), along it.
            if (on_boundary &&
                !((s.j == 0 && j == 0) || (s.i == 0 && i == 0) || (s.i + s.j == n && i + j == n)))
              continue;
            Vec3 p;
            try {
              p = point(s.face, layout.weights(i, j));
            } catch (const std::exception&) {
              continue;
            }
            mesh.positions[std::size_t(v)] = p;
            test.update_around(v);
            const std::size_t c = count_folds(around);
            if (c < best) best = c, best_position = p;
          }
        }
      mesh.positions[std::size_t(v)] = best_position;
      test.update_around(v);
      if (best_position != original) kept = true;
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
