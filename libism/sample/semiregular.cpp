#include "sample/semiregular.hpp"
#include "mesh/edge_key.hpp"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace ism {

SemiregularLayout semiregular_layout(const TriangleMesh& base, int levels) {
  if (levels < 0 || levels > 10)
    throw std::invalid_argument("semiregular_mesh: levels must be in 0..10");
  const int n = 1 << levels;
  const int nv = int(base.n_vertices());
  const int nf = int(base.n_faces());

  // Base edges in order of first appearance.
  std::unordered_map<std::uint64_t, int> edge_index;
  std::vector<int> face_edge(3 * std::size_t(nf));
  int n_edges = 0;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = base.triangles[f][k], b = base.triangles[f][(k + 1) % 3];
      if (a < 0 || a >= nv || b < 0 || b >= nv || a == b)
        throw std::invalid_argument("semiregular_mesh: bad base face " + std::to_string(f));
      auto [it, fresh] =
          edge_index.emplace(directed_edge_key(std::min(a, b), std::max(a, b)), n_edges);
      if (fresh) ++n_edges;
      face_edge[3 * std::size_t(f) + k] = it->second;
    }

  const std::size_t per_edge = std::size_t(n - 1);
  const std::size_t per_face = n >= 2 ? std::size_t(n - 1) * std::size_t(n - 2) / 2 : 0;
  const std::size_t edge_start = std::size_t(nv);
  const std::size_t face_start = edge_start + per_edge * std::size_t(n_edges);
  SemiregularLayout out;
  out.levels = levels;
  out.sites.assign(face_start + per_face * std::size_t(nf), SemiregularSite{});
  out.triangles.reserve(std::size_t(nf) * std::size_t(n) * std::size_t(n));
  out.second_sites.assign(out.sites.size(), SemiregularSite{});
  std::vector<int> edge_faces(std::size_t(n_edges), 0);
  for (int e : face_edge) ++edge_faces[std::size_t(e)];
  out.boundary_edges.assign(std::size_t(nf), 0);
  for (std::size_t f = 0; f < std::size_t(nf); ++f)
    for (int k = 0; k < 3; ++k)
      if (edge_faces[std::size_t(face_edge[3 * f + k])] == 1) out.boundary_edges[f] |= 1 << k;
  auto place = [&](std::size_t v, int f, int i, int j) {
    if (out.sites[v].face < 0)
      out.sites[v] = {f, i, j};
    else if (v >= edge_start && v < face_start)
      out.second_sites[v] = {f, i, j};
  };

  // Grid point (i, j) of a face: weights ((n-i-j)/n, i/n, j/n) of corners 0, 1, 2.
  std::vector<int> grid(std::size_t(n + 1) * std::size_t(n + 1), -1);
  auto at = [&](int i, int j) -> int& { return grid[std::size_t(j) * (n + 1) + i]; };
  for (int f = 0; f < nf; ++f) {
    const Triangle& t = base.triangles[f];
    // Corners.
    const int ci[3] = {0, n, 0}, cj[3] = {0, 0, n};
    for (int k = 0; k < 3; ++k) {
      at(ci[k], cj[k]) = t[k];
      place(std::size_t(t[k]), f, ci[k], cj[k]);
    }
    // Edges: corner k to corner k+1, step s = 1..n-1 from corner k.
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const std::size_t first =
          edge_start + per_edge * std::size_t(face_edge[3 * std::size_t(f) + k]);
      const int k1 = (k + 1) % 3;
      for (int s = 1; s < n; ++s) {
        const int i = ci[k] + (ci[k1] - ci[k]) / n * s, j = cj[k] + (cj[k1] - cj[k]) / n * s;
        const int from_low = a < b ? s : n - s;  // parameter from the lower endpoint
        const std::size_t v = first + std::size_t(from_low - 1);
        at(i, j) = int(v);
        place(v, f, i, j);
      }
    }
    // Interior.
    std::size_t v = face_start + per_face * std::size_t(f);
    for (int j = 1; j < n; ++j)
      for (int i = 1; i + j < n; ++i, ++v) {
        at(i, j) = int(v);
        place(v, f, i, j);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        out.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j + 2 <= n) out.triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  return out;
}

Eigen::Vector3d SemiregularLayout::weights(double i, double j) const {
  const double n = double(1 << levels);
  return Eigen::Vector3d((n - i - j) / n, i / n, j / n);
}

TriangleMesh semiregular_mesh(
    const TriangleMesh& base, int levels,
    const std::function<Vec3(int face, const Eigen::Vector3d& bary)>& point) {
  SemiregularLayout layout = semiregular_layout(base, levels);
  TriangleMesh out;
  out.triangles = std::move(layout.triangles);
  out.positions.resize(layout.sites.size());
  for (std::size_t v = 0; v < layout.sites.size(); ++v) {
    const SemiregularSite& s = layout.sites[v];
    // Base vertices on no face keep their own position.
    out.positions[v] = s.face < 0 ? base.positions[v] : point(s.face, layout.weights(s.i, s.j));
  }
  return out;
}

