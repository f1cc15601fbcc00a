#pragma once
// semireg's pipeline (paper §6.2): a semi-regular remesh of a surface of any
// genus, closed or with boundary loops, over a coarse base mesh (with as many
// loops). The base vertices are snapped to surface vertices, a consistent
// path network with the base's connectivity partitions the surface (holes
// capped, the boundary mapped onto the base's boundary edges), the map from
// the base (faces equilateral) to the surface is optimised, every base face
// is sampled on the barycentric grid of 2^levels subdivisions (DESIGN.md §5)
// and the vertices of folded triangles re-sampled nearby. The command-line
// tool and the Python module both run it.
#include "io/draco_io.hpp"
#include "io/features.hpp"
#include "tool/map_stage.hpp"
#include "tool/tool.hpp"

#include <string>

namespace ism::pipeline {

/// semireg's options, with its defaults. Exactly one of base, base_vertices
/// and base_size gives the base.
struct SemiregOptions {
  tool::InputMesh input;            // the surface, closed or open
  tool::InputMesh base;             // a base mesh: vertices snapped, faces kept
  io::FeatureSource base_vertices;  // base vertices only, connected by their Voronoi regions
  std::size_t base_size = 0;        // decimate to a base of this many vertices (0: not)
  int levels = 4;                   // subdivisions of each base face: faces × 4^levels
  // Re-sample the vertices of folded remesh triangles at nearby points of
  // their base face or edge (unfold_semiregular()); off: every vertex at its
  // grid point.
  bool unfold = true;
  // Files written when named: the remesh, the base used (.obj .ply .off .stl
  // .drc .glb), the PLY of the patches.
  std::string output, write_base, dump_patches;
  io::MeshFileOptions mesh_file;
  tool::MapSettings map;  // one variant: symmetric energy, cone moves relaxed
};

struct SemiregResult {
  TriangleMesh remesh;  // the base's vertices first, then the edges' and faces' samples
  TriangleMesh base;    // the base used, its vertices the remesh's first ones
};

/// Runs semireg in `run` (stages, progress, report, the files named in
/// `options`; run.finish() is the caller's). Throws tool::Failure with the
/// tool's one-line message (kinds as gim_remesh()). No file is left partial.
SemiregResult semireg(tool::Run& run, const SemiregOptions& options);

}  // namespace ism::pipeline
