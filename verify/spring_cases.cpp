#include "verify/spring_cases.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "solver/time/implicit.hpp"
#include "solver/time/integrator.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::verify {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

/// The block's scenes (cases/hybmss/block.yaml.in): E = 10 000 Pa.
constexpr double kBlockE = 10000.0, kBlockEdge = 5.0;

std::string hybmss_term(double youngs, double nu, double a) {
  return "hybmss: {youngs_modulus: " + fmt("%.10g", youngs) + " Pa, poisson_ratio: " + fmt("%.10g", nu) +
         ", A: " + fmt("%.10g", a) + "}";
}

std::string fem_term(const std::string& law, double youngs, double nu) {
  return "fem_element: {law: " + law + ", parameters: {E: " + fmt("%.10g", youngs) + " Pa, nu: " + fmt("%.10g", nu) +
         "}}";
}

/// Model of a block run: name and the term's YAML.
struct BlockModel {
  std::string name;  ///< hybmss_fd, hybmss, fem
  std::string term;
};

std::vector<BlockModel> block_models(double youngs, double nu) {
  return {{"hybmss_fd", hybmss_term(youngs, nu, 0.0)},
          {"hybmss", hybmss_term(youngs, nu, 1.0)},
          {"fem", fem_term("neo_hookean", youngs, nu)}};
}

/// Scene text of a static run of `steps` load steps over 1 s.
std::string integrator_yaml(int steps, double rtol) {
  return "integrator: {type: static, dt: " + fmt("%.10g", 1.0 / steps) +
         " s, dt_min: " + fmt("%.10g", 1.0 / (16.0 * steps)) + " s, adapt: false, newton_rtol: " + fmt("%.3g", rtol) +
         ", max_newton: 30}\nrun: {t_end: 1 s}\n";
}

std::string material_yaml(const std::string& term) {
  return "materials:\n  - name: sample\n    labels: [1]\n    density: 1000 kg/m^3\n    terms:\n      - " + term + "\n";
}

/// The 10 x 10 x 10 sample with bonded plates; the top face moves along `axis` (0 x shear, 2 z
/// compression / tension) by `disp` metres, its other two coordinates held.
std::string block_scene(const std::string& term, int axis, double disp, int steps) {
  const char* held = axis == 2 ? "xy" : "yz";
  const char* axis_name = axis == 2 ? "z" : "x";
  std::ostringstream os;
  os << "name: verify-hybmss-block\nmesh: {box: [5 m, 5 m, 5 m], divisions: [10, 10, 10], topology: hex}\n"
     << material_yaml(term) << "boundary:\n"
     << "  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1], tolerance: 1 mm}}}\n    fix: xyz\n"
     << "  - select: {region: {plane: {point: [0, 0, 5 m], normal: [0, 0, 1], tolerance: 1 mm}}}\n    fix: " << held
     << "\n  - select: {region: {plane: {point: [0, 0, 5 m], normal: [0, 0, 1], tolerance: 1 mm}}}\n"
     << "    control: {axis: " << axis_name << ", displacement: {ramp: {to: " << fmt("%.10g", disp)
     << " m, duration: 1 s}}}\n"
     << integrator_yaml(steps, 1e-9);
  return os.str();
}

struct StaticResult {
  Eigen::Matrix3Xd x, f;  ///< last converged positions and the nodal forces there (N)
  int steps_done = 0;
  double t_reached = 0.0;  ///< load parameter of the returned state (s; 1 = full load)
  bool completed = false;
  std::string failure;  ///< message of the failed step
};

