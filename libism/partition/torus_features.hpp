#pragma once
// Automatic features for the flat 3×3 torus domain of domain::torus_3x3():
// a harmonic map of the genus-1 surface to a flat torus (cohomology basis
// from a tree–cotree decomposition, cotangent-harmonic projection, period
// lattice reduced to its two shortest directions), a 3×3 lattice in it
// re-spaced so that the points spread over the whole surface, and the
// surface vertices at the lattice points.
#include "partition/partition.hpp"

#include <vector>

namespace ism {

/// Nine surface vertices, row-major in the 3×3 grid of domain::torus_3x3(),
/// spread over a closed genus-1 surface along two independent
/// non-contractible directions, oriented like the domain: of the candidate
/// sets, the one that covers the surface most evenly (no path is traced, so
/// trace_torus_network() may settle on another). Throws PartitionError if
/// the surface is not a closed genus-1 manifold.
std::vector<int> choose_torus_features(const TriangleMesh& surface);

/// Traces the torus network with automatic features. Candidates (both
/// assignments of the torus directions to rows and columns, lattice offsets
/// by thirds of a cell, three ways of spacing) are traced from the most
/// evenly spread on; of the first few valid ones whose spread is within 5% of
/// the best valid one, the network with the shortest total length is
/// returned. Mirrored grids are a last resort. Throws PartitionError if the
/// surface is not closed genus-1 or no candidate gives a valid network.
PathNetwork trace_torus_network(const TriangleMesh& surface, const PartitionOptions& options = {});

/// All valid networks of those candidates (the first few within 5% of the
/// best spread, or mirrored ones as a last resort), shortest first, for a
/// choice by map energy (choose_network). Same errors.
std::vector<PathNetwork> trace_torus_networks(const TriangleMesh& surface,
                                              const PartitionOptions& options = {});

/// Traces the torus network between given features (row-major in the 3×3
/// grid), each path in the homotopy class of a harmonic map of the surface
/// to the flat torus, laid so that the features sit closest to the grid
/// points (the lattice basis change with entries in -1..1 and determinant 1
/// that fits best). Throws PartitionError for a wrong count, bad indices, a
/// surface that is not closed genus 1, or an order that cannot be realised.
PathNetwork trace_torus_network(const TriangleMesh& surface, const std::vector<int>& features,
                                const PartitionOptions& options = {});

}  // namespace ism
