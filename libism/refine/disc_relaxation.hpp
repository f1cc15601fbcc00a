#pragma once
// Re-embedding discs of M² whole (paper §5.1's local re-embedding with
// several vertices placed at once), where the vertex-at-a-time moves are
// stuck: a region squeezed into a sliver of M¹ cannot be opened by moving
// one vertex, since each is confined by its squeezed neighbours
// (fandisk.obj's octahedral map kept three faces of domain area 2e-8 that
// held all but nothing of the energy).
#include "map/inter_surface_map.hpp"
#include "map/surface_map.hpp"
#include "refine/flat_reembedding.hpp"

#include <vector>

namespace ism {

/// Re-embeds the faces around `vertices` (SurfaceMap::disc_layout): their
/// free vertices start at their mean-value positions in the surface's
/// metric with the rest of the disc fixed (Floater 2003), if that lowers
/// the energy, else where they are, and descend together (descend_layout);
/// the result is installed if it validates and lowers the energy
/// (SurfaceMap::set_disc_layout). Returns the energy decrease.
double reembed_disc(SurfaceMap& map, const std::vector<int>& vertices,
                    const FlatDescentOptions& options = {200, 1e-6, 10, 8});

/// The same for the symmetric core's side 1 over side 0, where the disc
/// lies over one face of side 0 or two across their shared edge
/// (InterSurfaceMap::disc_layout; 0 otherwise), installed through
/// InterSurfaceMap::set_disc_layout.
double reembed_disc(InterSurfaceMap& map, const std::vector<int>& vertices,
                    const FlatDescentOptions& options = {200, 1e-6, 10, 8});

/// Re-embeds, worst first, discs around the faces whose energy exceeds
/// `outlier` × the mean face energy (at most `max_discs` of them): the
/// vertices within 1, 2, 4, then 8 rings of the face's corners until one
/// disc gains. Returns the energy decrease; `tried` and `applied` count the
/// discs. With `validate_each_step`, validate() after every disc (throws
/// std::runtime_error). Deterministic.
double disc_relaxation(SurfaceMap& map, double outlier, std::size_t max_discs, std::size_t& tried,
                       std::size_t& applied, bool validate_each_step = false);

}  // namespace ism
