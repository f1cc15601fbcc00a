#pragma once
// Test fixture: candidates with domains of their own, as semireg makes them
// (the surface decimated to a base by the quadric and the isotropic
// priority, each base's equilateral domain with its traced network).
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/network_choice.hpp"

#include <memory>
#include <vector>

namespace ism::test {

inline std::vector<DomainCandidate> decimated_candidates(const TriangleMesh& surface,
                                                         std::size_t base_vertices) {
  std::vector<DomainCandidate> out;
  for (SimplifyPriority priority : {SimplifyPriority::quadric, SimplifyPriority::isotropic}) {
    const ProgressiveMesh decimated = simplify_to(surface, base_vertices, {.priority = priority});
    const TriangleMesh base = base_mesh(decimated);
    out.push_back({std::make_unique<DomainGeometry>(base, equilateral_lengths(base)),
                   trace_path_network(surface, base, decimated.base_vertices)});
  }
  return out;
}

}  // namespace ism::test
