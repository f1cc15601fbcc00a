#pragma once
// The map core: the meta-mesh between a refining surface and a coarse
// domain, its local operations, validation, measures and queries.
#include "map/domain_geometry.hpp"
#include "map/flat_torus_overlay.hpp"
#include "map/meta_mesh.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "map/overlay.hpp"
#include "map/surface_map.hpp"
