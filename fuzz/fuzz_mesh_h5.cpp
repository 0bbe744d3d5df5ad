// libFuzzer target: the mesh.h5 reader on arbitrary bytes (HDF5 files with wrong shapes, indices
// out of range, NaN coordinates, missing groups). Inputs may only be rejected with InputError.
#include <cstdint>

#include "common/error.hpp"
#include "fuzz_input.hpp"
#include "preprocess/mesh_io.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Silence the HDF5 library's own error stack printing; the reader reports errors itself.
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace adamss;
  const auto path = fuzz::write_input(data, size, ".h5");
  try {
    (void)preprocess::read_mesh_h5(path);
  } catch (const InputError&) {
  }
  return 0;
}
