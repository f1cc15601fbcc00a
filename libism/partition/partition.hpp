#pragma once
// Consistent path network (paper §4): one path on the surface M² per edge of
// the domain M¹, meeting only at features, leaving each feature in the cyclic
// order M¹ prescribes, so that the paths cut M² into one disc per face of M¹.
#include "mesh/triangle_mesh.hpp"

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ism {

/// A network that cannot be built (bad features, unrealisable order); the
/// message says why in words a user can act on.
class PartitionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PathNetwork {
  /// M² with the Steiner vertices that paths needed: the input's vertices keep
  /// their indices, Steiner vertices (edge midpoints, inserted by edge splits)
  /// are appended after them. Faces are re-indexed.
  TriangleMesh surface;
  std::size_t original_vertices = 0;
  /// Surface vertex of domain vertex i.
  std::vector<int> features;
  /// Domain edges (a < b) and, for each, its path as surface vertices from
  /// features[a] to features[b].
  std::vector<std::array<int, 2>> domain_edges;
  std::vector<std::vector<int>> paths;
  /// Domain face of each surface face.
  std::vector<int> face_patch;
  /// Face of the traced surface (the tracer's input) each surface face lies
  /// in: Steiner vertices split faces, the pieces keep their origin. Filled
  /// by trace_path_network() and the tracers built on it; empty from
  /// trace_compatible_networks().
  std::vector<int> face_origin;

  std::size_t steiner_vertices() const { return surface.n_vertices() - original_vertices; }
  /// Total 3D length of the paths.
  double total_length() const;
};

struct PartitionOptions {
  /// Progress callback with the fraction of paths traced (may be empty).
  std::function<void(double)> progress;
  /// trace_octahedral_networks(): also try each antipodal pair as the poles
  /// (for metrics in which the poles differ from the equator).
  bool distinguish_poles = false;
  /// The paper's heuristics against swirls (§4): paths at the surface's
  /// extremities first (features whose mean distance to their 8 nearest
  /// features is in the top quarter: their paths count half their length),
  /// and a path that passes a neighbouring feature (third corner of one of
  /// its domain edge's two faces) on the other side than in M¹ waits until
  /// only such paths are left. Off by default: on the octahedral networks of
  /// gim-remesh they did not pay (bunny 16 -> 16 flipped triangles, dragon
  /// efficiency 0.569 -> 0.549, fandisk worse); on a torus the homotopy
  /// guide below decides the class exactly.
  bool swirl_heuristics = false;
  /// Homotopy guide for a domain that lives on the flat torus R²/Z² (such as
  /// domain::torus_3x3()): a point of that torus per surface vertex (a map
  /// of the surface to it, e.g. a harmonic one) and per domain vertex. When
  /// given, the path of domain edge (a, b) is the shortest one whose lift to
  /// the plane moves by the domain edge's own shortest displacement, so the
  /// network is in the map's homotopy class: no path winds around a handle
  /// more than the domain says (no swirls, no Dehn twists). Points count
  /// modulo 1; the points of neighbouring surface vertices must be less than
  /// half a period apart.
  std::vector<Eigen::Vector2d> surface_torus_points;
  std::vector<Eigen::Vector2d> domain_torus_points;
  /// trace_path_network(): domain edges (a, b) whose path is given as the
  /// surface edge between features[a] and features[b] (e.g. the boundary and
  /// cap edges of bounded_base()): taken before any traced path, when the
  /// order at their features allows, and that surface edge is never split.
  /// trace_path_network() throws PartitionError when the two features are
  /// not joined by an edge or (a, b) is not a domain edge.
  std::vector<std::array<int, 2>> direct_edges;
};

/// Traces the network of `domain`'s connectivity on `surface` between the
/// given features (features[i] is the surface vertex of domain vertex i).
/// Throws PartitionError for duplicate or out-of-range features, a wrong
/// count, a genus or boundary mismatch, or an order that cannot be realised.
PathNetwork trace_path_network(const TriangleMesh& surface, const TriangleMesh& domain,
                               const std::vector<int>& features,
                               const PartitionOptions& options = {});

/// Six well-separated surface vertices for the octahedron of
/// domain::octahedron() and the network they give: the valid assignment with
/// the shortest total path length among those tried.
PathNetwork trace_octahedral_network(const TriangleMesh& surface,
                                     const PartitionOptions& options = {});

/// Every valid octahedral network among the candidates tried (extremes of
/// the principal axes and geodesic farthest points, each in both
/// chiralities), shortest first; throws PartitionError when none is valid.
std::vector<PathNetwork> trace_octahedral_networks(const TriangleMesh& surface,
                                                   const PartitionOptions& options = {});

/// A base mesh on given surface vertices (sites) with free connectivity:
/// the dual of the sites' geodesic Voronoi regions (Dijkstra over the
/// surface's edges), each dual triangle oriented like the surface. Vertex i
/// is sites[i] at its position. Throws PartitionError for a bad or repeated
/// site, or when the dual is not a closed manifold of the surface's genus
/// (sites too sparse for the shape, or unevenly spread).
TriangleMesh delaunay_base(const TriangleMesh& surface, const std::vector<int>& sites);

/// Checks a network: every patch a disc bounded by the three paths of its
/// domain face with the same orientation, paths disjoint but at features.
/// An open surface and domain (compatible networks) may have boundaries: the
/// paths of the domain's boundary edges run along the surface's boundary,
/// which lies on paths everywhere. Returns the first problem found, or nothing.
std::optional<std::string> validate_network(const PathNetwork& network, const TriangleMesh& domain);

}  // namespace ism

namespace ism {

/// Writes the network for looking at it: an ASCII PLY with faces coloured by
/// patch, path vertices dark grey and features red.
void write_patch_dump(const PathNetwork& network, const std::filesystem::path& path);

}  // namespace ism
