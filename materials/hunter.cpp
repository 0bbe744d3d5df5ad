#include "materials/hunter.hpp"

#include <string>

#include "materials/params.hpp"

namespace adamss::materials {

namespace {
constexpr std::array<std::array<int, 3>, 6> kTermIndex{
    {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0, 1, 5}, {0, 2, 4}, {1, 2, 3}}};

/// g, g', g'' of x^2 (a - x)^-b for 0 <= x < a.
void pole_zero(double x, double a, double b, double& g0, double& g1, double& g2) {
  const double t = a - x;
  const double p = std::pow(t, -b);
  const double r = x / t;
  g0 = x * x * p;
  g1 = x * p * (2.0 + b * r);
  g2 = p * (2.0 + 4.0 * b * r + b * (b + 1.0) * r * r);
}
}  // namespace

HunterParams hunter_canine() {
  HunterParams p;
  p.k = {2842.0, 63.0, 310.0, 1000.0, 1000.0, 1000.0};
  p.a = {0.318, 0.429, 1.037, 0.731, 0.731, 0.886};
  p.b = {0.624, 2.48, 0.398, 2.0, 2.0, 2.0};
  return p;
}

HunterPoleZero::HunterPoleZero(const HunterParams& p) : p_(p) {
  check_open_interval("hunter", "pole_fraction", p.pole_fraction, 0.0, 1.0);
  for (int t = 0; t < 6; ++t) {
    const std::string id(HunterParams::kTerms[t]);
    check_non_negative("hunter", "k" + id, p.k[t]);
    check_positive("hunter", "a" + id, p.a[t]);
    check_non_negative("hunter", "b" + id, p.b[t]);
    Term& term = terms_[t];
    term.i = kTermIndex[t][0];
    term.j = kTermIndex[t][1];
    term.voigt = kTermIndex[t][2];
    term.k = p.k[t];
    term.a = p.a[t];
    term.b = p.b[t];
    term.x_star = p.pole_fraction * p.a[t];
    pole_zero(term.x_star, term.a, term.b, term.g0, term.g1, term.g2);
  }
}

void HunterPoleZero::derivatives(const Term& term, double e, double& g1, double& g2) {
  const double x = std::abs(e);
  if (x < term.x_star) {
    double g0 = 0.0;
    pole_zero(x, term.a, term.b, g0, g1, g2);
  } else {
    g1 = term.g1 + term.g2 * (x - term.x_star);
    g2 = term.g2;
  }
  if (e < 0.0) g1 = -g1;
}

Eigen::Matrix3d HunterPoleZero::stress(const Eigen::Matrix3d& E) const {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const Term& term : terms_) {
    double g1 = 0.0, g2 = 0.0;
    if (term.i == term.j) {
      derivatives(term, E(term.i, term.i), g1, g2);
      S(term.i, term.i) = term.k * g1;
    } else {
      derivatives(term, 0.5 * (E(term.i, term.j) + E(term.j, term.i)), g1, g2);
      S(term.i, term.j) = S(term.j, term.i) = 0.5 * term.k * g1;
    }
  }
  return S;
}

Matrix6d HunterPoleZero::tangent(const Eigen::Matrix3d& E) const {
  Matrix6d D = Matrix6d::Zero();
  for (const Term& term : terms_) {
    double g1 = 0.0, g2 = 0.0;
    const double e = 0.5 * (E(term.i, term.j) + E(term.j, term.i));
    derivatives(term, e, g1, g2);
    D(term.voigt, term.voigt) = (term.i == term.j ? 1.0 : 0.25) * term.k * g2;
  }
  return D;
}

void HunterPoleZero::stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
  S.setZero();
  D.setZero();
  for (const Term& term : terms_) {
    double g1 = 0.0, g2 = 0.0;
    if (term.i == term.j) {
      derivatives(term, E(term.i, term.i), g1, g2);
      S(term.i, term.i) = term.k * g1;
      D(term.voigt, term.voigt) = term.k * g2;
    } else {
      derivatives(term, 0.5 * (E(term.i, term.j) + E(term.j, term.i)), g1, g2);
      S(term.i, term.j) = S(term.j, term.i) = 0.5 * term.k * g1;
      D(term.voigt, term.voigt) = 0.25 * term.k * g2;
    }
  }
}

Eigen::Matrix3d HunterPoleZero::apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
  Eigen::Matrix3d dS = Eigen::Matrix3d::Zero();
  for (const Term& term : terms_) {
    double g1 = 0.0, g2 = 0.0;
    derivatives(term, 0.5 * (E(term.i, term.j) + E(term.j, term.i)), g1, g2);
    if (term.i == term.j) {
      dS(term.i, term.i) = term.k * g2 * dE(term.i, term.i);
    } else {
      dS(term.i, term.j) = dS(term.j, term.i) = 0.25 * term.k * g2 * (dE(term.i, term.j) + dE(term.j, term.i));
    }
  }
  return dS;
}

}  // namespace adamss::materials
