#pragma once
// Loading scene text in tests: the one cache folder, the InputError message of a scene that must
// fail, and a checked text substitution.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::test {

/// Loads scene `text` as if read from `name`, recipe meshes cached in the temp folder.
inline solver::LoadedScene load_scene(const std::string& text, const std::string& name = "scene.yaml") {
  solver::SceneOptions o;
  o.cache_dir = std::filesystem::temp_directory_path() / "adamss-test-scene-cache";
  return solver::load_scene_text(text, name, o);
}

/// The InputError message of loading `text` ("" if it loads).
inline std::string scene_error(const std::string& text) {
  try {
    (void)load_scene(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// `s` with the first `from` replaced by `to`; a test failure if `from` is not there.
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

}  // namespace adamss::test