/// Drives a loaded scene with the static Newton through `steps` load steps of 1/steps s, the
/// prescribed displacements ramping with t. Stops at the first step that does not converge and
/// returns the last converged state (completed = false). dt_min of the scenes (integrator_yaml)
/// bounds the halvings of a failing step to four.
StaticResult solve_static(solver::LoadedScene& sc, int steps) {
  solver::State s = sc.initial;
  s.v.setZero();
  solver::System sys(sc.model);
  sys.set_fixed_positions(s.x);
  sys.impose(s);
  auto integ = solver::make_integrator("static", sys, sc.run.abm3, &sc.run.implicit);
  StaticResult r;
  for (int i = 1; i <= steps && r.failure.empty(); ++i) {
    const double target = static_cast<double>(i) / steps;
    int guard = 0;
    while (s.t < target - 1e-12) {
      const solver::State saved = s;
      try {
        if (guard++ >= 64) throw NumericalError("more than 64 sub-steps to reach t = " + std::to_string(target));
        (void)integ->step(s, target - s.t);
      } catch (const std::exception& e) {
        s = saved;
        r.failure = e.what();
        break;
      }
    }
    if (r.failure.empty()) r.steps_done = i;
  }
  r.t_reached = s.t;
  r.completed = r.steps_done == steps;
  r.x = s.x;
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, s.x.cols());
  sys.forces(s.x, zero, s.t, r.f);
  return r;
}

solver::LoadedScene load(const std::string& text, const VerifyOptions& o) {
  solver::SceneOptions so;
  so.cache_dir = o.cache_dir;
  return solver::load_scene_text(text, "verify-springs", so);
}

std::string pct(double v) {
  return fmt("%.2f %%", v);
}

// ---------------------------------------------------------------------------------------------
// hybmss-volume

/// Tables 2-3 of seed 001 (%): HybMSS-FD, HybMSS, FEM, keyed by test, nu, strain.
std::array<double, 3> paper_volume(bool tension, double nu, int strain) {
  static const std::map<std::string, std::array<double, 3>> kTables = {
      {"c0_5", {5.37, 5.61, 5.00}},     {"c0.25_5", {3.25, 3.17, 3.10}},     {"c0.499_5", {0.00, 0.01, 0.02}},
      {"c0_20", {23.62, 19.88, 20.00}}, {"c0.25_20", {15.99, 13.52, 12.70}}, {"c0.499_20", {0.01, 0.00, 0.10}},
      {"t0_5", {7.46, 4.40, 5.00}},     {"t0.25_5", {0.85, 2.54, 2.61}},     {"t0.499_5", {0.00, 0.00, 0.00}},
      {"t0_20", {24.92, 20.00, 19.99}}, {"t0.25_20", {3.15, 8.90, 10.11}},   {"t0.499_20", {0.00, 0.00, 0.00}}};
  return kTables.at(std::string(tension ? "t" : "c") + fmt("%g", nu) + "_" + std::to_string(strain));
}

}  // namespace

double euler_bernoulli_tip(double rho, double g, double length, double width, double height, double youngs) {
  const double inertia = width * height * height * height / 12.0;
  return -rho * g * width * height * std::pow(length, 4) / (8.0 * youngs * inertia);
}

NodeErrors node_errors(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y) {
  if (x.cols() != y.cols() || x.cols() == 0) {
    throw InputError("node_errors: configurations of " + std::to_string(x.cols()) + " and " + std::to_string(y.cols()) +
                     " nodes");
  }
  const Eigen::VectorXd d = (x - y).colwise().norm().transpose();
  return {d.maxCoeff(), d.mean()};
}

Moduli central_difference_moduli(double reaction_plus, double reaction_minus, double lateral_plus, double lateral_minus,
                                 double strain, double area) {
  if (!(strain > 0.0) || !(area > 0.0)) throw InputError("central_difference_moduli: strain and area must be positive");
  return {(reaction_plus - reaction_minus) / (2.0 * strain * area), -(lateral_plus - lateral_minus) / (2.0 * strain)};
}

