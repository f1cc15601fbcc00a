// Flipped faces of a remesh: the fold test of Praun & Hoppe's geometry
// images, usable on any triangle mesh, whole (flipped_faces) or face by face
// on moving positions (FoldTest).
#include "metrics/metrics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace ism {

FoldTest::FoldTest(const TriangleMesh& mesh) : mesh_(mesh) {
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

std::span<const std::size_t> FoldTest::faces_of(int v) const {
  return {faces_.data() + start_[std::size_t(v)], faces_.data() + start_[std::size_t(v) + 1]};
}

void FoldTest::ring(std::size_t f, std::vector<std::size_t>& out) const {
  // A neighbour sharing an edge must count once, not twice.
  out.clear();
  for (int v : mesh_.triangles[f]) {
    const auto around = faces_of(v);
    out.insert(out.end(), around.begin(), around.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

Vec3 FoldTest::ring_normal(std::size_t f, std::vector<std::size_t>& scratch) const {
  ring(f, scratch);
  Vec3 sum = Vec3::Zero();
  for (std::size_t g : scratch) sum += normal_[g];
  return sum;
}

bool FoldTest::folded(std::size_t f, std::vector<std::size_t>& scratch) const {
  return normal_[f].dot(ring_normal(f, scratch)) < 0.0;
}

double FoldTest::fold_depth(std::size_t f, std::vector<std::size_t>& scratch) const {
  const Vec3 sum = ring_normal(f, scratch);
  const double scale = normal_[f].norm() * sum.norm();
  if (!(scale > 0)) return 0.0;
  return std::max(0.0, -normal_[f].dot(sum) / scale);
}

void FoldTest::influenced(int v, std::vector<std::size_t>& out) const {
  out.clear();
  std::vector<std::size_t> r;
  for (std::size_t f : faces_of(v)) {
    ring(f, r);
    out.insert(out.end(), r.begin(), r.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void FoldTest::update_around(int v) {
  for (std::size_t f : faces_of(v)) normal_[f] = face_normal_scaled(mesh_, f);
}

std::size_t flipped_faces(const TriangleMesh& mesh) {
  const FoldTest test(mesh);
  std::vector<char> flipped(mesh.n_faces(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.n_faces()), [&](const auto& range) {
    std::vector<std::size_t> scratch;
    for (std::size_t f = range.begin(); f != range.end(); ++f) flipped[f] = test.folded(f, scratch);
  });
  return static_cast<std::size_t>(std::count(flipped.begin(), flipped.end(), 1));
}

}  // namespace ism
