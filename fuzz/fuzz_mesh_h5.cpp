// Fuzz target: the mesh.h5 reader on arbitrary bytes (HDF5 files with wrong shapes, indices out
// of range, NaN coordinates, missing groups). Inputs may only be rejected with InputError.
//
// read_mesh_h5 reads every file in a child process first (common/guarded_read.hpp): the libhdf5
// 1.10.8 crashes of fuzz/known-libhdf5/ are InputErrors, and so is its hang on a corrupted
// global heap after ADAMSS_HDF5_GUARD_SECONDS, set to 3 s here (the fuzzers' -timeout is 10 or
// 20 s). Inputs holding a global-heap collection (signature "GCOL") are still not run: each such
// hang would cost those 3 s, and files adamss writes have no global heap (fixed-length string
// attributes); known/hdf5-vlen-global-heap-hang.h5 is a unit test of the guard instead
// (MeshIoHostile.LibraryCrashesAndHangsAreInputErrors).
#include <algorithm>
#include <cstdint>
#include <cstdlib>
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
  static const bool guard_limit_set = setenv("ADAMSS_HDF5_GUARD_SECONDS", "3", 0) == 0;
  (void)guard_limit_set;
  if (has_global_heap(data, size)) return 0;
  const auto path = fuzz::write_input(data, size, ".h5");
  try {
    (void)preprocess::read_mesh_h5(path);
  } catch (const InputError&) {
  }
  return 0;
}
