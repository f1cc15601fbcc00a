// libFuzzer target: OpenEXR images through read_exr_rgb (the geometry-image
// reader's first step).
#include "fuzz_file.hpp"
#include "io/image_io.hpp"
#include "io/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const FuzzFile file(data, size);
  try {
    int width = 0, height = 0;
    ism::io::ExrAttributes attributes;
    const auto pixels = ism::io::read_exr_rgb(file.path(), width, height, &attributes);
    if (width <= 0 || height <= 0 || pixels.size() != std::size_t(width) * std::size_t(height))
      __builtin_trap();
  } catch (const ism::io::FileError&) {
  }
  return 0;
}
