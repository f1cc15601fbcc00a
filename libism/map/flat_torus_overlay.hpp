#pragma once
// The symmetric core's map on a flat torus read as, and rebuilt from, a
// flat layout (FlatTorusLayout, surface_map.hpp): side 0 the unit-square
// torus of unit_square_layouts (its vertices 0..n-1 the domain's), side 1
// the surface. A layout places every side-1 vertex in R²/Z² and makes each
// side-1 face a straight triangle there; its overlay with the domain's
// straight faces is a map the symmetric core can continue from. This is how
// the global re-embedding (refine/flat_reembedding.hpp) moves every vertex
// at once on the symmetric core.
#include "map/domain_geometry.hpp"
#include "map/inter_surface_map.hpp"
#include "map/meta_mesh.hpp"
#include "map/surface_map.hpp"

#include <optional>

namespace ism {

/// Side 1 of `map` laid out in the flat torus `domain`: each active side-1
/// vertex at the point of its location in its domain face, each face's
/// corners lifted along the images of its edges (the lattice translations
/// of the faces those images cross), so the shifts are the map's homotopy
/// class. The layout's faces are the straight triangles between those
/// points: the map itself where no side-1 face holds a domain vertex or a
/// kink, its straightened version elsewhere, where a thin face may turn
/// over (untangle_layout). Nothing if the domain is not a flat unit-square
/// torus or not side 0's.
std::optional<FlatTorusLayout> flat_layout(const InterSurfaceMap& map,
                                           const DomainGeometry& domain);

/// The overlay of side 1's faces laid out by `layout` with the domain's
/// faces (both straight in the flat torus), on the two sides of `map` as
/// they are now: each side-1 vertex inside the domain face holding its
/// point, each domain vertex inside the side-1 face whose lifted triangle
/// holds it, every crossing of a side-1 edge with a domain edge recorded
/// with both parameters, no kinks. Nothing if the layout does not fit side
/// 1, a face of it is not counter-clockwise, or a point of one side lies on
/// an edge or vertex of the other (within 1e-12: a degenerate overlay). Not
/// validated here (InterSurfaceMap::replace_overlay does).
std::optional<MetaMesh> flat_torus_overlay(const InterSurfaceMap& map, const DomainGeometry& domain,
                                           const FlatTorusLayout& layout);

}  // namespace ism
