#include "io/io.hpp"
#include "partition/partition.hpp"

#include <cmath>

namespace ism {

namespace {

// Well-separated hues by the golden angle, so neighbouring patch indices
// get clearly different colours.
io::Rgb patch_colour(int patch) {
  const double hue = std::fmod(patch * 0.618033988749895, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  double r = 0, g = 0, b = 0;
  switch (int(hue)) {
    case 0:
      r = 1, g = x;
      break;
    case 1:
      r = x, g = 1;
      break;
    case 2:
      g = 1, b = x;
      break;
    case 3:
      g = x, b = 1;
      break;
    case 4:
      r = x, b = 1;
      break;
    default:
      r = 1, b = x;
      break;
  }
  auto channel = [](double c) { return static_cast<unsigned char>(80 + 160 * c); };
  return {channel(r), channel(g), channel(b)};
}

}  // namespace

void write_patch_dump(const PathNetwork& network, const std::filesystem::path& path) {
  std::vector<io::Rgb> vertex(network.surface.n_vertices(), io::Rgb{200, 200, 200});
  for (const auto& p : network.paths)
    for (int v : p) vertex[v] = {40, 40, 40};
  for (int f : network.features) vertex[f] = {230, 20, 20};
  std::vector<io::Rgb> face(network.surface.n_faces());
  for (std::size_t f = 0; f < face.size(); ++f) face[f] = patch_colour(network.face_patch[f]);
  io::write_colored_ply(network.surface, vertex, face, path);
}

}  // namespace ism
