#pragma once
// Folded triangles of a sampled remesh undone by re-sampling their vertices
// a little off their grid points: the one loop behind unfold_semiregular()
// (semiregular.hpp), unfold_torus_grid() (torus_grid.hpp) and
// unfold_geometry_image() (sample.hpp). A remesh
// vertex is the map's image of its grid point; the map is a bijection, but
// straight triangles between samples can still fold where the map turns
// faster than the grid samples it (a sharp bend, a crease). Moving such a
// vertex to the image of a nearby parameter point keeps it on the surface
// and the connectivity untouched.
#include "mesh/triangle_mesh.hpp"

#include <cstddef>
#include <functional>
#include <vector>

namespace ism {

/// What an unfold did.
struct UnfoldReport {
  std::size_t folds_before = 0;    // flipped_faces() of the mesh as given
  std::size_t folds_after = 0;     // ... as returned
  std::size_t moved_vertices = 0;  // vertices sampled elsewhere than their grid point
};

struct UnfoldOptions {
  int max_rounds = 8;
  /// Among positions that fold as many triangles, prefer one that folds them
  /// less deeply (FoldTest::fold_depth summed): a fold that no single move
  /// undoes may yield to several (false: the number alone decides).
  bool by_depth = false;
};

/// Re-samples the vertices of folded triangles of `mesh` (the test of
/// flipped_faces(): a face whose normal opposes the sum of the area-weighted
/// normals of the faces sharing a vertex with it). For each vertex of a
/// folded triangle, `candidates(v, out)` fills `out` with the positions v
/// may take instead (each the map's image of a point near v's grid point;
/// the caller decides which, and may leave it empty; the same list each time
/// it is asked for v; one at a neighbour's position is skipped, so no two
/// vertices meet); the first candidate that lowers the number of folded
/// triangles v's position can change most is kept. Rounds over the remaining
/// folds repeat while any vertex moved, at most options.max_rounds. Only
/// positions change; a vertex is moved only to one of its candidates, so
/// every vertex stays a value of the caller's map. `chosen`, when given,
/// receives per vertex the index in its candidate list of the position it
/// holds (-1: not moved). Deterministic: vertices are visited in increasing
/// order, candidates in the order given.
UnfoldReport unfold_samples(TriangleMesh& mesh,
                            const std::function<void(int v, std::vector<Vec3>& out)>& candidates,
                            const UnfoldOptions& options = {}, std::vector<int>* chosen = nullptr);

}  // namespace ism
