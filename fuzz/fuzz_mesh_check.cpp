// libFuzzer target: the mesh checks (prepare_mesh and the messages built from
// them) on polygon soups decoded from the bytes: a vertex count, coordinates
// from a small palette (so that coincident, collinear, tiny, huge and
// non-finite points are common), then polygons of 1 to 6 corners. Any crash,
// sanitizer report or broken invariant of the prepared mesh is a finding.
#include "mesh/mesh_check.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace {

constexpr double kPalette[16] = {0.0,
                                 1.0,
                                 -1.0,
                                 0.5,
                                 2.0,
                                 -0.0,
                                 1e-300,
                                 1e300,
                                 3.0,
                                 1e-9,
                                 -2.5,
                                 1 + 1e-15,
                                 7.0,
                                 0.25,
                                 std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity()};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::size_t at = 0;
  auto next = [&]() -> unsigned { return at < size ? data[at++] : 0u; };
  ism::PolygonSoup soup;
  const unsigned n = 1 + next() % 64;
  for (unsigned v = 0; v < n; ++v) {
    ism::Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = kPalette[next() % 16];
    soup.positions.push_back(p);
  }
  while (at < size) {
    std::vector<int>& face = soup.faces.emplace_back();
    const unsigned corners = 1 + next() % 6;
    for (unsigned c = 0; c < corners; ++c) face.push_back(int(next() % n));
  }
  const ism::PreparedMesh prepared = ism::prepare_mesh(soup);
  const ism::MeshCheck& c = prepared.check;
  // Invariants of the result.
  if (prepared.mesh.n_faces() != c.faces || prepared.mesh.n_vertices() != c.vertices)
    __builtin_trap();
  for (const ism::Triangle& t : prepared.mesh.triangles)
    for (int v : t)
      if (v < 0 || std::size_t(v) >= prepared.mesh.n_vertices()) __builtin_trap();
  if (c.valid_surface() && !c.defects().empty()) __builtin_trap();
  c.repairs();
  c.warnings();
  for (const bool closed : {false, true})
    for (const int genus : {0, 1}) {
      ism::MeshRequirements needs{.tool = "fuzz", .closed = closed, .genus = genus};
      needs.min_vertices = 6;
      ism::unmet_requirement(c, needs);
    }
  return 0;
}
