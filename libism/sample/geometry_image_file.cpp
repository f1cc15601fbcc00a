#include "sample/geometry_image_file.hpp"

#include "io/image_io.hpp"
#include "io/io.hpp"

namespace ism {

namespace {

// Positions as float RGB pixels, tagged with their layout.
void write_positions(const std::filesystem::path& path, int width, int height,
                     const std::vector<Vec3>& positions, const std::string& layout,
                     const std::vector<float>& alpha = {}) {
  std::vector<Eigen::Vector3f> pixels(positions.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = positions[i].cast<float>();
  io::write_exr_rgb(path, width, height, pixels,
                    {{"ism:layout", layout}, {"ism:version", ISM_VERSION}}, alpha);
}

std::vector<Vec3> read_positions(const std::filesystem::path& path, int& width, int& height,
                                 std::vector<float>* alpha = nullptr) {
  const std::vector<Eigen::Vector3f> pixels = io::read_exr_rgb(path, width, height, nullptr, alpha);
  std::vector<Vec3> positions;
  positions.reserve(pixels.size());
  for (const auto& p : pixels) positions.push_back(p.cast<double>());
  return positions;
}

}  // namespace

void write_geometry_image(const GeometryImage& image, const std::filesystem::path& path) {
  write_positions(path, image.n, image.n, image.pixels, "octahedral", image.alpha);
}

GeometryImage read_geometry_image(const std::filesystem::path& path) {
  int width = 0, height = 0;
  GeometryImage image;
  std::vector<Vec3> positions = read_positions(path, width, height, &image.alpha);
  if (width != height || !is_geometry_image_size(width))
    throw io::FileError(path.string() + ": " + std::to_string(width) + "x" +
                        std::to_string(height) +
                        " is not an octahedral geometry image (square, 2^k+1 pixels)");
  image.n = width;
  image.pixels = std::move(positions);
  return image;
}

TriangleMesh read_geometry_image_mesh(const std::filesystem::path& path) {
  return image_to_mesh(read_geometry_image(path));
}

void write_torus_image(const TorusGrid& grid, const std::filesystem::path& path) {
  write_positions(path, grid.columns, grid.rows, grid.points, "torus");
}

TorusGrid read_torus_image(const std::filesystem::path& path) {
  TorusGrid grid;
  grid.points = read_positions(path, grid.columns, grid.rows);
  if (!is_torus_grid_size(grid.columns, grid.rows))
    throw io::FileError(path.string() + ": " + std::to_string(grid.columns) + "x" +
                        std::to_string(grid.rows) +
                        " is not a torus grid image (at least 3x3 pixels)");
  return grid;
}

}  // namespace ism