bool unsubdivide(const TriangleMesh& fine, std::size_t base_vertices, TriangleMesh& coarse) {
  const std::size_t nv = fine.n_vertices();
  if (fine.n_faces() % 4 != 0 || base_vertices == 0 || base_vertices > nv) return false;
  // Directed edge (x, y) -> third corner z of the face (x, y, z).
  std::unordered_map<std::uint64_t, int> third;
  third.reserve(3 * fine.n_faces());
  for (const Triangle& t : fine.triangles)
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || std::size_t(t[k]) >= nv) return false;
      if (!third.emplace(directed_edge_key(t[k], t[(k + 1) % 3]), t[(k + 2) % 3]).second)
        return false;
    }
  auto next = [&](int m, int x) -> int {  // neighbour of m after x, counter-clockwise
    const auto it = third.find(directed_edge_key(m, x));
    return it == third.end() ? -1 : it->second;
  };
  auto previous = [&](int m, int x) -> int {  // neighbour of m before x
    const auto it = third.find(directed_edge_key(x, m));
    return it == third.end() ? -1 : it->second;
  };
  // Vertex across the odd vertex m from v: three steps around m, whose
  // one-ring must close after six; on a boundary edge (an open fan of four
  // around m), the fan's other end.
  auto across = [&](int v, int m) -> int {
    int ring[6];
    int x = v;
    for (int s = 0; s < 6; ++s) {
      ring[s] = x;
      x = next(m, x);
      if (x < 0) break;
    }
    if (x >= 0) return x == v ? ring[3] : -1;
    // Open: v must be one end of a fan v, o, o, w.
    if (previous(m, v) >= 0 && next(m, v) >= 0) return -1;
    int ends = 0, far = v, count = 1;
    for (int y = v; (y = next(m, y)) >= 0 && count <= 4;) far = y, ++count, ends |= 1;
    for (int y = v; (y = previous(m, y)) >= 0 && count <= 4;) far = y, ++count, ends |= 2;
    return count == 4 && ends != 3 ? far : -1;
  };
  std::vector<std::vector<int>> neighbours(nv);
  for (const Triangle& t : fine.triangles)
    for (int k = 0; k < 3; ++k) neighbours[t[k]].push_back(t[(k + 1) % 3]);

  enum : char { unknown, even, odd };
  std::vector<char> label(nv, unknown);
  std::vector<int> queue;
  for (std::size_t v = 0; v < base_vertices; ++v) label[v] = even, queue.push_back(int(v));
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int v = queue[q];
    for (int m : neighbours[v]) {
      if (label[m] == even) return false;
      label[m] = odd;
      const int w = across(v, m);
      if (w < 0 || label[w] == odd) return false;
      if (label[w] == unknown) label[w] = even, queue.push_back(w);
    }
  }
  std::vector<int> index(nv, -1);
  coarse = TriangleMesh{};
  for (std::size_t v = 0; v < nv; ++v) {
    if (label[v] == unknown) return false;  // unreachable from the base vertices
    if (label[v] == even) {
      index[v] = int(coarse.positions.size());
      coarse.positions.push_back(fine.positions[v]);
    }
  }
  // Each coarse face (a, b, c) must come with exactly its four fine faces.
  auto canonical = [](Triangle t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  std::vector<Triangle> expected, faces;
  for (const Triangle& t : fine.triangles) {
    const int k =
        int(std::find_if(t.begin(), t.end(), [&](int v) { return label[v] == even; }) - t.begin());
    if (k == 3) continue;  // middle face, checked below
    const int a = t[k], m1 = t[(k + 1) % 3], m2 = t[(k + 2) % 3];
    if (label[m1] != odd || label[m2] != odd) return false;
    const int b = across(a, m1), c = across(a, m2);
    if (b < 0 || c < 0 || label[b] != even || label[c] != even) return false;
    const Triangle f = canonical({a, b, c});
    if (f[0] != a) continue;  // each coarse face once, from its smallest corner
    const int mab = m1, mca = m2;
    // m_bc: the odd vertex between b and c.
    int mbc = -1;
    for (int m : neighbours[b])
      if (label[m] == odd && across(b, m) == c) mbc = m;
    if (mbc < 0) return false;
    faces.push_back(f);
    expected.push_back(canonical({a, mab, mca}));
    expected.push_back(canonical({b, mbc, mab}));
    expected.push_back(canonical({c, mca, mbc}));
    expected.push_back(canonical({mab, mbc, mca}));
  }
  std::vector<Triangle> actual;
  actual.reserve(fine.n_faces());
  for (const Triangle& t : fine.triangles) actual.push_back(canonical(t));
  std::sort(expected.begin(), expected.end());
  std::sort(actual.begin(), actual.end());
  if (expected != actual) return false;
  for (const Triangle& f : faces)
    coarse.triangles.push_back({index[f[0]], index[f[1]], index[f[2]]});
  return true;
}

}  // namespace ism
