// libFuzzer target: the STL reader (see fuzz_mesh_readers.hpp).
#include "fuzz_mesh_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_mesh_reader(data, size, ism::io::MeshFormat::stl);
}
