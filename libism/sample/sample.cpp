#include "sample/sample.hpp"

#include "metrics/metrics.hpp"
#include "sample/grid_measures.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

namespace ism {

namespace {

// Faces of domain::octahedron() per quadrant (0: u>=0 v>=0, 1: u<0 v>=0,
// 2: u<0 v<0, 3: u>=0 v<0), upper (around +z) and lower (around -z).
constexpr std::array<int, 4> kUpperFace = {0, 1, 2, 3};
constexpr std::array<int, 4> kLowerFace = {4, 5, 6, 7};

// Corners of the faces as in domain::octahedron(); vertex v lies on axis v/2
// with sign + for even v.
constexpr std::array<std::array<int, 3>, 8> kFaces = {
    {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}};

int quadrant(bool u_positive, bool v_positive) {
  if (v_positive) return u_positive ? 0 : 1;
  return u_positive ? 3 : 2;
}

void check_face(int face) {
  if (face < 0 || face >= 8)
    throw std::invalid_argument("octahedron face " + std::to_string(face) + " out of range");
}

void check_size(int n) {
  if (!is_geometry_image_size(n))
    throw std::invalid_argument("geometry image size " + std::to_string(n) +
                                " is not 2^k+1 with 1 <= k <= 15");
}

void check_image(const GeometryImage& image) {
  check_size(image.n);
  if (image.pixels.size() != static_cast<std::size_t>(image.n) * image.n)
    throw std::invalid_argument(
        "geometry image has " + std::to_string(image.pixels.size()) +
        " pixels, expected n*n = " + std::to_string(static_cast<std::size_t>(image.n) * image.n));
}

/// The first pixel (row-major) of the mirror orbit of (row, col): the one
/// that is evaluated and that names the mesh vertex.
std::array<int, 2> canonical_pixel(int n, int row, int col) {
  const int last = n - 1;
  const bool top = row == 0, bottom = row == last, left = col == 0, right = col == last;
  if ((top || bottom) && (left || right)) return {0, 0};  // -z
  if (top || bottom) return {row, std::min(col, last - col)};
  if (left || right) return {std::min(row, last - row), col};
  return {row, col};
}

/// The two triangles of grid cell (row, col)-(row+1, col+1) as pixel
/// {row, col} corners, counter-clockwise in (u,v), split along the diagonal
/// parallel to the octahedron edge of the cell's quadrant.
std::array<std::array<std::array<int, 2>, 3>, 2> cell_triangles(int n, int row, int col) {
  const int m = (n - 1) / 2;
  const bool u_positive = col >= m, v_positive = row < m;
  const std::array<int, 2> tl{row, col}, tr{row, col + 1}, bl{row + 1, col}, br{row + 1, col + 1};
  if (u_positive == v_positive) return {{{tl, bl, br}, {tl, br, tr}}};
  return {{{bl, br, tr}, {bl, tr, tl}}};
}

}  // namespace

OctahedronPoint octahedron_point(double u, double v) {
  u = std::clamp(u, -1.0, 1.0);
  v = std::clamp(v, -1.0, 1.0);
  const bool u_positive = u >= 0.0, v_positive = v >= 0.0;
  const double au = std::abs(u), av = std::abs(v);
  const int q = quadrant(u_positive, v_positive);
  // |x|, |y|, |z| of the point on |x|+|y|+|z| = 1; they are its barycentric
  // coordinates with respect to the axis vertices of its face. The side is
  // chosen from the sign of the very z that becomes a weight, so no weight
  // comes out as -1e-16.
  const double z = 1.0 - au - av;
  std::array<double, 3> axis_weight;
  int face;
  if (z >= 0.0) {
    face = kUpperFace[q];
    axis_weight = {au, av, z};
  } else {
    face = kLowerFace[q];
    axis_weight = {1.0 - av, 1.0 - au, -z};
  }
  OctahedronPoint p;
  p.face = face;
  for (int k = 0; k < 3; ++k) p.bary[k] = axis_weight[kFaces[face][k] / 2];
  return p;
}

Eigen::Vector2d square_point(int face, const Eigen::Vector3d& bary) {
  check_face(face);
  // Weight per axis, and the face's quadrant from its equator vertices.
  std::array<double, 3> axis_weight{0.0, 0.0, 0.0};
  double su = 1.0, sv = 1.0;
  for (int k = 0; k < 3; ++k) {
    const int vertex = kFaces[face][k];
    axis_weight[vertex / 2] = bary[k];
    if (vertex == 1) su = -1.0;
    if (vertex == 3) sv = -1.0;
  }
  const bool upper = face < 4;
  if (upper) return {su * axis_weight[0], sv * axis_weight[1]};
  return {su * (1.0 - axis_weight[1]), sv * (1.0 - axis_weight[0])};
}

Vec3 octahedron_position(const OctahedronPoint& p) {
  check_face(p.face);
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const int vertex = kFaces[p.face][k];
    x[vertex / 2] += (vertex % 2 == 0 ? 1.0 : -1.0) * p.bary[k];
  }
  return x;
}

