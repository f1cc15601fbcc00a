#pragma once
// Progressive meshes (Hoppe 1996) by half-edge collapses: the kept vertex
// keeps its position, so every vertex of a coarse level is a vertex of the
// input, and replaying the recorded vertex splits rebuilds the input exactly.
#include "mesh/triangle_mesh.hpp"
#include "partition/compatible_networks.hpp"
#include "partition/partition.hpp"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ism {

/// Inverse of the half-edge collapse vs -> vt: vertex vs reappears at
/// `position`, splitting vt; vl and vr are the third corners of the two faces
/// that the split creates, (vs, vt, vl) and (vt, vs, vr), counter-clockwise.
/// On the boundary of an open surface (simplify_compatible) one of vl, vr is
/// -1 and only the other face appears: the fan that moves to vs runs from
/// the existing wing to the boundary.
struct VertexSplit {
  int vs, vt, vl, vr;
  Vec3 position;
};

struct ProgressiveMesh {
  /// All vertices of the full-resolution mesh (indices as in the input),
  /// with the base mesh's faces only: vertices not yet split in are unused.
  TriangleMesh base;
  /// Vertex i of the base domain is base.triangles' vertex base_vertices[i].
  std::vector<int> base_vertices;
  /// In refinement order: splits[0] is the first split applied to the base.
  std::vector<VertexSplit> splits;
  /// Collapses that had to flip a face normal (or make a face degenerate)
  /// because no flip-free collapse was left; their splits undo the flip.
  std::size_t relaxed_collapses = 0;
};

/// Which collapse goes first.
enum class SimplifyPriority {
  /// Garland-Heckbert quadric error: keeps the shape, triangles may be long
  /// and thin where the surface is flat.
  quadric,
  /// Smallest merged region first (the input surface area that the two
  /// vertices stand for), divided by the squared shape quality of the
  /// triangles the collapse leaves: even, nearly equilateral faces. Base domains want this: their
  /// faces are mapped as equilateral
  /// triangles, so a base face's shape and size bound the map's stretch.
  isotropic,
};

struct SimplifyOptions {
  std::function<void(double)> progress;  // fraction of collapses done
  SimplifyPriority priority = SimplifyPriority::quadric;
  /// isotropic only: how strongly a collapse is postponed when it moves the
  /// valences it changes away from 6 (a base vertex of valence k becomes a
  /// cone of k·60° in an equilateral domain). 0 ignores valences.
  double valence_weight = 0.0;
  /// isotropic only: aim each vertex at the valence whose cone matches the
  /// Gaussian curvature of the surface it stands for (6 − 3K/π) instead of 6.
  bool valence_from_curvature = false;
};

/// Simplifies the network's surface down to a base mesh with exactly the
/// domain's faces: base vertex i is features[i], faces as in `domain`
/// (same orientation). Collapses keep the network: features stay, a path
/// vertex collapses only along its own path, no collapse joins two paths or
/// changes a patch's topology; link condition; no normal flips while that
/// is possible. base.triangles[f] is domain face f with each domain vertex i
/// replaced by features[i] (same rotation). Throws std::runtime_error if the
/// network is inconsistent or the base cannot be reached.
ProgressiveMesh simplify_constrained(const PathNetwork& network, const TriangleMesh& domain,
                                     const SimplifyOptions& options = {});

/// Unconstrained quadric simplification of a closed manifold mesh down to
/// `target_vertices` vertices (makes base meshes for tests and for
/// `semireg --base-size`). Same topology as the input. Stops with more
/// vertices than asked when no legal collapse is left (e.g. below the
/// minimum vertex count of the input's genus). Base vertices are the
/// remaining ones in increasing index order. Throws std::runtime_error if the
/// mesh is not a closed manifold (or has unreferenced vertices).
ProgressiveMesh simplify_to(const TriangleMesh& mesh, std::size_t target_vertices,
                            const SimplifyOptions& options = {});

/// simplify_to() for a surface whose boundary loops are capped
/// (cap_boundary_loops(), a fan per loop): the loop centres stay and each
/// loop is kept as a closed path of at least 3 vertices (its vertices
/// collapse only into their loop neighbours), so dropping the faces at the
/// centres from the base leaves a base with the surface's loops, every base
/// vertex a vertex of the input. `target_vertices` counts the centres. With
/// max_loop_span > 0 no base boundary edge spans more than that many edges
/// of its input loop (the base keeps more loop vertices where needed).
/// Either way no base boundary edge spans both ends of an input edge that
/// joins two vertices of its loop (an ear's tip stays a base vertex).
/// Throws std::runtime_error as simplify_to() does, or for a loop shorter
/// than 3 or a vertex given twice.
ProgressiveMesh simplify_capped_to(const TriangleMesh& mesh,
                                   const std::vector<std::vector<int>>& loops,
                                   const std::vector<int>& centres, std::size_t target_vertices,
                                   const SimplifyOptions& options = {},
                                   std::size_t max_loop_span = 0);

/// The base of simplify_capped_to() without its caps: the faces at the
/// `centres` last base vertices dropped. Vertex i of `mesh` is input vertex
/// vertices[i]; the mesh has the capped surface's loops as boundary loops.
struct UncappedBase {
  TriangleMesh mesh;
  std::vector<int> vertices;
};
UncappedBase uncapped_base(const ProgressiveMesh& pm, std::size_t centres);

/// Progressive meshes of two surfaces to one base (paper §3 step 2): the
/// constrained simplification of each network. Base vertex i of both is
/// features[i] (base_vertices[i] = features[i].vertex[s]) and both bases
/// have the faces of `networks.base`, in its order and orientation. Open
/// surfaces are simplified with their loops capped (networks.capped); the
/// caps are then dropped, so both progressive meshes rebuild the surfaces of
/// networks.networks exactly, their boundary splits having one wing (-1).
/// Throws std::runtime_error as simplify_constrained does.
std::array<ProgressiveMesh, 2> simplify_compatible(const CompatibleNetworks& networks,
                                                   const SimplifyOptions& options = {});

/// The mesh after applying the first `count` splits (all by default), with
/// unused vertices kept in place so that indices match the input. Throws
/// std::runtime_error if a split does not fit the mesh it is applied to.
TriangleMesh replay(const ProgressiveMesh& pm, std::size_t count = SIZE_MAX);

/// The base mesh alone, re-indexed so that vertex i is base_vertices[i].
TriangleMesh base_mesh(const ProgressiveMesh& pm);

}  // namespace ism

namespace ism {

/// Why replaying all of pm's splits does not give `surface` back (faces as
/// sets up to rotation, positions bit for bit), or nothing when it does.
std::optional<std::string> replay_mismatch(const ProgressiveMesh& pm, const TriangleMesh& surface);

}  // namespace ism
