// libFuzzer target: feature (and landmark) files, parsed and resolved on a
// small surface, as gim-remesh, torus-remesh and semireg do.
#include "domain/domain.hpp"
#include "io/features.hpp"
#include "io/io.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ism::TriangleMesh surface = ism::domain::octahedron();
  try {
    const auto entries = ism::io::parse_feature_text(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    for (const int columns : {0, 3, int(entries.size())}) {
      try {
        const std::vector<int> features =
            ism::io::resolve_features(entries, surface, columns, "fuzz");
        for (int v : features)
          if (v < 0 || v >= int(surface.n_vertices())) __builtin_trap();
      } catch (const ism::io::FileError&) {
      }
    }
  } catch (const ism::io::FileError&) {
  }
  return 0;
}