CaseResult hybmss_volume_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "hybmss-volume";
  std::vector<int> strains{5};
  if (o.full) strains.push_back(20);
  std::ostringstream md;
  md << "Seed 001 Tables 2-3: e = |V - V0| / V0 of the 10 x 10 x 10 sample (bonded plates).\n\n"
     << "| test | nu | strain | HybMSS-FD (paper) | HybMSS (paper) | FEM (paper) | ours: HybMSS-FD | ours: HybMSS | "
        "ours: FEM | HybMSS - FEM (pp) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const bool tension : {false, true}) {
    const std::string test = tension ? "tension" : "compression";
    for (const double nu : {0.0, 0.25, 0.499}) {
      for (const int strain : strains) {
        const int steps = strain / 5 * 2;
        const double disp = (tension ? 1.0 : -1.0) * kBlockEdge * strain / 100.0;
        std::array<double, 3> e{};
        std::array<std::string, 3> cell;
        bool all_done = true;
        std::string failures;
        const auto models = block_models(kBlockE, nu);
        for (std::size_t k = 0; k < models.size(); ++k) {
          solver::LoadedScene sc = load(block_scene(models[k].term, 2, disp, steps), o);
          const StaticResult r = solve_static(sc, steps);
          const double v0 = solver::total_volume(*sc.model.mesh, sc.model.x_ref);
          e[k] = 100.0 * std::abs(solver::total_volume(*sc.model.mesh, r.x) / v0 - 1.0);
          cell[k] = pct(e[k]);
          if (!r.completed) {
            all_done = false;
            const double reached = static_cast<double>(strain) * r.t_reached;
            cell[k] += " (stopped at " + fmt("%.1f", reached) + " %)";
            failures +=
                " " + models[k].name + " Newton failed after " + fmt("%.1f", reached) + " % (" + r.failure + ");";
          }
        }
        const auto paper = paper_volume(tension, nu, strain);
        const std::string key = test + ".nu" + fmt("%g", nu) + ".strain" + std::to_string(strain) + "pct";
        const std::string note = "e: HybMSS-FD " + cell[0] + ", HybMSS " + cell[1] + ", FEM " + cell[2] +
                                 "; paper HybMSS " + pct(paper[1]) + ", FEM " + pct(paper[2]) + failures;
        const bool checked = strain == 5;
        cr.rows.push_back(make_row(
            cr.name, "e_diff_pp.hybmss." + key, checked && !all_done ? kNaN : std::abs(e[1] - e[2]), 0.5,
            note + (checked ? " (issue 7: <= 0.5 pp at 5 %)" : " (20 %: report only)"), checked ? "<=" : "report"));
        cr.rows.push_back(make_row(
            cr.name, "e_diff_pp.hybmss_fd." + key, std::abs(e[0] - e[2]), 0.0,
            "HybMSS-FD vs FEM (report only; paper: " + fmt("%.2f", std::abs(paper[0] - paper[2])) + " pp)", "report"));
        md << "| " << test << " | " << fmt("%g", nu) << " | " << strain << " % | " << pct(paper[0]) << " | "
           << pct(paper[1]) << " | " << pct(paper[2]) << " | " << cell[0] << " | " << cell[1] << " | " << cell[2]
           << " | " << fmt("%+.2f", e[1] - e[2]) << " |\n";
      }
    }
  }
  cr.table_markdown = md.str();
  return cr;
}

