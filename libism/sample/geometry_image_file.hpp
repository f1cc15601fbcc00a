#pragma once
// Geometry images as files: float RGB OpenEXR with the layout of sample.hpp.
// Part of the ism_formats library (it needs OpenEXR).
#include "sample/sample.hpp"

#include <filesystem>

namespace ism {

/// Writes positions as a float RGB EXR tagged "ism:layout" = "octahedral".
void write_geometry_image(const GeometryImage& image, const std::filesystem::path& path);

/// Reads a square 2^k+1 float RGB EXR; throws io::FileError otherwise.
GeometryImage read_geometry_image(const std::filesystem::path& path);

/// The mesh an octahedral geometry image file describes (image_to_mesh).
TriangleMesh read_geometry_image_mesh(const std::filesystem::path& path);

}  // namespace ism