bool is_geometry_image_size(int n) {
  // k <= 15 keeps n² below 2^31, so pixel and vertex ids fit an int.
  if (n < 3 || n > (1 << 15) + 1) return false;
  const int m = n - 1;
  return (m & (m - 1)) == 0;
}

Eigen::Vector2d pixel_square_point(int n, int row, int col) {
  const double last = n - 1;
  return {-1.0 + 2.0 * col / last, 1.0 - 2.0 * row / last};
}

std::array<int, 2> octahedron_vertex_pixel(int n, int vertex) {
  const int m = (n - 1) / 2, last = n - 1;
  switch (vertex) {
    case 0:
      return {m, last};
    case 1:
      return {m, 0};
    case 2:
      return {0, m};
    case 3:
      return {last, m};
    case 4:
      return {m, m};
    case 5:
      return {0, 0};
  }
  throw std::invalid_argument("octahedron vertex " + std::to_string(vertex) + " out of range");
}

std::vector<int> image_vertex_of_pixel(int n) {
  check_size(n);
  std::vector<int> vertex(static_cast<std::size_t>(n) * n, -1);
  int next = 0;
  // Row-major: the canonical pixel of an orbit comes first, so its id is set
  // before any mirror reads it.
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const auto [r, c] = canonical_pixel(n, row, col);
      const std::size_t self = static_cast<std::size_t>(row) * n + col;
      vertex[self] = (r == row && c == col) ? next++ : vertex[static_cast<std::size_t>(r) * n + c];
    }
  return vertex;
}

GeometryImage sample_octahedral(int n,
                                const std::function<Vec3(const OctahedronPoint&)>& surface_point) {
  check_size(n);
  GeometryImage image;
  image.n = n;
  image.pixels.assign(static_cast<std::size_t>(n) * n, Vec3::Zero());
  // Each canonical pixel is written by exactly one task: deterministic.
  tbb::parallel_for(0, n, [&](int row) {
    for (int col = 0; col < n; ++col) {
      const auto [r, c] = canonical_pixel(n, row, col);
      if (r != row || c != col) continue;
      const Eigen::Vector2d uv = pixel_square_point(n, row, col);
      image.at(row, col) = surface_point(octahedron_point(uv.x(), uv.y()));
    }
  });
  // Mirrors exist only on the boundary: copy them serially, bit for bit.
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const auto [r, c] = canonical_pixel(n, row, col);
      if (r != row || c != col) image.at(row, col) = image.at(r, c);
    }
  return image;
}

TriangleMesh image_to_mesh(const GeometryImage& image) {
  check_image(image);
  const int n = image.n;
  const std::vector<int> vertex = image_vertex_of_pixel(n);
  TriangleMesh mesh;
  mesh.positions.resize(static_cast<std::size_t>(n - 1) * (n - 1) + 2);
  // A vertex takes the value of its first pixel (row-major); mirrors of an
  // image that is not bit-symmetric are ignored rather than averaged.
  int next = 0;
  for (std::size_t p = 0; p < vertex.size(); ++p)
    if (vertex[p] == next) mesh.positions[next++] = image.pixels[p];
  mesh.triangles.reserve(2 * static_cast<std::size_t>(n - 1) * (n - 1));
  for (int row = 0; row + 1 < n; ++row)
    for (int col = 0; col + 1 < n; ++col)
      for (const auto& t : cell_triangles(n, row, col)) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) tri[k] = vertex[image.index(t[k][0], t[k][1])];
        mesh.triangles.push_back(tri);
      }
  return mesh;
}

namespace {

// A grid triangle (pixel corners) lies on the input surface: no alpha, or
// alpha 1 at all three corners.
bool on_surface(const GeometryImage& image, const std::array<std::array<int, 2>, 3>& t) {
  if (image.alpha.empty()) return true;
  for (const auto& c : t)
    if (image.alpha[image.index(c[0], c[1])] < 0.5f) return false;
  return true;
}

}  // namespace