CaseResult hybmss_shear_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "hybmss-shear";
  std::vector<int> strains{5};
  if (o.full) strains.push_back(20);
  const std::map<int, std::array<double, 3>> paper = {{5, {3390, 3396, 3317}}, {20, {14662, 14600, 13234}}};
  std::ostringstream md;
  md << "Seed 001 Table 4: top-plate force (N), nu = 0.25, the top face moved along x.\n\n"
     << "| shear | HybMSS-FD (paper) | HybMSS (paper) | FEM (paper) | ours: HybMSS-FD | ours: HybMSS | ours: FEM |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const int strain : strains) {
    const int steps = strain / 5 * 2;
    const double disp = kBlockEdge * strain / 100.0;
    std::array<double, 3> force{};
    const auto models = block_models(kBlockE, 0.25);
    for (std::size_t k = 0; k < models.size(); ++k) {
      solver::LoadedScene sc = load(block_scene(models[k].term, 0, disp, steps), o);
      const StaticResult r = solve_static(sc, steps);
      double fx = 0.0;
      for (Eigen::Index i = 0; i < sc.model.x_ref.cols(); ++i)
        if (sc.model.x_ref(2, i) > kBlockEdge - 1e-3) fx += r.f(0, i);
      force[k] = r.completed ? std::abs(fx) : kNaN;
    }
    const auto& p = paper.at(strain);
    const double tol = strain == 5 ? 0.05 : 0.10;
    for (const std::size_t k : {std::size_t{1}, std::size_t{0}}) {
      const double rel = std::abs(force[k] - force[2]) / force[2];
      cr.rows.push_back(make_row(
          cr.name,
          "plate_force_rel_diff." + std::string(k == 1 ? "hybmss" : "hybmss_fd") + "." + std::to_string(strain) + "pct",
          rel, tol,
          "F = " + fmt("%.0f", force[k]) + " N vs FEM " + fmt("%.0f", force[2]) + " N; paper " + fmt("%.0f", p[k]) +
              " vs " + fmt("%.0f", p[2]) + " N (" + fmt("%.1f", 100.0 * std::abs(p[k] - p[2]) / p[2]) + " %)"));
    }
    md << "| " << strain << " % | " << fmt("%.0f N", p[0]) << " | " << fmt("%.0f N", p[1]) << " | "
       << fmt("%.0f N", p[2]) << " | " << fmt("%.0f N", force[0]) << " | " << fmt("%.0f N", force[1]) << " | "
       << fmt("%.0f N", force[2]) << " |\n";
  }
  cr.table_markdown = md.str();
  return cr;
}

CaseResult hybmss_beam_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "hybmss-beam";
  constexpr double kE = 1e7, kRho = 1000.0, kG = 10.0, kL = 2.4, kB = 0.4;
  const double eb = euler_bernoulli_tip(kRho, kG, kL, kB, kB, kE);
  std::ostringstream md;
  md << "Seed 001 eq. 6.1: tip deflection of the 2.4 x 0.4 x 0.4 m cantilever, E = 10 MPa, nu = 0.25; "
     << "Euler-Bernoulli " << fmt("%.4f m", eb) << ".\n\n"
     << "| mesh | model | tip z displacement (m) | vs Euler-Bernoulli |\n|---|---|---|---|\n";
  std::map<std::string, std::array<double, 2>> err;  // model -> relative error coarse, fine
  for (const int n : {4, 8}) {
    const std::string mesh = std::to_string(6 * n) + "x" + std::to_string(n) + "x" + std::to_string(n);
    for (const auto& m : block_models(kE, 0.25)) {
      if (n == 8 && m.name != "hybmss" && !o.full) continue;
      std::ostringstream os;
      os << "name: verify-beam\nmesh: {box: [2.4 m, 0.4 m, 0.4 m], divisions: [" << 6 * n << ", " << n << ", " << n
         << "], topology: hex}\n"
         << material_yaml(m.term) << "loads:\n  gravity: [0, 0, -10 m/s^2]\nboundary:\n"
         << "  - select: {region: {plane: {point: [0, 0, 0], normal: [1, 0, 0], tolerance: 1 mm}}}\n    fix: xyz\n"
         << integrator_yaml(1, 1e-9);
      solver::LoadedScene sc = load(os.str(), o);
      const StaticResult r = solve_static(sc, 1);
      Eigen::Index tip = 0;
      (sc.model.x_ref.colwise() - Eigen::Vector3d(kL, kB / 2, kB / 2)).colwise().squaredNorm().minCoeff(&tip);
      const double uz = r.completed ? r.x(2, tip) - sc.model.x_ref(2, tip) : kNaN;
      const double rel = uz / eb - 1.0;
      err[m.name][n == 4 ? 0 : 1] = rel;
      cr.rows.push_back(make_row(cr.name, "tip_rel_error_vs_euler_bernoulli." + m.name + "." + mesh, rel, 0.0,
                                 "tip " + fmt("%.4f m", uz) + ", Euler-Bernoulli " + fmt("%.4f m", eb), "report"));
      md << "| " << mesh << " | " << m.name << " | " << fmt("%.4f", uz) << " | " << fmt("%+.1f %%", 100.0 * rel)
         << " |\n";
    }
  }
  for (const auto& [name, e] : err) {
    if (name != "hybmss" && !o.full) continue;
    cr.rows.push_back(make_row(cr.name, "error_ratio_fine_over_coarse." + name, std::abs(e[1]) / std::abs(e[0]), 1.0,
                               "|err(48x8x8)| / |err(24x4x4)|: " + fmt("%.4f", e[1]) + " / " + fmt("%.4f", e[0]) +
                                   " (the error against Euler-Bernoulli must decrease with refinement)"));
  }
  md << "\nEuler-Bernoulli neglects shear deformation (L/h = 6) and geometric nonlinearity: exact agreement is not "
        "expected.\n";
  cr.table_markdown = md.str();
  return cr;
}

