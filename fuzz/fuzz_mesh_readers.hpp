#pragma once
// One libFuzzer entry per mesh format: the bytes as a file of that format.
// A FileError is the reader refusing the input, which is fine; anything else
// (a crash, a sanitizer report, a hang, an allocation past the fuzzer's
// limits, another exception type) is a finding.
#include "io/io.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

inline int fuzz_mesh_reader(const std::uint8_t* data, std::size_t size,
                            ism::io::MeshFormat format) {
  try {
    const ism::PolygonSoup soup = ism::io::parse_polygon_soup(
        std::string_view(reinterpret_cast<const char*>(data), size), format, "fuzz");
    // The contract the rest of the library relies on.
    for (const auto& face : soup.faces)
      for (int v : face)
        if (v < 0 || std::size_t(v) >= soup.positions.size()) __builtin_trap();
    if (soup.faces.empty()) __builtin_trap();
  } catch (const ism::io::FileError&) {
  }
  return 0;
}
