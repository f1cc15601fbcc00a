// Bumpy star-shaped sphere.
#include "shapes/shapes.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace ism::shapes {
namespace {

struct Bump {
  Vec3 centre;       // unit direction
  double amplitude;  // radial offset at the centre
  double width;      // angular falloff: exp(-(1 - d.centre) / width)
};

// Our own conversion of the 64-bit draws (std::uniform_real_distribution is
// implementation-defined), so a seed gives the same blob on every platform.
std::vector<Bump> random_bumps(std::uint64_t seed, double bumpiness) {
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return double(rng() >> 11) * 0x1.0p-53; };  // [0, 1)
  std::vector<Bump> bumps(6 + rng() % 5);
  double dent = 0.0;  // sum of the negative amplitudes
  for (Bump& b : bumps) {
    // One draw per statement: the order of calls within an expression is unspecified.
    const double z = 2.0 * uniform() - 1.0;
    const double angle = 2.0 * M_PI * uniform();
    const double s = std::sqrt(1.0 - z * z);
    b.centre = Vec3(s * std::cos(angle), s * std::sin(angle), z);
    // Clear bumps, a third of them dents: |a| in [0.4, 1] * bumpiness.
    b.amplitude = bumpiness * (0.4 + 0.6 * uniform());
    if (uniform() < 1.0 / 3.0) b.amplitude = -b.amplitude;
    b.width = 0.05 + 0.2 * uniform();
    if (b.amplitude < 0) dent -= b.amplitude;
  }
  // Even if all dents overlap, r = 1 - dent must stay >= 0.4 (> 0.3).
  if (dent > 0.6)
    for (Bump& b : bumps)
      if (b.amplitude < 0) b.amplitude *= 0.6 / dent;
  return bumps;
}

}  // namespace

TriangleMesh blob(int target_faces, std::uint64_t seed, double bumpiness) {
  const std::vector<Bump> bumps = random_bumps(seed, bumpiness);
  TriangleMesh mesh = sphere(target_faces);
  // A face (p0, p1, p2) = (r0 d0, r1 d1, r2 d2) has normal.centroid =
  // det(p0, p1, p2) = r0 r1 r2 det(d0, d1, d2) > 0 for any radii r > 0, so every
  // face keeps facing outward and the surface stays a radial graph (embedded).
  for (Vec3& d : mesh.positions) {
    double r = 1.0;
    for (const Bump& b : bumps) r += b.amplitude * std::exp(-(1.0 - d.dot(b.centre)) / b.width);
    d *= r;
  }
  return mesh;
}

}  // namespace ism::shapes
