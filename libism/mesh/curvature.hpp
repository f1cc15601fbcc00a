#pragma once
// Discrete curvature of a triangle mesh: where a surface bends, a piecewise
// linear sampling of it errs most, so maps can spend more samples there.
#include "mesh/triangle_mesh.hpp"

#include <vector>

namespace ism {

/// Root-mean-square normal curvature at each vertex, in 1/length: the mean
/// over its edges of κ_ij² = (2 n_i·(x_j − x_i) / |x_j − x_i|²)² (the circle
/// through x_j tangent to the surface at x_i; n_i the area-weighted vertex
/// normal), then `smoothing_rings` times averaged with its edge neighbours
/// (weighted by vertex area) so that one noisy edge does not decide it.
/// Unreferenced vertices get 0.
std::vector<double> vertex_curvature(const TriangleMesh& mesh, int smoothing_rings = 2);

/// A sampling density per vertex, 1 + weight · κ / κ_rms with κ from
/// vertex_curvature and κ_rms its area-weighted root mean square: scale
/// invariant, mean about 1 + weight. weight 0 gives 1 everywhere.
/// Precondition: weight >= 0.
std::vector<double> curvature_density(const TriangleMesh& mesh, double weight,
                                      int smoothing_rings = 2);

}  // namespace ism
