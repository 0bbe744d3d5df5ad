// libFuzzer target: the NIfTI readers (labels, scalars, vectors) on arbitrary bytes, as .nii and
// as .nii.gz. Inputs may only be rejected with adamss::InputError.
#include <cstdint>

#include "common/error.hpp"
#include "fuzz_input.hpp"
#include "preprocess/image/nifti_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace adamss;
  const auto path = fuzz::write_input(data, size, ".nii");
  try {
    (void)preprocess::read_label_image(path);
  } catch (const InputError&) {
  }
  try {
    (void)preprocess::read_scalar_image(path);
  } catch (const InputError&) {
  }
  try {
    (void)preprocess::read_vector_image(path);
  } catch (const InputError&) {
  }
  return 0;
}
