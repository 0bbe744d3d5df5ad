// Fuzz target: the mesh.h5 reader on arbitrary bytes (HDF5 files with wrong shapes, indices out
// of range, NaN coordinates, missing groups). Inputs may only be rejected with InputError.
//
// Known-hang class, skipped: libhdf5 1.10 loops forever inside H5HG__protect on a corrupted
// global-heap collection (fuzz/README.md, known/hdf5-vlen-global-heap-hang.h5). Global heaps
// hold variable-length data, which files written by adamss no longer have (string attributes are
// fixed-length); an input containing a global heap collection (signature "GCOL") is not run, so
// neither libFuzzer nor the standalone driver spends its time (or CI's) rediscovering that hang.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "common/error.hpp"
#include "fuzz_input.hpp"
#include "preprocess/mesh/mesh_io.hpp"

namespace {
bool has_global_heap(const std::uint8_t* data, std::size_t size) {
  static const char kSignature[] = "GCOL";
  return std::search(data, data + size, kSignature, kSignature + 4) != data + size;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace adamss;
  if (has_global_heap(data, size)) return 0;
  const auto path = fuzz::write_input(data, size, ".h5");
  try {
    (void)preprocess::read_mesh_h5(path);
  } catch (const InputError&) {
  }
  return 0;
}
