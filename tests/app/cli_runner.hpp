#pragma once
// Runs the built adamss executable and captures its output and exit code.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace adamss::test {

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

/// `env`: variable assignments put before the command ("TMPDIR=/x"), none by default.
inline RunResult run_adamss(const std::string& args, const std::string& env = "") {
  const std::string cmd = (env.empty() ? "" : env + " ") + std::string(ADAMSS_BINARY) + " " + args + " 2>&1";
  RunResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) r.output += buf.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A fresh scratch directory for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("adamss_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `text` to dir/scene.yaml and returns that path.
inline std::filesystem::path write_scene(const std::filesystem::path& dir, const std::string& text) {
  const std::filesystem::path p = dir / "scene.yaml";
  std::ofstream(p) << text;
  return p;
}

/// The --cache option pointing into `dir` (keeps tests from sharing the user's mesh cache).
inline std::string cache_arg(const std::filesystem::path& dir) {
  return " --cache " + (dir / "cache").string();
}

/// out/summary.json, parsed.
inline nlohmann::json read_summary(const std::filesystem::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in);
}

/// The scene both run and restart tests use, up to and including "integrator: ": a 2 x 2 x 4 mm
/// tet6m slab of a neo-Hookean virtual hexahedron (plus `extra_terms`), bottom fixed, top pulled
/// 0.5 mm over 2 ms. The caller appends the integrator, run and output settings.
inline std::string slab_scene_head(const std::string& extra_terms = "") {
  return R"(
name: slab
mesh: {phantom: slab, slab_size: [2, 2, 4], voxel_size: 1 mm, topology: tet6m, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: neo_hookean, parameters: {E: 20 kPa, nu: 0.3}})" +
         extra_terms + R"(
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
  - select: {region: {plane: {point: [0, 0, 4 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    control: {axis: z, displacement: {ramp: {to: 0.5 mm, duration: 2 ms}}}
integrator: )";
}

}  // namespace adamss::test
