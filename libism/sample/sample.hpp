#pragma once
// Octahedral geometry images (Praun & Hoppe 2003; Schreiner et al. 2004 §6.3):
// the octahedron domain::octahedron() unfolded into the square [-1,1]², sampled
// on a regular pixel grid, and the image read back as a watertight mesh.
//
// Layout (the contract for every program that reads or writes our images):
//
//  - The image is n × n pixels with n = 2^k + 1, k >= 1. Pixel (row i,
//    column j), row 0 at the top, sits at the square point
//        u = -1 + 2j/(n-1),   v = 1 - 2i/(n-1).
//  - Unfolding: +z at the centre (0,0); +x at (1,0), +y at (0,1), -x at
//    (-1,0), -y at (0,-1); -z at all four corners (±1,±1). The upper faces
//    (those around +z) fill the diamond |u|+|v| <= 1, the lower faces the
//    four corner triangles, one upper and one lower face per quadrant:
//        quadrant  u>=0 v>=0: upper {0,2,4} = (1,0),(0,1),(0,0)
//                             lower {2,0,5} = (0,1),(1,0),(1,1)
//                  u<0  v>=0: upper {2,1,4}, lower {1,2,5}
//                  u<0  v<0 : upper {1,3,4}, lower {3,1,5}
//                  u>=0 v<0 : upper {3,0,4}, lower {0,3,5}
//    (vertex ids of domain::octahedron(): 0..5 = +x,-x,+y,-y,+z,-z). The
//    octahedron point of (u,v) is (u, v, 1-|u|-|v|) inside the diamond and
//    (sign(u)(1-|v|), sign(v)(1-|u|), 1-|u|-|v|) outside it, on the regular
//    octahedron |x|+|y|+|z| = 1. Every face keeps its counter-clockwise order
//    in (u,v), so an outward surface gives counter-clockwise triangles in (u,v).
//  - Vertex pixels, with m = (n-1)/2: +z at (m,m); +x at (m,n-1); +y at (0,m);
//    -x at (m,0); -y at (n-1,m); -z at the four corners (0,0),(0,n-1),(n-1,0),
//    (n-1,n-1).
//  - Boundary: each side of the square is mirrored about its midpoint, so
//    pixel (0,j) = (0,n-1-j), (n-1,j) = (n-1,n-1-j), (i,0) = (n-1-i,0) and
//    (i,n-1) = (n-1-i,n-1), and the four corners are one point. Such pixels
//    hold bit-identical values.
//  - Triangulation: grid cell (i,j)-(i+1,j+1) is split along the diagonal
//    parallel to the octahedron edge of its quadrant: from (i,j) to (i+1,j+1)
//    in the quadrants u>0,v>0 and u<0,v<0, from (i+1,j) to (i,j+1) in the
//    other two. Every grid triangle then lies in one octahedron face (and is
//    equilateral on the regular octahedron).
#include "mesh/triangle_mesh.hpp"
#include "sample/unfold.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace ism {

/// A point of domain::octahedron(): a face and barycentric coordinates with
/// respect to that face's corners in its vertex order.
struct OctahedronPoint {
  int face = 0;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

/// The octahedron point of the square point (u,v) in [-1,1]² (clamped to it).
/// Points on a face boundary go to the face of the quadrant with u >= 0 /
/// v >= 0 first, the upper face when |u|+|v| = 1. Weights are >= 0.
OctahedronPoint octahedron_point(double u, double v);

/// Inverse of octahedron_point: the square point of a face point (bary sums
/// to 1), in the face's own quadrant (so -z of face {2,0,5} is (1,1)).
Eigen::Vector2d square_point(int face, const Eigen::Vector3d& bary);

/// The point on the regular octahedron |x|+|y|+|z| = 1 (Σ bary_k · vertex_k).
Vec3 octahedron_position(const OctahedronPoint& p);

/// True when n = 2^k + 1 with k >= 1 (and n² pixels fit an int index).
bool is_geometry_image_size(int n);

/// The square point (u,v) of pixel (row, col) of an n × n image.
Eigen::Vector2d pixel_square_point(int n, int row, int col);

/// The pixel {row, col} of octahedron vertex 0..5; -z gives the corner (0,0).
std::array<int, 2> octahedron_vertex_pixel(int n, int vertex);

/// For each pixel (row-major), the vertex of image_to_mesh it becomes:
/// vertices are numbered in row-major order of the first pixel of each
/// distinct octahedron point, mirrored pixels share their vertex.
/// There are (n-1)² + 2 vertices.
std::vector<int> image_vertex_of_pixel(int n);

struct GeometryImage {
  int n = 0;
  std::vector<Vec3> pixels;  // row-major, n * n
  /// Empty, or per pixel (row-major) 1 where the sample lies on the input
  /// surface and 0 where it lies on a cap that closed one of its holes
  /// (gim-remesh of an open surface; EXR channel A).
  std::vector<float> alpha;

