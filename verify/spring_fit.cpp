#include "verify/spring_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"

namespace adamss::verify {

PolynomialFit fit_polynomial(const std::vector<double>& x, const std::vector<double>& y, const std::vector<int>& powers,
                             FitNorm norm, FitScale scale, bool nonnegative) {
  if (x.empty() || x.size() != y.size()) throw InputError("fit: need equally many x and y samples (at least one)");
  if (powers.empty()) throw InputError("fit: no polynomial powers given");
  for (const int p : powers)
    if (p < 1 || p > 3) throw InputError("fit: power " + std::to_string(p) + " is outside 1..3");
  const auto n = static_cast<Eigen::Index>(x.size());
  const auto m = static_cast<Eigen::Index>(powers.size());
  double ymax = 0.0;
  for (const double v : y) ymax = std::max(ymax, std::abs(v));
  Eigen::MatrixXd a(n, m);
  Eigen::VectorXd b(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double yj = y[static_cast<std::size_t>(j)];
    if (!(std::abs(yj) > 0.0) || !std::isfinite(yj)) {
      throw InputError("fit: target value " + std::to_string(yj) +
                       " at x = " + std::to_string(x[static_cast<std::size_t>(j)]) + " (need finite, non-zero values)");
    }
    const double d = scale == FitScale::Relative ? yj : ymax;
    for (Eigen::Index c = 0; c < m; ++c)
      a(j, c) = std::pow(x[static_cast<std::size_t>(j)], powers[static_cast<std::size_t>(c)]) / d;
    b[j] = yj / d;  // residual (p(x_j) - y_j) / d
  }
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd best;
  double best_max = 1e300;
  const int iterations = norm == FitNorm::Max ? 200 : 1;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd sw = w.cwiseSqrt();
    const Eigen::VectorXd c = (sw.asDiagonal() * a).colPivHouseholderQr().solve(sw.asDiagonal() * b);
    const Eigen::VectorXd r = (a * c - b).cwiseAbs();
    const double mx = r.maxCoeff();
    if (mx < best_max) {
      best_max = mx;
      best = c;
    }
    // Lawson: w_j <- w_j |r_j|, normalised.
    w = w.cwiseProduct(r);
    const double s = w.sum();
    if (!(s > 0.0)) break;
    w /= s;
  }
  if (nonnegative && best.minCoeff() < 0.0 && m > 1) {
    Eigen::Index worst = 0;
    best.minCoeff(&worst);
    std::vector<int> fewer;
    for (Eigen::Index c = 0; c < m; ++c)
      if (c != worst) fewer.push_back(powers[static_cast<std::size_t>(c)]);
    return fit_polynomial(x, y, fewer, norm, scale, true);
  }
  PolynomialFit out;
  for (Eigen::Index c = 0; c < m; ++c)
    out.k[static_cast<std::size_t>(powers[static_cast<std::size_t>(c)] - 1)] = best[c];
  double sum2 = 0.0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double p = solver::spring_value(out.k, x[j]);
    const double rel = std::abs(p - y[j]) / std::abs(y[j]);
    out.max_rel_error = std::max(out.max_rel_error, rel);
    out.max_abs_error = std::max(out.max_abs_error, std::abs(p - y[j]));
    sum2 += rel * rel;
    out.max_fullscale_error = std::max(out.max_fullscale_error, std::abs(p - y[j]) / ymax);
  }
  out.rms_rel_error = std::sqrt(sum2 / static_cast<double>(x.size()));
  return out;
}

double uniaxial_nominal_stress(const materials::Law& law, int axis, double eps, Eigen::Vector2d* lateral) {
  const double lambda = 1.0 + eps;
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  e(axis, axis) = 0.5 * (lambda * lambda - 1.0);
  // Newton on (E_bb, E_cc) for S_bb = S_cc = 0, tangent from apply_tangent.
  for (int it = 0; it < 50; ++it) {
    const Eigen::Matrix3d s = law.stress(e);
    const Eigen::Vector2d r(s(b, b), s(c, c));
    const double scale = std::max(std::abs(s(axis, axis)), 1e-12);
    if (r.cwiseAbs().maxCoeff() <= 1e-13 * scale) break;
    Eigen::Matrix2d k;
    for (int j = 0; j < 2; ++j) {
      Eigen::Matrix3d de = Eigen::Matrix3d::Zero();
      const int q = j == 0 ? b : c;
      de(q, q) = 1.0;
      const Eigen::Matrix3d ds = law.apply_tangent(e, de);
      k(0, j) = ds(b, b);
      k(1, j) = ds(c, c);
    }
    const Eigen::Vector2d d = k.fullPivLu().solve(-r);
    if (!d.allFinite()) throw NumericalError("uniaxial_nominal_stress: singular lateral tangent");
    e(b, b) += d[0];
    e(c, c) += d[1];
  }
  if (lateral != nullptr) *lateral = Eigen::Vector2d(e(b, b), e(c, c));
  return lambda * law.stress(e)(axis, axis);
}

