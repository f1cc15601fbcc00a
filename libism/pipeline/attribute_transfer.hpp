#pragma once
// Attributes carried from one surface onto the vertices of another through a
// map's correspondence (the images of the target's vertices on the source,
// pipeline::input_correspondence): every value interpolated barycentrically
// in the source face holding the image.
#include "io/io.hpp"
#include "map/meta_mesh_sampler.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/polygon_soup.hpp"

#include <array>
#include <string>
#include <vector>

namespace ism::pipeline {

using Texcoord = std::array<double, 2>;

/// A per-vertex field of the source carried onto the target's vertices: row
/// i is the field interpolated at images[i] (faces: the source's triangles).
io::VertexField transfer_field(const io::VertexField& field, const std::vector<Triangle>& faces,
                               const std::vector<SurfacePoint>& images);

/// The texture coordinates of every corner of a prepared mesh's triangles,
/// from the soup it was prepared from (the corners of the face each triangle
/// came from): result[f][k] for corner k of triangle f. Throws
/// std::invalid_argument saying what is missing: no texture coordinates at
/// all, or how many triangles have a corner without one.
std::vector<std::array<Texcoord, 3>> corner_texcoords(const PolygonSoup& soup,
                                                      const PreparedMesh& prepared);

struct TexcoordTransfer {
  std::vector<Texcoord> texcoords;  // one per target vertex
  /// Target triangles whose corners' images lie in different texture charts
  /// of the source (faces joined across edges whose two ends keep their
  /// coordinates): their interpolated coordinates span a seam, so the
  /// texture is wrong inside them.
  std::size_t seam_triangles = 0;
};

/// The source's corner texture coordinates (corner_texcoords) carried onto
/// the target's vertices through `images` (images[i]: target vertex i on the
/// source); `target_faces` are the target's triangles (for seam_triangles).
TexcoordTransfer transfer_texcoords(const std::vector<Triangle>& source_faces,
                                    const std::vector<std::array<Texcoord, 3>>& corners,
                                    const std::vector<SurfacePoint>& images,
                                    const std::vector<Triangle>& target_faces);

/// The colours of a prepared mesh's vertices (RGB in [0, 1]), from the soup
/// it was prepared from (welded vertices: the first position's). Throws
/// std::invalid_argument when the soup has none.
io::VertexField vertex_colors(const PolygonSoup& soup, const PreparedMesh& prepared);

/// RGB fractions (a 3-column field) as 8-bit colours, rounded and clamped.
std::vector<io::Rgb> to_rgb(const io::VertexField& colours);

}  // namespace ism::pipeline