namespace {

/// Effective small-strain moduli of the 1 m block (4 x 4 x 4 cells of `topology`) with `term`,
/// by a uniaxial test along x at +-1 %: face x = 0 fixed in x, face x = L prescribed in x, the
/// lateral faces free; node (0, 0, 0) pinned in y and z, node (0, W, 0) in z. R = -sum of the x
/// forces on x = L, e_lat = mean of the y and z strains of the face-mean positions.
Moduli uniaxial_moduli(const std::string& topology, const std::string& term, const VerifyOptions& o) {
  constexpr double kStrain = 0.01, kLen = 1.0, kTol = 1e-9;
  double reaction[2] = {0, 0}, lateral[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    const double eps = side == 0 ? kStrain : -kStrain;
    std::ostringstream os;
    os << "name: verify-moduli\nmesh: {box: [1 m, 1 m, 1 m], divisions: [4, 4, 4], topology: " << topology << "}\n"
       << material_yaml(term) << integrator_yaml(2, 1e-12);
    solver::LoadedScene sc = load(os.str(), o);
    solver::Model& m = sc.model;
    const Eigen::Index n = m.x_ref.cols();
    m.constraints = solver::Constraints(static_cast<std::size_t>(n));
    std::vector<Eigen::Index> far, face[2][2];
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3d p = m.x_ref.col(i);
      const bool x0 = p.x() < kTol;
      if (x0) m.constraints.fix(i, 1, "verify");
      if (p.x() > kLen - kTol) {
        m.constraints.control(i, 0, solver::TimeCourse::ramp(0.0, eps * kLen, 0.0, 1.0), false, "verify");
        far.push_back(i);
      }
      if (x0 && p.y() < kTol && p.z() < kTol) m.constraints.fix(i, 6, "verify");
      if (x0 && p.y() > kLen - kTol && p.z() < kTol) m.constraints.fix(i, 4, "verify");
      for (int a = 0; a < 2; ++a) {
        if (p[a + 1] < kTol) face[a][0].push_back(i);
        if (p[a + 1] > kLen - kTol) face[a][1].push_back(i);
      }
    }
    const StaticResult r = solve_static(sc, 2);
    if (!r.completed) return {kNaN, kNaN};
    for (const auto i : far) reaction[side] -= r.f(0, i);
    auto mean = [&](const std::vector<Eigen::Index>& set, int c) {
      double s = 0.0;
      for (const auto i : set) s += r.x(c, i);
      return s / static_cast<double>(set.size());
    };
    double e = 0.0;
    for (int a = 0; a < 2; ++a) e += 0.5 * ((mean(face[a][1], a + 1) - mean(face[a][0], a + 1)) / kLen - 1.0);
    lateral[side] = e;
  }
  return central_difference_moduli(reaction[0], reaction[1], lateral[0], lateral[1], kStrain, kLen * kLen);
}

const double kRequestedNu[] = {0.0, 0.25, 0.4, 0.499};

}  // namespace

