// The overlay pair of an ism-map run checked as a user would, independently
// of the map code: both files hold the same faces, and each, placed on its
// surface, has every vertex on it, no triangle flipped against the face
// holding it and its areas (signed and not) equal to the surface's
// (metrics' overlay_on_surface) — a bijection.
//   overlay_check A B PREFIX
// reads A and B as the tools read them and PREFIX_on_A.obj, PREFIX_on_B.obj
// at full precision; prints one JSON line; exits 1 when a check fails.
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "metrics/metrics.hpp"

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: overlay_check A B PREFIX\n");
    return 2;
  }
  try {
    const ism::TriangleMesh a = ism::prepare_mesh(ism::io::read_polygon_soup(argv[1])).mesh;
    const ism::TriangleMesh b = ism::prepare_mesh(ism::io::read_polygon_soup(argv[2])).mesh;
    const std::string prefix = argv[3];
    const ism::TriangleMesh on_a = ism::io::read_triangles_exact(prefix + "_on_A.obj");
    const ism::TriangleMesh on_b = ism::io::read_triangles_exact(prefix + "_on_B.obj");
    const bool same = on_a.triangles == on_b.triangles && on_a.n_vertices() == on_b.n_vertices();
    const ism::OverlayOnSurface ca = ism::overlay_on_surface(on_a, a);
    const ism::OverlayOnSurface cb = ism::overlay_on_surface(on_b, b);
    const bool ok = same && ca.bijective() && cb.bijective();
    auto side = [](const ism::OverlayOnSurface& c) {
      char s[256];
      std::snprintf(s, sizeof s,
                    "{\"largest_distance\": %.3g, \"flipped\": %zu, \"signed_area_error\": %.3g, "
                    "\"unsigned_area_error\": %.3g}",
                    c.largest_distance, c.flipped, c.signed_area / c.surface_area - 1,
                    c.unsigned_area / c.surface_area - 1);
      return std::string(s);
    };
    std::printf(
        "{\"triangles\": %zu, \"same_connectivity\": %s, \"on_a\": %s, \"on_b\": %s, "
        "\"bijective\": %s}\n",
        on_a.n_faces(), same ? "true" : "false", side(ca).c_str(), side(cb).c_str(),
        ok ? "true" : "false");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "overlay_check: %s\n", e.what());
    return 2;
  }
}