  Vec3& at(int row, int col) { return pixels[index(row, col)]; }
  const Vec3& at(int row, int col) const { return pixels[index(row, col)]; }
  std::size_t index(int row, int col) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(n) +
           static_cast<std::size_t>(col);
  }
};

/// Samples a surface over the octahedron: surface_point is called once per
/// distinct octahedron point (concurrently from several threads, so it must
/// be thread-safe) and its value copied to the mirrored pixels, which are
/// then bit-identical. The result does not depend on the thread schedule.
/// Throws std::invalid_argument unless is_geometry_image_size(n).
GeometryImage sample_octahedral(int n,
                                const std::function<Vec3(const OctahedronPoint&)>& surface_point);

/// The remesh: one vertex per distinct octahedron point (image_vertex_of_pixel),
/// two triangles per grid cell as in the layout, counter-clockwise so that an
/// image of an outward surface gives an outward mesh. A closed genus-0 mesh
/// with (n-1)² + 2 vertices and 2(n-1)² triangles. Should mirrored pixels
/// differ, the first of them (row-major) gives the vertex position. Throws
/// std::invalid_argument for a bad size or pixel count.
TriangleMesh image_to_mesh(const GeometryImage& image);

/// The remesh of the input surface alone: image_to_mesh() without the grid
/// triangles that touch a cap (alpha 0 at a corner) and without the vertices
/// only those used (the others keep their order). The same as
/// image_to_mesh() for an image without alpha. For an open input it is open
/// where the input is: the boundary runs along the last pixels on the
/// surface. Throws as image_to_mesh(), and for an alpha of the wrong size.
TriangleMesh image_to_surface_mesh(const GeometryImage& image);

/// The domain a grid triangle's stretch is measured from.
enum class ImageDomain {
  square,      ///< the flat pixel grid: right isosceles triangles
  octahedron,  ///< the pixels placed on the regular octahedron: equilateral triangles
};

/// One-way L2 stretch efficiency of the map domain -> image surface over the
/// grid triangles (ism::one_way_stretch: weights are the 3D triangle areas,
/// so zero-area triangles weigh nothing but still count in the domain area).
/// 1 for an isometry up to scale. With alpha, only the grid triangles of
/// image_to_surface_mesh() count. Lengths only: a fold is not penalised
/// (count those with flipped_triangles). Throws std::invalid_argument for a bad
/// image or one with zero total area.
double image_efficiency(const GeometryImage& image, ImageDomain domain);

/// Number of grid triangles whose normal has a negative dot product with the
/// sum of the area-weighted normals of all triangles sharing a vertex with it
/// (itself included), on the welded mesh of image_to_surface_mesh, so neighbours
/// across the mirrored boundary count. Zero-area triangles are never flipped.
std::size_t flipped_triangles(const GeometryImage& image);

/// Re-samples the vertices of folded grid triangles of image_to_mesh(image)
/// (unfold_samples(), unfold.hpp, by their number alone) at nearby square points: a quarter, half
/// or three quarters of the way towards each of the eight neighbouring pixels of the vertex's first
/// pixel, clamped into the square (octahedron_point), through
/// `surface_point` as sample_octahedral() calls it (again for each tried
/// point; one that throws is not tried). Mirrored pixels keep bit-identical
/// values. An image with alpha (an open surface's) is left as it is: a
/// moved sample could cross onto a cap. `moved_to`, when given, receives per
/// pixel the octahedron point whose image a moved pixel now holds (face -1
/// for a pixel left at its grid point), so that other attributes (normals)
/// can be sampled at the same points. folds_before and folds_after are
/// flipped_triangles() of the image as given and as returned. Throws
/// std::invalid_argument for a bad image.
UnfoldReport unfold_geometry_image(GeometryImage& image,
                                   const std::function<Vec3(const OctahedronPoint&)>& surface_point,
                                   std::vector<OctahedronPoint>* moved_to = nullptr);

}  // namespace ism
