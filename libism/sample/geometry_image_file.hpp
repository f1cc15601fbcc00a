#pragma once
// Geometry images as files: float RGB OpenEXR with the layouts of sample.hpp
// (octahedral) and torus_grid.hpp (periodic). Part of the ism_formats
// library (it needs OpenEXR).
#include "sample/sample.hpp"
#include "sample/torus_grid.hpp"

#include <filesystem>

namespace ism {

/// Writes positions as a float RGB EXR tagged "ism:layout" = "octahedral",
/// with the image's alpha as channel A when it has one.
void write_geometry_image(const GeometryImage& image, const std::filesystem::path& path);

/// Reads a square 2^k+1 float RGB EXR (and its channel A into alpha, if
/// any); throws io::FileError otherwise.
GeometryImage read_geometry_image(const std::filesystem::path& path);

/// The mesh an octahedral geometry image file describes (image_to_mesh).
TriangleMesh read_geometry_image_mesh(const std::filesystem::path& path);

/// Writes a torus grid as its periodic geometry image: V rows × U columns of
/// float RGB pixels, pixel (row j, column i) = grid point (j, i) (no repeated
/// row or column), tagged "ism:layout" = "torus".
void write_torus_image(const TorusGrid& grid, const std::filesystem::path& path);

/// Reads a periodic geometry image back as a torus grid; throws
/// io::FileError unless its size is a torus grid size.
TorusGrid read_torus_image(const std::filesystem::path& path);

}  // namespace ism
