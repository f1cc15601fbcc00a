#include "sample/geometry_image_file.hpp"

#include "io/image_io.hpp"
#include "io/io.hpp"

namespace ism {

void write_geometry_image(const GeometryImage& image, const std::filesystem::path& path) {
  std::vector<Eigen::Vector3f> pixels(image.pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = image.pixels[i].cast<float>();
  io::write_exr_rgb(path, image.n, image.n, pixels,
                    {{"ism:layout", "octahedral"}, {"ism:version", ISM_VERSION}});
}

GeometryImage read_geometry_image(const std::filesystem::path& path) {
  int width = 0, height = 0;
  const std::vector<Eigen::Vector3f> pixels = io::read_exr_rgb(path, width, height);
  if (width != height || !is_geometry_image_size(width))
    throw io::FileError(path.string() + ": " + std::to_string(width) + "x" +
                        std::to_string(height) +
                        " is not an octahedral geometry image (square, 2^k+1 pixels)");
  GeometryImage image;
  image.n = width;
  image.pixels.reserve(pixels.size());
  for (const auto& p : pixels) image.pixels.push_back(p.cast<double>());
  return image;
}

TriangleMesh read_geometry_image_mesh(const std::filesystem::path& path) {
  return image_to_mesh(read_geometry_image(path));
}

}  // namespace ism
