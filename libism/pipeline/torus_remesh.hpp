#pragma once
// torus-remesh's pipeline (paper §6.4): a valence-4 remesh of a closed genus-1
// surface. Nine features (given, or chosen from the surface's flat-torus
// structure) are joined by a consistent path network with the connectivity of
// the flat 3×3 torus domain::torus_3x3(), the map from that torus (faces right
// isosceles, the unit square's metric) to the surface is optimised with the
// features released, and the unit square is sampled on a periodic U×V grid: a
// closed quad mesh in which every vertex has valence 4 (layout in
// sample/torus_grid.hpp). The command-line tool and the Python module both run it.
#include "io/draco_io.hpp"
#include "io/features.hpp"
#include "mesh/quad_mesh.hpp"
#include "sample/torus_grid.hpp"
#include "tool/map_stage.hpp"
#include "tool/tool.hpp"

#include <string>

namespace ism::pipeline {

/// torus-remesh's options, with its defaults (README, "Torus grids").
struct TorusRemeshOptions {
  tool::InputMesh input;       // the closed genus-1 surface
  io::FeatureSource features;  // 9 vertices, row-major in the 3×3 grid; empty: automatic
  std::string size = "128";    // "N" (N×N) or "UxV"
  bool triangulate = false;    // write two triangles per grid quad (.glb always does)
  bool no_global_reembedding = false;
  // Vertices of folded grid triangles re-sampled at nearby parameter points
  // (unfold_torus_grid(), for every variant scored and for the output);
  // off (--grid-points): every vertex at its grid point.
  bool unfold = true;
  // Files written when named: the grid (quads as .obj .ply .off; triangles
  // also as .stl .drc; .glb triangles), the periodic geometry image (.exr),
  // the PLY of the patches.
  std::string output, image, dump_patches;
  io::MeshFileOptions mesh_file;
  // The one-way weight folds fewer grid triangles on most models (teapot
  // 49 -> 22) and the symmetric energy on others (rocker_arm 9 -> 0).
  // When one of them folds grid triangles, the same two with an anisotropy
  // penalty (ratio of singular values past 3) are refined too and compete:
  // the folds sit where a skinny image of the grid cells crosses a bend of
  // the surface (teapot 16 -> 0, mug 13 -> 0, cup 18 -> 0, rocker_arm's
  // one-way variant 6 -> 0); elsewhere the penalty would only cost stretch
  // (knot 0.251 -> 0.202).
  tool::MapSettings map{
      .variants = {{.inverse_stretch_weight = 0.1}, {}},
      .fallback_variants = {
          {.inverse_stretch_weight = 0.1, .anisotropy_weight = 0.1, .anisotropy_threshold = 3},
          {.anisotropy_weight = 0.1, .anisotropy_threshold = 3}}};
};

struct TorusRemeshResult {
  TorusGrid grid;          // the U×V samples (the periodic geometry image)
  QuadMesh quads;          // torus_grid_mesh(grid)
  TriangleMesh triangles;  // torus_grid_triangles(grid)
};

/// Runs torus-remesh in `run` (stages, progress, report, the files named in
/// `options`; run.finish() is the caller's). Throws tool::Failure with the
/// tool's one-line message (kinds as gim_remesh()). No file is left partial.
TorusRemeshResult torus_remesh(tool::Run& run, const TorusRemeshOptions& options);

}  // namespace ism::pipeline
