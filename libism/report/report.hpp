#pragma once
// Reports: the JSON value and the sections every tool shares.
#include "map/surface_map.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"
#include "partition/partition.hpp"
#include "pm/pm.hpp"
#include "refine/refine.hpp"
#include "refine/refine_surfaces.hpp"
#include "report/json.hpp"

namespace ism {

/// The check of an input mesh: sizes, topology, defects, repairs.
Json to_json(const MeshCheck& check);

/// The "partition" section: features, Steiner vertices, patches (face count
/// and Euler characteristic of each), total path length, base mesh V/E/F.
Json partition_report(const PathNetwork& network, const TriangleMesh& domain,
                      const ProgressiveMesh& pm);

/// The "partition" section of a two-surface partition: genus, loops,
/// features given and added (each added one with its vertex on A and B and
/// its origin), base V/E/F, and per surface its size, Steiner vertices, path
/// length and progressive mesh.
Json compatible_partition_report(const CompatibleNetworks& networks,
                                 const std::array<ProgressiveMesh, 2>& pms);

/// The "map" section: validity, size, symmetric and one-way efficiencies (m,
/// from map.measures()), optimisations and the fast-path fraction. The map must have
/// passed validate().
Json map_report(const SurfaceMap& map, const MapMeasures& m, const RefineStats& stats);
/// The same for a map on the symmetric core (its side 1 the surface): faces
/// of each side, efficiencies, and what the operations did.
Json map_report(const InterSurfaceMap& map, const MapMeasures& m, const SurfaceRefineStats& stats);
/// Where a refinement on the symmetric core spent its wall time
/// ("seconds_by_operation": the optimisations committed by chart kind, the
/// splits, the local discs, and the planning of optimisations ahead on
/// several threads, whose commits count by chart) and, when `map` is given,
/// how its plans fared ("plans": held, optimised anew).
Json refine_timing(const SurfaceRefineStats& stats, const InterSurfaceMap* map);
/// The "map" section of a map between two surfaces (side 0 A, side 1 B):
/// faces [A, B], the symmetric efficiency and symmetric Dirichlet energy (=
/// 4 / efficiency, both areas scaled to 1), both one-way efficiencies, the
/// refinement's time and what the operations did. The map must have passed
/// validate().
Json two_surface_map_report(const InterSurfaceMap& map, const MapMeasures& m,
                            const SurfaceRefineStats& stats);

/// The "distance" section: PSNR, rms both ways and pooled, Hausdorff.
Json distance_report(const SurfaceDistance& distance);

}  // namespace ism
