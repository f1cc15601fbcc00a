#pragma once
// Generators of closed test surfaces with known topology and geometry: every
// result is one closed, edge- and vertex-manifold component, oriented outward
// (positive signed volume), without degenerate or duplicate faces or
// duplicate positions, and fully deterministic. target_faces is a hint; each
// shape documents the exact count it produces.
#include "mesh/triangle_mesh.hpp"

#include <cstdint>

namespace ism::shapes {

/// Geodesic sphere of the given radius centred at the origin: an icosahedron
/// whose faces are each split into n^2 triangles (class I, frequency
/// n = max(1, round(sqrt(target_faces / 20)))) and projected onto the sphere.
/// Exactly 20 n^2 faces and 10 n^2 + 2 vertices; the first 12 vertices are the
/// icosahedron corners.
TriangleMesh sphere(int target_faces, double radius = 1.0);

/// sphere(target_faces) scaled by semi_axes (all > 0) along x, y, z.
TriangleMesh ellipsoid(int target_faces, const Vec3& semi_axes);

/// Bumpy star-shaped genus-0 surface: the unit geodesic sphere with every
/// vertex moved radially to r(d) = 1 + sum_k a_k exp(-(1 - d.c_k) / w_k) for
/// 6 to 10 random bumps (centres c_k, amplitudes a_k ~ bumpiness, widths w_k)
/// drawn from std::mt19937_64(seed). r stays above 0.3, and radial motion
/// keeps every face facing away from the origin, so the surface is embedded.
/// Same face and vertex counts as sphere(target_faces).
TriangleMesh blob(int target_faces, std::uint64_t seed = 1, double bumpiness = 0.35);

/// Torus around the z axis with major radius R and minor radius r (R > r > 0):
/// an n x m grid of quads, each split into two triangles, with m/n ~ r/R so the
/// cells are roughly square and 2 n m ~ target_faces (n, m >= 3). Vertex
/// i * m + j sits at angle 2 pi i / n around z and angle 2 pi j / m around the
/// tube (j = 0 on the outer equator).
TriangleMesh torus(int target_faces, double R = 2.0, double r = 1.0);

/// Closed genus-2 surface: the boundary of a 5 x 3 x 1 slab of unit voxels
/// with two 1 x 1 through-holes, each boundary unit square split into k x k
/// squares of two triangles (k = max(1, round(sqrt(target_faces / 100))), so
/// exactly 100 k^2 faces and 50 k^2 - 2 vertices), then rounded by Laplacian
/// smoothing over a fixed physical length, so the shape hardly depends on k
/// (about 4.75 x 2.75 x 0.87, centred at the origin; k = 1 stays boxy). No
/// face turns by 90 degrees or more from its voxel square.
TriangleMesh double_torus(int target_faces);

}  // namespace ism::shapes