double shear_stress_for_torsion(const materials::Law& law, int pair, double delta) {
  static constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  const int l = kPairs[pair][0], m = kPairs[pair][1];
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  e(l, m) = e(m, l) = 0.5 * delta;
  return law.stress(e)(l, m);
}

SpringFitResult fit_springs(const materials::Law& law, const FitOptions& o) {
  if (!(o.max_strain > 0.0 && o.max_strain <= 0.5)) throw InputError("--max-strain must be in (0, 0.5]");
  if (o.samples < 2) throw InputError("--samples must be >= 2");
  std::vector<double> x(static_cast<std::size_t>(o.samples));
  for (int j = 0; j < o.samples; ++j) x[static_cast<std::size_t>(j)] = o.max_strain * (j + 1) / o.samples;
  SpringFitResult out;
  out.set.name = "fitted";
  out.set.axial.scaling = solver::SpringScaling::Virtual;
  out.set.torsion.scaling = solver::SpringScaling::Virtual;
  out.set.torsion.form = solver::TorsionForm::Cosine;
  std::vector<double> y(x.size());
  for (int l = 0; l < 3; ++l) {
    for (std::size_t j = 0; j < x.size(); ++j) y[j] = uniaxial_nominal_stress(law, l, x[j]);
    out.axial[static_cast<std::size_t>(l)] = fit_polynomial(x, y, o.powers, o.norm, o.scale, true);
    const bool has_linear = std::find(o.powers.begin(), o.powers.end(), 1) != o.powers.end();
    if (has_linear && out.axial[static_cast<std::size_t>(l)].k[0] == 0.0 && o.powers.size() > 1) {
      // k_1 dropped by the active set: a spring without stiffness at rest makes the static
      // tangent singular, so k_1 is fixed to the law's small-strain slope dP/deps(0) and the
      // other powers are fitted to the rest (y - k_1 x).
      const double h = 1e-7, k1 = uniaxial_nominal_stress(law, l, h) / h;
      std::vector<double> rest(y.size());
      for (std::size_t j = 0; j < y.size(); ++j) rest[j] = y[j] - k1 * x[j];
      std::vector<int> others;
      for (const int p : o.powers)
        if (p != 1) others.push_back(p);
      PolynomialFit f = fit_polynomial(x, rest, others, o.norm, o.scale, true);
      f.k[0] = k1;
      // errors against the full curve
      double ymax = 0.0;
      for (const double v : y) ymax = std::max(ymax, std::abs(v));
      f.max_rel_error = f.max_abs_error = f.max_fullscale_error = f.rms_rel_error = 0.0;
      double sum2 = 0.0;
      for (std::size_t j = 0; j < y.size(); ++j) {
        const double d = std::abs(solver::spring_value(f.k, x[j]) - y[j]);
        f.max_rel_error = std::max(f.max_rel_error, d / std::abs(y[j]));
        f.max_abs_error = std::max(f.max_abs_error, d);
        f.max_fullscale_error = std::max(f.max_fullscale_error, d / ymax);
        sum2 += d * d / (y[j] * y[j]);
      }
      f.rms_rel_error = std::sqrt(sum2 / static_cast<double>(y.size()));
      out.axial[static_cast<std::size_t>(l)] = f;
    }
    out.set.axial.k[static_cast<std::size_t>(l)] = out.axial[static_cast<std::size_t>(l)].k;
    for (std::size_t j = 0; j < x.size(); ++j) y[j] = shear_stress_for_torsion(law, l, x[j]);
    out.torsion[static_cast<std::size_t>(l)] = fit_polynomial(x, y, o.powers, o.norm, o.scale, true);
    out.set.torsion.k[static_cast<std::size_t>(l)] = out.torsion[static_cast<std::size_t>(l)].k;
  }
  return out;
}

namespace {
std::string poly(const solver::SpringPolynomial& k) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "[%.6g Pa, %.6g Pa, %.6g Pa]", k[0], k[1], k[2]);
  return buf;
}
}  // namespace

std::string spring_terms_yaml(const solver::SpringSet& set, const std::string& indent) {
  std::ostringstream os;
  os << indent << "- axial_springs: {scaling: virtual, fibre: " << poly(set.axial.k[0])
     << ", sheet: " << poly(set.axial.k[1]) << ", normal: " << poly(set.axial.k[2]) << "}\n";
  os << indent << "- torsion_springs: {scaling: virtual, form: "
     << (set.torsion.form == solver::TorsionForm::Cosine ? "cosine" : "angle")
     << ", fibre_sheet: " << poly(set.torsion.k[0]) << ", fibre_normal: " << poly(set.torsion.k[1])
     << ", sheet_normal: " << poly(set.torsion.k[2]) << "}\n";
  return os.str();
}

}  // namespace adamss::verify
