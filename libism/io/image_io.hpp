#pragma once
// Geometry images on disk: 32-bit float RGB OpenEXR (RGB = XYZ of the surface
// sample) and an 8-bit PNG preview to look at. The third-party headers stay in
// image_io.cpp so that including this file costs nothing.
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace ism::io {

/// String attributes stored in an EXR header, e.g. {"ism:layout", "octahedral"}.
using ExrAttributes = std::vector<std::pair<std::string, std::string>>;

/// Writes width x height float RGB pixels (row-major, row 0 at the top) as a
/// ZIP-compressed OpenEXR with 32-bit float channels R, G, B, adding each
/// attribute as a string attribute of the header. Throws std::invalid_argument
/// when the sizes disagree or an attribute name is empty or taken by a
/// standard attribute of another type ("compression", "channels", ...), and
/// FileError (message starting with the path) when the file cannot be written.
/// A non-empty `alpha` (one value per pixel) is written as a fourth float
/// channel A.
void write_exr_rgb(const std::filesystem::path& path, int width, int height,
                   const std::vector<Eigen::Vector3f>& pixels, const ExrAttributes& attributes = {},
                   const std::vector<float>& alpha = {});

/// Reads the R, G, B channels of an OpenEXR (any pixel type, converted to
/// float; 32-bit float files read back bit-exact), row-major with row 0 at the
/// top of the data window. When `attributes` is given it receives every string
/// attribute of the header, sorted by name. Throws FileError for a missing or
/// invalid file or a missing channel. Hostile files are refused before
/// OpenEXR opens them: the header is checked first (every attribute within
/// the file and, for the types OpenEXR reads by their structure, exactly
/// its declared size; no multi-part, deep or ID-manifest data), and a data
/// window, tile or offset table larger than the file's size can hold (at
/// most ~1100 decoded bytes per byte of file) is refused.
/// When `alpha` is given it receives channel A (converted to float), or is
/// left empty when the file has none.
std::vector<Eigen::Vector3f> read_exr_rgb(const std::filesystem::path& path, int& width,
                                          int& height, ExrAttributes* attributes = nullptr,
                                          std::vector<float>* alpha = nullptr);

/// Writes an 8-bit RGB PNG (always PNG, whatever the extension) through
/// OpenImageIO. Throws std::invalid_argument when the sizes disagree and
/// FileError when the file cannot be written.
void write_png_preview(const std::filesystem::path& path, int width, int height,
                       const std::vector<std::array<unsigned char, 3>>& pixels);

/// Writes an 8-bit greyscale PNG (e.g. a mask: 255 on, 0 off); throws as
/// write_png_preview.
void write_png_grey(const std::filesystem::path& path, int width, int height,
                    const std::vector<unsigned char>& pixels);

}  // namespace ism::io