CaseResult hybmss_moduli_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "hybmss-moduli";
  constexpr double kE = 10e3;
  std::ostringstream md;
  md << "Effective moduli of a 4 x 4 x 4 hexahedral block, +-1 % uniaxial stretch along x, lateral faces free, "
        "E = 10 kPa.\n\n| requested nu | HybMSS E/E | HybMSS nu | FEM (neo-Hookean) E/E | FEM nu |\n"
        "|---|---|---|---|---|\n";
  for (const double nu : kRequestedNu) {
    const Moduli h = uniaxial_moduli("hex", hybmss_term(kE, nu, 1.0), o);
    const Moduli f = uniaxial_moduli("hex", fem_term("neo_hookean", kE, nu), o);
    const std::string key = ".nu" + fmt("%g", nu);
    cr.rows.push_back(make_row(cr.name, "nu_abs_error.hybmss" + key, std::abs(h.poisson - nu), 0.01,
                               "measured nu " + fmt("%.4f", h.poisson)));
    cr.rows.push_back(make_row(cr.name, "E_rel_error.hybmss" + key, std::abs(h.youngs / kE - 1.0), 0.02,
                               "measured E/E " + fmt("%.4f", h.youngs / kE)));
    cr.rows.push_back(make_row(
        cr.name, "nu_abs_error.fem" + key, std::abs(f.poisson - nu), 0.0,
        "FEM reference, measured nu " + fmt("%.4f", f.poisson) + ", E/E " + fmt("%.4f", f.youngs / kE), "report"));
    md << "| " << fmt("%g", nu) << " | " << fmt("%.4f", h.youngs / kE) << " | " << fmt("%.4f", h.poisson) << " | "
       << fmt("%.4f", f.youngs / kE) << " | " << fmt("%.4f", f.poisson) << " |\n";
  }
  cr.table_markdown = md.str();
  return cr;
}

CaseResult lloyd_moduli_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "lloyd-moduli";
  constexpr double kE = 15e3;
  std::ostringstream md;
  md << "Effective moduli of a 4 x 4 x 4 tet6m block with Lloyd's springs (no nu input), +-1 % uniaxial stretch "
        "along x, E = 15 kPa.\n\n| model | E/E | nu | requested nu: gap nu - requested |\n|---|---|---|---|\n";
  for (const bool vf : {false, true}) {
    const std::string model = vf ? "eq14_volume" : "eq12";
    const Moduli l = uniaxial_moduli(
        "tet6m", "lloyd_springs: {youngs_modulus: 15 kPa, volume_force: " + std::string(vf ? "true" : "false") + "}",
        o);
    cr.rows.push_back(make_row(
        cr.name, "nu_minus_quarter." + model, std::abs(l.poisson - 0.25), 0.02,
        "measured nu " + fmt("%.4f", l.poisson) + " (Lloyd's constants are derived for nu = 1/4; seed 002 sec. 4.2)"));
    cr.rows.push_back(make_row(cr.name, "E_rel_error." + model, std::abs(l.youngs / kE - 1.0), 0.25,
                               "measured E/E " + fmt("%.4f", l.youngs / kE) +
                                   " (loose bound: the right-angled tet6m tetrahedra make the block too stiff)"));
    std::string gaps;
    for (const double nu : kRequestedNu) {
      cr.rows.push_back(make_row(cr.name, "nu_gap_to_requested." + model + ".nu" + fmt("%g", nu), l.poisson - nu, 0.0,
                                 "measured nu " + fmt("%.4f", l.poisson) + " whatever nu is wanted", "report"));
      gaps += (gaps.empty() ? "" : ", ") + fmt("%g", nu) + ": " + fmt("%+.3f", l.poisson - nu);
    }
    md << "| " << (vf ? "eq. 14 + volume force" : "eq. 12") << " | " << fmt("%.4f", l.youngs / kE) << " | "
       << fmt("%.4f", l.poisson) << " | " << gaps << " |\n";
  }
  md << "\nHybMSS on the hexahedral block reaches the requested nu within 0.01 (case hybmss-moduli).\n";
  cr.table_markdown = md.str();
  return cr;
}

