#pragma once
// Consistent partition of two surfaces (paper §3 step 1, §4): path
// networks on surfaces A and B with the same connectivity and the same cyclic
// order of paths around every feature, cutting both into one disc per face of
// one common base mesh. The base's connectivity is free: it grows from the
// feature pairs, greedily by the summed length of the two paths of a pair.
#include "partition/partition.hpp"

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ism {

/// Where a feature pair comes from.
enum class FeatureOrigin {
  given,      // the caller's pairs, in their order
  automatic,  // added before tracing: too few for the surfaces' genus
  cycle,      // added on a non-separating cycle that would close on one
              // feature or join two joined features (paper §4)
  split,      // added on a splitting path between two joined features
  clip,       // where a path to a boundary loop's centre met the loop
};
const char* to_string(FeatureOrigin origin);

/// One vertex of the common base: vertex[0] on A, vertex[1] on B (indices of
/// networks[0].surface and networks[1].surface; given and automatic features
/// are vertices of the input surfaces, added ones may be Steiner vertices).
struct FeaturePair {
  std::array<int, 2> vertex{-1, -1};
  FeatureOrigin origin = FeatureOrigin::given;
};

struct CompatibleOptions {
  /// Progress callback (fraction of the base's edges traced; may be empty).
  std::function<void(double)> progress;
  /// Candidate paths join each feature to this many nearest features.
  int nearest = 10;
  /// The paper's heuristics against swirls: paths at extremities first, paths
  /// passing a neighbouring feature on different sides on A and B wait, and
  /// when only those are left the best is re-routed on the side it has on the
  /// other surface.
  bool swirl_heuristics = true;
  /// Names of the two surfaces in messages (e.g. their files).
  std::array<std::string, 2> names{"A", "B"};
};

/// The networks on closed copies of the surfaces in which every boundary
/// loop is capped by a fan around a centre vertex (paper §4). Empty for
/// closed surfaces.
struct CappedNetworks {
  /// The base and one triangle fan per loop: vertex i < the base's count is
  /// base vertex i, then the loops' centres.
  TriangleMesh base;
  /// On the capped surfaces: the input's vertices, then one centre per loop,
  /// then the Steiner vertices of networks[s] in the same order.
  std::array<PathNetwork, 2> networks;
  std::size_t loops = 0;
};

struct CompatibleNetworks {
  /// The common base mesh: vertex i is features[i] (at its position on A),
  /// faces counter-clockwise on both surfaces, open where they are open.
  TriangleMesh base;
  std::vector<FeaturePair> features;
  /// The network on A and on B, both with `base` as domain: same domain
  /// edges, paths in the same cyclic order around every feature, patch f of
  /// each is base face f. Surfaces with boundaries: the loops are cut into
  /// paths between the clip features and are base edges too.
  std::array<PathNetwork, 2> networks;
  CappedNetworks capped;

  int genus = 0;
  std::size_t boundary_loops = 0;
  /// Search statistics: candidate pairs traced, pairs whose two shortest
  /// paths left or entered a feature in different sectors (traced again with
  /// each side's sectors imposed on the other), paths that waited for being
  /// on the wrong side of a neighbouring feature, and re-routings.
  std::size_t candidates_traced = 0, sector_conflicts = 0, swirl_delays = 0, reroutes = 0;
};

/// Traces compatible networks on surfaces `a` and `b` (closed or with
/// boundary loops, one connected orientable manifold each, of the same genus
/// and number of loops) through the given feature pairs ({vertex of a, vertex
/// of b}, possibly none). Features are added where needed: up to four on a
/// genus-0 surface (at least one on any other), by a fixed rule (farthest
/// from the features there are, matched by their distances to those), and
/// during tracing as the paper adds them. Boundary loops correspond through
/// the pairs on them, or by themselves when that is unambiguous (one loop,
/// or loops of clearly different lengths). Throws PartitionError (one line)
/// for mismatched topology, bad or repeated pair vertices, a pair joining a
/// boundary vertex to an interior one, boundary features in different orders
/// along corresponding loops, or a network that cannot be completed.
CompatibleNetworks trace_compatible_networks(const TriangleMesh& a, const TriangleMesh& b,
                                             const std::vector<std::array<int, 2>>& pairs,
                                             const CompatibleOptions& options = {});

/// Checks both networks against the base (validate_network), that they have
/// the same paths and features, and that the base is a manifold mesh without
/// repeated edges or faces. Returns the first problem, or nothing.
std::optional<std::string> validate_compatible(const CompatibleNetworks& networks);

/// Writes both networks for looking at them (write_patch_dump): the same
/// colour on both is the same base face.
void write_compatible_dumps(const CompatibleNetworks& networks, const std::filesystem::path& a,
                            const std::filesystem::path& b);

}  // namespace ism
