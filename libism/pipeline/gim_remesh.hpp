#pragma once
// gim-remesh's pipeline (paper §6.3): a map from the octahedron, unfolded into
// the square, to a genus-0 surface, optimised for stretch and sampled on an
// n×n grid. The command-line tool and the Python module both run it.
//
// A surface with holes (boundary loops) is closed first: each loop capped by
// a fan around its centre (paper §4), cut by rings, the caps mapped as surface. The image
// then has an alpha channel (1 on the input surface, 0 on a cap), the remesh
// drops the grid triangles that touch a cap (open where the input is), and
// every measure is taken on the input surface alone (stretch weighted by its
// area, PSNR against it).
#include "io/draco_io.hpp"
#include "io/features.hpp"
#include "mesh/boundary.hpp"
#include "sample/sample.hpp"
#include "tool/map_stage.hpp"
#include "tool/tool.hpp"

#include <string>

namespace ism::pipeline {

/// gim-remesh's options, with its defaults (README, "Tools").
struct GimRemeshOptions {
  tool::InputMesh input;                   // a genus-0 surface, closed or not
  io::FeatureSource features;              // 6 vertices for +x -x +y -y +z -z; empty: automatic
  int size = 257;                          // n = 2^k+1
  std::string metric = "right-isosceles";  // or "equilateral"
  // Files written when named (through temporary names): the image (.exr),
  // the normal map (.exr), the remesh (.obj .ply .off .stl .drc .glb), the
  // PNG preview, the PNG mask (255 on the input surface, 0 on a cap), the
  // PLY of the patches.
  std::string output, normals, mesh, preview, mask, dump_patches;
  io::MeshFileOptions mesh_file;
  /// Pixels of folded grid triangles re-sampled at nearby square points
  /// (unfold_geometry_image(), closed surfaces; the normal map follows);
  /// off (--grid-points): every pixel at its grid point.
  bool unfold = true;
  /// How the holes of an open surface are closed (mesh/boundary.hpp): the
  /// paper's fan cut by 4 flat rings. Against the plain fan, one-way
  /// efficiency / PSNR (257², docs/results-open-surfaces.md): venus_loop2
  /// 0.850 / 83.4 -> 0.865 / 83.8 dB, head_3holes 0.872 / 80.8 -> 0.880 /
  /// 81.1, mannequin_devil 0.836 / 79.3 -> 0.847 / 79.6, camelhead
  /// 0.778 / 82.4 -> 0.777 / 82.6; a dome (height 0.5) takes more pixels
  /// (venus_loop2: PSNR 82.2), 8 rings folded venus_loop2 (0.838, 6 folds).
  CapOptions cap{.rings = 4};
  // Mostly the one-way stretch the image is judged by (bunny, regular
  // octahedron 0.660 -> 0.720), and the symmetric energy without cone
  // relaxation, which flat-faced models need (cube.obj 0.60 -> 0.86). The
  // image is judged by how closely it rebuilds the surface: spend samples
  // where the surface bends (bunny: PSNR 79.5 -> 80.0 dB for 0.771 -> 0.768
  // efficiency; equilateral metric, octahedron efficiency / PSNR: bunny
  // 0.721 / 80.0 -> 0.719 / 80.6, gargoyle 0.725 / 79.0 -> 0.718 / 79.6,
  // against the paper's 0.717 / 79.9 and 0.679 / 79.3).
  tool::MapSettings map{.variants = {{.inverse_stretch_weight = 0.1},
                                     {.inverse_stretch_weight = 1, .cone_relaxation_rings = 0}},
                        .curvature_weight = 0.5};
};

struct GimRemeshResult {
  GeometryImage image;    // surface positions (README, "Geometry image layout"), alpha if open
  GeometryImage normals;  // unit normals at the same samples
  TriangleMesh remesh;    // image_to_surface_mesh(image)
};

/// Runs gim-remesh in `run` (stages, progress, report, the files named in
/// `options`; run.finish() is the caller's). Throws tool::Failure with the
/// tool's one-line message: the input, an option or a feature file is
/// unsuitable (Kind::input), a file cannot be read or written (Kind::file),
/// the optimisation failed (Kind::internal). No file is left partial.
GimRemeshResult gim_remesh(tool::Run& run, const GimRemeshOptions& options);

}  // namespace ism::pipeline
