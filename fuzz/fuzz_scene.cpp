// libFuzzer target: the scene parser and model assembly on arbitrary YAML text. Inputs may only be
// rejected with adamss::InputError or NumericalError. Meshes come from in-memory recipes (box,
// cylinder, ellipsoid) or cached phantoms in a private cache folder; relative mesh files are
// resolved next to a scratch origin, so `file:` keys see nothing on disk.
#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "fuzz_input.hpp"
#include "solver/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace adamss;
  const std::string text(reinterpret_cast<const char*>(data), size);
  solver::SceneOptions opt;
  opt.cache_dir = fuzz::scratch_file("-cache");
  try {
    (void)solver::load_scene_text(text, fuzz::scratch_file("-scene.yaml"), opt);
  } catch (const InputError&) {
  } catch (const NumericalError&) {
  }
  return 0;
}
