// The implicit solvers' linear-solver set-up as a run sees it: GAMG gets the rigid-body
// near-null space and MUMPS its workspace allowance (ICNTL(14) = 100) whoever chose them (the
// size rule or the user's PETSc options), an option the user names wins, and a run without MUMPS
// gets no MUMPS options. Read from PETSc's own reports (-ksp_view, -options_view).
#include <gtest/gtest.h>

#include <string>

#include "cli_runner.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;

namespace {

/// A 8 x 4 x 4 mm block of 8 x 4 x 4 neo-Hookean hexahedra (675 unknowns, below the 750 000 of the
/// automatic switch to GAMG), clamped at x = 0 and pulled 0.2 mm along x at x = 8 mm in two
/// static load steps.
const char* const kBlock = R"(
name: block
mesh: {box: [8 mm, 4 mm, 4 mm], divisions: [8, 4, 4], topology: hex}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: neo_hookean, parameters: {E: 20 kPa, nu: 0.3}, quadrature: gauss}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    fix: xyz
  - select: {region: {plane: {point: [8 mm, 0, 0], normal: [1, 0, 0], tolerance: 0.001 mm}}}
    control: {axis: x, displacement: {ramp: {to: 0.2 mm, duration: 2 s}}}
integrator: {type: static, dt: 1 s, adapt: false}
run: {t_end: 2 s}
output: {frame_interval: 2 s}
)";

/// `adamss run` of the block with `petsc` as --petsc; the run's output (PETSc's reports included).
std::string run_block(const std::string& name, const std::string& petsc) {
  const auto dir = scratch_dir(name);
  const auto scene = write_scene(dir, kBlock);
  const auto r =
      run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + " -q --petsc \"" + petsc + "\"");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

bool has(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

}  // namespace

TEST(LinearSolverOptions, GamgChosenByTheUserCoarsensWithTheSixRigidBodyModes) {
  // With the particle coordinates GAMG's coarse operators have 6 unknowns per aggregate (3
  // translations, 3 rotations); without them 3, the translations alone (bs=3 on every level).
  const std::string out = run_block("lso_gamg", "-ksp_type gmres -pc_type gamg -ksp_view");
  ASSERT_TRUE(has(out, "type: gamg")) << out;
  EXPECT_TRUE(has(out, "bs=6")) << out;
}

// adamss's MUMPS workspace allowance (-mat_mumps_icntl_14 100) is set in PETSc's option table,
// which -options_view prints when PETSc finalises.
TEST(LinearSolverOptions, MumpsChosenByTheUserGetsTheLargerWorkspace) {
  const std::string out =
      run_block("lso_mumps", "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps -options_view");
  EXPECT_TRUE(has(out, "\n-mat_mumps_icntl_14 100\n")) << out;
}

TEST(LinearSolverOptions, TheDefaultMumpsLuGetsTheSameWorkspace) {
  const std::string out = run_block("lso_default", "-options_view");
  EXPECT_TRUE(has(out, "\n-mat_mumps_icntl_14 100\n")) << out;
}

TEST(LinearSolverOptions, AnOptionTheUserNamesWins) {
  const std::string out = run_block("lso_user", "-mat_mumps_icntl_14 30 -options_view");
  EXPECT_TRUE(has(out, "\n-mat_mumps_icntl_14 30\n")) << out;
  EXPECT_FALSE(has(out, "-mat_mumps_icntl_14 100")) << out;
}

TEST(LinearSolverOptions, NoMumpsNoMumpsOptions) {
  const std::string out = run_block("lso_petsc", "-pc_factor_mat_solver_type petsc -options_view");
  EXPECT_TRUE(has(out, "#PETSc Option Table entries")) << out;
  EXPECT_FALSE(has(out, "-mat_mumps_icntl_14")) << out;
}