CaseResult lloyd_cylinder_case(const VerifyOptions& o) {
  CaseResult cr;
  cr.name = "lloyd-cylinder";
  constexpr double kH = 0.02;
  const char* loads[] = {"stretch", "compression", "shear"};
  // Seed 002 sec. 5.6 max (mean) node errors, cm: [volume force][load].
  const double paper[2][3][2] = {{{0.039, 0.013}, {0.111, 0.025}, {0.088, 0.029}},
                                 {{0.029, 0.009}, {0.073, 0.018}, {0.183, 0.080}}};
  auto run = [&](const std::string& term, int kind) {
    std::ostringstream os;
    os << "name: verify-cylinder\nmesh: {cylinder: [1 cm, 2 cm], divisions: [4, 4, 8], topology: tet6m}\n"
       << material_yaml(term) << integrator_yaml(4, 1e-10);
    solver::LoadedScene sc = load(os.str(), o);
    solver::Model& m = sc.model;
    const Eigen::Index n = m.x_ref.cols();
    m.constraints = solver::Constraints(static_cast<std::size_t>(n));
    const double d = 0.15 * kH;
    const int axis = kind == 2 ? 0 : 2;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (m.x_ref(2, i) < 1e-9) m.constraints.fix(i, 7, "verify");
      if (m.x_ref(2, i) > kH - 1e-9) {
        m.constraints.control(i, axis, solver::TimeCourse::ramp(0.0, kind == 1 ? -d : d, 0.0, 1.0), false, "verify");
        m.constraints.fix(i, static_cast<std::uint8_t>(7 & ~(1 << axis)), "verify");
      }
    }
    const StaticResult r = solve_static(sc, 4);
    if (!r.completed) throw NumericalError("lloyd-cylinder: " + std::string(loads[kind]) + ": " + r.failure);
    return r.x;
  };
  std::ostringstream md;
  md << "Seed 002 sec. 5.6: cylinder r = 1 cm, h = 2 cm (4 x 4 x 8 cells, tet6m), E = 15 kPa, 15 % of h; node "
        "distance to our FEM (linear tetrahedra, svk, nu = 1/4) on the same mesh.\n\n"
     << "| load | model | max error (cm) | mean error (cm) | paper max (mean) |\n|---|---|---|---|---|\n";
  for (int l = 0; l < 3; ++l) {
    const Eigen::Matrix3Xd xf = run(fem_term("svk", 15e3, 0.25), l);
    for (int vf = 0; vf < 2; ++vf) {
      const Eigen::Matrix3Xd xl =
          run("lloyd_springs: {youngs_modulus: 15 kPa, volume_force: " + std::string(vf ? "true" : "false") + "}", l);
      const NodeErrors e = node_errors(xl * 100.0, xf * 100.0);
      const std::string model = vf ? "eq14_volume" : "eq12";
      const std::string key = std::string(loads[l]) + "." + model;
      const double pm = paper[vf][l][0], pa = paper[vf][l][1];
      cr.rows.push_back(make_row(cr.name, "max_node_error_cm." + key, e.max, 3.0 * pm,
                                 "paper " + fmt("%.3f cm", pm) + "; tolerance 3x the paper's"));
      cr.rows.push_back(make_row(cr.name, "mean_node_error_cm." + key, e.mean, 3.0 * pa,
                                 "paper " + fmt("%.3f cm", pa) + "; tolerance 3x the paper's"));
      md << "| " << loads[l] << " | " << (vf ? "eq. 14 + volume" : "eq. 12") << " | " << fmt("%.3f", e.max) << " | "
         << fmt("%.3f", e.mean) << " | " << fmt("%.3f", pm) << " (" << fmt("%.3f", pa) << ") |\n";
    }
  }
  md << "\nOur FEM is geometrically nonlinear, the paper's small-strain: the check is the same order (3x).\n";
  cr.table_markdown = md.str();
  return cr;
}

}  // namespace adamss::verify
