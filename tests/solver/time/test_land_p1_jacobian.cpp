// The assembled operator of the Land problem 1 scene (uncoupled Guccione at the Gauss points,
// element volume, follower pressure) against finite differences at a bent, twisted state: the
// static Newton converges quadratically only if every term's Jacobian is exact there.
#include <gtest/gtest.h>

#include <cmath>

#include "force_term_harness.hpp"
#include "scene_fixtures.hpp"

using namespace adamss;

TEST(LandP1Jacobian, EveryTermMatchesFiniteDifferencesAtALargeBend) {
  const std::string scene = R"(
name: p1
mesh: {box: [10 mm, 1 mm, 1 mm], divisions: [5, 1, 1], topology: hex, fibre: [1, 0, 0], sheet: [0, 1, 0]}
materials:
  - name: beam
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: guccione_land_problem1, quadrature: gauss, uncoupled: true}
      - volume: {p: 2000 kPa, distribution: isotropic}
loads:
  pressure:
    - name: bottom
      surface: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 0.001 mm}}}
      pressure: 400 Pa
integrator: {type: static, dt: 0.1 s}
run: {t_end: 1 s}
)";
  const auto loaded = test::load_scene(scene);
  const Eigen::Matrix3Xd& X = loaded.model.mesh->nodes;
  // Bend about y through up to 60 degrees, stretch the fibres by 10 %, a little twist.
  Eigen::Matrix3Xd x(3, X.cols());
  for (Eigen::Index i = 0; i < X.cols(); ++i) {
    const double s = X(0, i) / 10e-3, th = 1.0 * s, tw = 0.2 * s;
    const double r = 1.1 * 10e-3 / 1.0, zz = X(2, i) - 0.5e-3, yy = X(1, i) - 0.5e-3;
    x(0, i) = (r - zz) * std::sin(th);
    x(2, i) = r - (r - zz) * std::cos(th);
    x(1, i) = 0.5e-3 + yy * std::cos(tw) - zz * std::sin(tw) * 0.1;
  }
  x += test::perturbed(X, 1e-3, 0.02) - X;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, X.cols());
  for (const auto& term : loaded.model.terms) {
    if (!term->has_jacobian()) continue;
    test::HarnessOptions opt;
    opt.internal = false;
    opt.tolerance = 1e-6;
    test::check_force_term(*term, x, v, 1e-3, opt);
  }
}
