// Two progressive meshes to one base (paper §3 step 2).
#include "pm/pm.hpp"

#include <tbb/parallel_invoke.h>

#include <stdexcept>
#include <string>

namespace ism {
namespace {

// The progressive mesh of a capped surface without its caps: centres and
// their faces go, a split whose wing is a centre becomes a boundary split.
ProgressiveMesh drop_caps(const ProgressiveMesh& capped, const PathNetwork& open,
                          const TriangleMesh& base, std::size_t loops) {
  const std::size_t input = open.original_vertices;
  auto map = [&](int v) {
    if (v < 0) return -1;
    if (std::size_t(v) < input) return v;
    if (std::size_t(v) < input + loops) return -1;
    return int(v - loops);
  };
  ProgressiveMesh pm;
  pm.base.positions = open.surface.positions;
  if (capped.base.n_vertices() != pm.base.n_vertices() + loops)
    throw std::runtime_error("simplify_compatible: the capped surface does not match the open one");
  for (const Triangle& t : capped.base.triangles) {
    const Triangle m{map(t[0]), map(t[1]), map(t[2])};
    if (m[0] >= 0 && m[1] >= 0 && m[2] >= 0) pm.base.triangles.push_back(m);
  }
  if (pm.base.n_faces() != base.n_faces())
    throw std::runtime_error("simplify_compatible: " + std::to_string(pm.base.n_faces()) +
                             " base faces without the caps, the base has " +
                             std::to_string(base.n_faces()));
  for (std::size_t i = 0; i < base.n_vertices(); ++i)
    pm.base_vertices.push_back(map(capped.base_vertices[i]));
  pm.splits.reserve(capped.splits.size());
  for (const VertexSplit& s : capped.splits) {
    const VertexSplit m{map(s.vs), map(s.vt), map(s.vl), map(s.vr), s.position};
    if (m.vs < 0 || m.vt < 0)
      throw std::runtime_error("simplify_compatible: a loop's centre was collapsed");
    pm.splits.push_back(m);
  }
  pm.relaxed_collapses = capped.relaxed_collapses;
  return pm;
}

}  // namespace

std::array<ProgressiveMesh, 2> simplify_compatible(const CompatibleNetworks& networks,
                                                   const SimplifyOptions& options) {
  // Both surfaces side by side; progress follows A's.
  std::array<ProgressiveMesh, 2> out;
  auto simplify = [&](int s) {
    SimplifyOptions side = options;
    if (s) side.progress = nullptr;
    if (networks.capped.loops == 0) {
      out[s] = simplify_constrained(networks.networks[s], networks.base, side);
      return;
    }
    const ProgressiveMesh capped =
        simplify_constrained(networks.capped.networks[s], networks.capped.base, side);
    out[s] = drop_caps(capped, networks.networks[s], networks.base, networks.capped.loops);
  };
  tbb::parallel_invoke([&] { simplify(0); }, [&] { simplify(1); });
  return out;
}

}  // namespace ism
