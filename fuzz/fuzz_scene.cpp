// Fuzz target: the scene parser and model assembly on arbitrary YAML text. Inputs may only be
// rejected with adamss::InputError or NumericalError. Meshes come from in-memory recipes (box,
// cylinder, ellipsoid) or cached phantoms in a private cache folder; relative mesh files are
// resolved next to a scratch origin, so `file:` keys see nothing on disk.
//
// Valid but too large for a fuzz run, skipped (not a finding): a mesh recipe of more than
// kMaxCells voxels or cells (slab_size or divisions), or a voxel phantom (lv, biv, beam) with
// voxels under 1 mm. Such scenes are legitimate -- `slab_size: [4, 4, 999999]` asks for 16 M
// hexahedra and gets them after a minute and gigabytes (known/scene-huge-slab-timeout.yaml) --
// but they spend the fuzzing time (and CI's) in the mesher instead of the parser.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "common/units.hpp"
#include "fuzz_input.hpp"
#include "solver/scene/scene.hpp"

namespace {

constexpr double kMaxCells = 20000.0;

/// True for a scene whose mesh recipe is too large for a fuzz run (see above). Anything it cannot
/// read is left to the parser under test.
bool too_large(const std::string& text) {
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap() || !root["mesh"] || !root["mesh"].IsMap()) return false;
    const YAML::Node mesh = root["mesh"];
    for (const char* key : {"slab_size", "divisions"}) {
      if (!mesh[key] || !mesh[key].IsSequence()) continue;
      double cells = 1.0;
      for (const auto& n : mesh[key]) cells *= std::abs(n.as<double>());
      if (!(cells <= kMaxCells)) return true;
    }
    if (mesh["phantom"] && mesh["phantom"].IsScalar() && mesh["phantom"].as<std::string>() != "slab") {
      if (!mesh["voxel_size"]) return true;  // the default, 0.5 mm
      const double h = adamss::common::parse_quantity(mesh["voxel_size"].as<std::string>(),
                                                      adamss::common::Dimension::Length, "voxel_size");
      if (!(h >= 1e-3)) return true;
    }
  } catch (...) {
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace adamss;
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (too_large(text)) return 0;
  solver::SceneOptions opt;
  opt.cache_dir = fuzz::scratch_file("-cache");
  try {
    (void)solver::load_scene_text(text, fuzz::scratch_file("-scene.yaml"), opt);
  } catch (const InputError&) {
  } catch (const NumericalError&) {
  }
  return 0;
}
