#pragma once
// The scene of the unloading tests (tests/solver/run/test_unload.cpp, tests/app/test_unload_cli.cpp):
// an 8 x 2 x 2 mm neo-Hookean cantilever (E 20 kPa, 8 x 2 x 2 hexahedra) clamped at x = 0 and
// sagging under gravity, its tip about 0.69 mm down: moderately nonlinear.
#include <string>

namespace adamss::test {

/// The cantilever's own mesh mapping, without its closing brace (callers may add keys).
inline const std::string kCantileverBoxOpen = "{box: [8 mm, 2 mm, 2 mm], divisions: [8, 2, 2], topology: hex";

/// The scene text with `mesh` as its mesh mapping (default the box), integrator type `integrator`,
/// and `tail` appended after the run section (e.g. an output section).
inline std::string gravity_cantilever(const std::string& mesh = kCantileverBoxOpen + "}",
                                      const std::string& integrator = "static", const std::string& tail = "") {
  return "name: cantilever\nmesh: " + mesh + R"(
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 20 kPa, nu: 0.3}}
loads:
  gravity: [0, 0, -9.81 m/s^2]
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    fix: xyz
integrator: {type: )" +
         integrator + R"(, dt: 0.5 s, newton_rtol: 1e-10}
run: {t_end: 1 s}
)" + tail;
}

}  // namespace adamss::test
