// libFuzzer target: meta-mesh files (README "Meta-mesh files"), read and then
// validated, as the reader's contract asks before any use.
#include "fuzz_file.hpp"
#include "io/io.hpp"
#include "map/meta_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const FuzzFile file(data, size);
  try {
    const ism::MetaMesh meta = ism::read_meta_mesh(file.path());
    if (!ism::validate(meta)) ism::measures(meta);
  } catch (const ism::io::FileError&) {
  }
  return 0;
}
