#pragma once
// The verification suite of seed 000 sec. 2.8 (`adamss verify`): each case builds its model in
// memory (scene text through solver::load_scene_text, or a benchmark scene file), drives it with
// the solver's own integrators (the PETSc `static` Newton for the stretch/shear cases), and
// reports rows (case, metric, value, tolerance, pass) plus plot data like the thesis figures.
//
// Cases (verify/cases.cpp has the details of each):
//   uniaxial-voxel-tet6, uniaxial-cuboid-{tet6m,tet5m,hex}    Figs. 2.23/2.24, aligned fibres,
//        stretch along global z of the fibre, sheet and normal axis in turn, to 20 % strain.
//        BC "uniaxial stress": nodes on z = 0 fixed in z, nodes on z = L prescribed in z
//        (L (1 + eps)), all other coordinates free except rigid-mode pins (node (0,0,0) in x, y;
//        node (0,D,0) in x). Analytic: the law's uniaxial-stress curve P_aa(eps)
//        (spring_fit.hpp, uniaxial_nominal_stress; lateral strains solved for S_bb = S_cc = 0).
//   uniaxial-rotated-{tet6m,hex}                            Fig. 2.25, fibre frame rotated by
//        theta = 49.6 deg, phi = 21.25 deg (spherical: f = (sin t cos p, sin t sin p, cos t),
//        s = e_theta, n = f x s), stretch along global z. A free-sliding uniaxial-stress state is
//        not homogeneous for a rotated orthotropic law (the bar wants to shear but its ends are
//        held flat), so this case uses "uniaxial strain": every boundary node is prescribed to
//        the homogeneous field x = diag(1, 1, lambda) X, interior nodes free. Analytic:
//        P_zz = lambda (B S(B^T E B) B^T)_zz, E = (lambda^2 - 1)/2 e_z e_z, B = [f s n].
//   Stress measure (all uniaxial cases): the volume average of the nominal stress from the
//        nodal forces, P_bar = -(1/V0) sum_a f_a X_a^T (exact virtual work with the affine test
//        field; equals the top-face reaction / A0 for the uniaxial-stress BC), component zz.
//   Models per mesh: `vhex` = virtual_hexahedron + the law (hexahedra: the default axis
//        quadrature + hourglass, as in the thesis, and `vhex-gauss` = quadrature gauss);
//        `springs` = the polynomial axial + torsion springs fitted to the law (spring_fit.hpp,
//        powers {1, 3}, 20 %), + hourglass on hexahedra.
//   Metric: max over the load steps of |P_sim - P_law| / |P_law|.
//   shear-voxel-tet6, shear-cuboid-tet6m                   Figs. 2.26/2.27: simple shear, the
//        face X_l = 0 fixed, the face X_l = L_l displaced along m by gamma L_l (its other two
//        coordinates fixed), l != m over the six combinations of the aligned fibre frame
//        (fibre = x, sheet = y, normal = z), gamma to 0.2. Metric: |W - U| / U at gamma = 0.2,
//        W the applied work of eqs. 2.151-2.152 (trapezoid over the load steps, all nodes: the
//        free ones carry no net force), U the terms' stored energy.
//   gravity-volume                                          Fig. 2.28: the benchmark scenes
//        cases/benchmarks/gravity-volume-p1e{2,3,4,5}.yaml, run to t_end (default 0.08 s, which
//        covers the first sag and its peak (measured 60 ms) |dV/V0| at t ~ 60 ms; --full: the scene's 1 s).
//        Metric: max |dV/V0|, tolerance 1 % (the thesis's claim for p >= 1e3 kPa).
//   resolution                                              the fibre uniaxial-stress test on the
//        4 x 4 x 8 mm box at 2x2x4, 4x4x8 and 8x8x16 tet6m divisions: max relative difference of
//        the stress curves to the finest one.
//   cost                                                    Fig. 2.29 (not in --all): the
//        6 x 6 x 12 cm hexahedral cuboid of the gravity benchmark at several resolutions, wall
//        time per backward_euler_newton step (fixed dt) against the element count; linear fit
//        and R^2 (tolerance R^2 >= 0.9); report row: the log-log slope p of t ~ n^p, with the
//        Newton and Krylov iterations per step of each mesh (measured p = 1.7: the static and
//        implicit steps factorise with LU, one Krylov iteration per Newton iteration).
//   hybmss-volume, hybmss-shear, hybmss-beam, hybmss-moduli, lloyd-moduli, lloyd-cylinder
//        the spring-model experiments of seeds 001 and 002 against our FEM reference (issue 7;
//        verify/spring_cases.hpp has the setups and metrics).
#include <filesystem>
#include <string>
#include <vector>

namespace adamss::verify {

struct VerifyRow {
  std::string case_name;
  std::string metric;
  double value = 0.0;
  double tolerance = 0.0;
  std::string comparison = "<=";  ///< "<=" (value <= tolerance), ">=" (value >= tolerance) or "report"
                                  ///< (informational: always passes unless the value is not finite)
  bool pass = false;
  std::string note;
};

/// One plotted series: simulated points or an analytic line.
struct Series {
  std::string title;
  std::vector<double> x, y;
  bool line = false;  ///< line (analytic / reference) or points (simulated)
  int colour = 0;     ///< 0 red, 1 green, 2 blue, 3 magenta, ...
};

struct Plot {
  std::string name;  ///< file stem
  std::string title, xlabel, ylabel;
  bool log_y = false;
  std::vector<Series> series;
};

struct CaseResult {
  std::string name;
  std::vector<VerifyRow> rows;
  std::vector<Plot> plots;
  std::string table_markdown;  ///< extra Markdown (paper vs ours vs FEM), appended to verify.md
  double seconds = 0.0;
};

struct VerifyOptions {
  int steps = 10;                     ///< load steps to 20 % (uniaxial, shear)
  double max_strain = 0.2;            ///< final engineering strain / shear
  std::filesystem::path benchmarks;   ///< folder of gravity-volume-p1e*.yaml
  std::filesystem::path cache_dir;    ///< mesh-recipe cache (empty: solver default)
  bool full_gravity = false;          ///< run the gravity scenes to their own t_end
  bool full = false;                  ///< spring-model cases: add the expensive rows (20 %, fine beam)
  std::string law = "hunter_canine";  ///< the law (no parameters: its defaults)
};

/// A row with `pass` set: value <= tolerance ("<="), value >= tolerance (">="), or always
/// ("report", informational); never for a non-finite value. InputError for another comparison.
[[nodiscard]] VerifyRow make_row(const std::string& case_name, const std::string& metric, double value,
                                 double tolerance, const std::string& note = "", const std::string& comparison = "<=");

/// Every case name, in run order.
[[nodiscard]] std::vector<std::string> case_names();
/// The cases of --all (every case except `cost`).
[[nodiscard]] std::vector<std::string> default_cases();
/// Runs one case. Throws InputError for an unknown name (the message lists the known ones).
[[nodiscard]] CaseResult run_case(const std::string& name, const VerifyOptions& options);

struct ReportFiles {
  std::filesystem::path json, markdown;
  std::vector<std::filesystem::path> plots;    ///< .png written (empty without gnuplot)
  std::vector<std::filesystem::path> scripts;  ///< .gp + .dat
  bool gnuplot = false;
};

/// Writes OUT/verify.json, OUT/verify.md and OUT/plots/NAME.{dat,gp} for every plot, and runs
/// gnuplot (pngcairo) on each script when `gnuplot` is found on PATH (else only the scripts).
ReportFiles write_report(const std::vector<CaseResult>& results, const std::filesystem::path& out);

}  // namespace adamss::verify