TriangleMesh image_to_surface_mesh(const GeometryImage& image) {
  TriangleMesh mesh = image_to_mesh(image);
  if (image.alpha.empty()) return mesh;
  if (image.alpha.size() != image.pixels.size())
    throw std::invalid_argument("geometry image with " + std::to_string(image.alpha.size()) +
                                " alpha values for " + std::to_string(image.pixels.size()) +
                                " pixels");
  const int n = image.n;
  std::vector<Triangle> kept;
  std::size_t f = 0;
  for (int row = 0; row + 1 < n; ++row)
    for (int col = 0; col + 1 < n; ++col)
      for (const auto& t : cell_triangles(n, row, col)) {
        if (on_surface(image, t)) kept.push_back(mesh.triangles[f]);
        ++f;
      }
  // Vertices that only cap triangles used go; the others keep their order.
  std::vector<int> index(mesh.n_vertices(), -1);
  for (const Triangle& t : kept)
    for (int v : t) index[v] = 0;
  TriangleMesh out;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = int(out.positions.size());
      out.positions.push_back(mesh.positions[v]);
    }
  out.triangles.reserve(kept.size());
  for (const Triangle& t : kept) out.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return out;
}

double image_efficiency(const GeometryImage& image, ImageDomain domain) {
  check_image(image);
  const int n = image.n;
  auto domain_point = [&](int row, int col) -> Vec3 {
    const Eigen::Vector2d uv = pixel_square_point(n, row, col);
    if (domain == ImageDomain::square) return {uv.x(), uv.y(), 0.0};
    return octahedron_position(octahedron_point(uv.x(), uv.y()));
  };
  return detail::grid_efficiency(
      n - 1,
      [&](int row, std::vector<StretchPiece>& pieces) {
        for (int col = 0; col + 1 < n; ++col)
          for (const auto& t : cell_triangles(n, row, col))
            if (on_surface(image, t))
              pieces.push_back(
                  {detail::triangle_lengths(domain_point(t[0][0], t[0][1]),
                                            domain_point(t[1][0], t[1][1]),
                                            domain_point(t[2][0], t[2][1])),
                   detail::triangle_lengths(image.at(t[0][0], t[0][1]), image.at(t[1][0], t[1][1]),
                                            image.at(t[2][0], t[2][1]))});
      },
      "image_efficiency");
}

std::size_t flipped_triangles(const GeometryImage& image) {
  return flipped_faces(image_to_surface_mesh(image));
}

UnfoldReport unfold_geometry_image(GeometryImage& image,
                                   const std::function<Vec3(const OctahedronPoint&)>& surface_point,
                                   std::vector<OctahedronPoint>* moved_to) {
  check_image(image);
  const int n = image.n;
  if (moved_to) moved_to->assign(image.pixels.size(), OctahedronPoint{.face = -1});
  if (!image.alpha.empty()) {
    const std::size_t folds = flipped_triangles(image);
    return {.folds_before = folds, .folds_after = folds};
  }
  const std::vector<int> vertex = image_vertex_of_pixel(n);
  TriangleMesh mesh = image_to_mesh(image);
  // Each vertex's first pixel (row-major), where its samples are placed.
  std::vector<std::size_t> first(mesh.n_vertices(), 0);
  for (std::size_t p = vertex.size(); p-- > 0;) first[std::size_t(vertex[p])] = p;
  // The eight neighbouring pixels' directions (columns, rows) and the steps towards them.
  static constexpr int kDirections[8][2] = {{1, 0}, {-1, 0},  {0, 1},  {0, -1},
                                            {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  static constexpr double kSteps[3] = {0.25, 0.5, 0.75};
  const double pixel = 2.0 / (n - 1);
  // The points each vertex's candidates were sampled at (those that threw left out).
  std::vector<std::vector<OctahedronPoint>> offered(mesh.n_vertices());
  auto candidates = [&](int v, std::vector<Vec3>& out) {
    const std::size_t p = first[std::size_t(v)];
    const Eigen::Vector2d uv = pixel_square_point(n, int(p) / n, int(p) % n);
    std::vector<OctahedronPoint>& points = offered[std::size_t(v)];
    points.clear();
    for (double step : kSteps)
      for (const auto& d : kDirections) {
        const OctahedronPoint q =
            octahedron_point(uv.x() + step * pixel * d[0], uv.y() - step * pixel * d[1]);
        try {
          out.push_back(surface_point(q));
          points.push_back(q);
        } catch (const std::exception&) {
        }
      }
  };
  std::vector<int> chosen;
  const UnfoldReport report = unfold_samples(mesh, candidates, {}, &chosen);
  for (std::size_t p = 0; p < vertex.size(); ++p) {
    const std::size_t v = std::size_t(vertex[p]);
    if (chosen[v] < 0) continue;
    image.pixels[p] = mesh.positions[v];
    if (moved_to) (*moved_to)[p] = offered[v][std::size_t(chosen[v])];
  }
  return report;
}

}  // namespace ism
