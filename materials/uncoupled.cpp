#include "materials/uncoupled.hpp"

#include <Eigen/LU>
#include <stdexcept>
#include <utility>

namespace adamss::materials {

namespace {

/// Everything the stress and the tangent share at one strain E (see uncoupled.hpp).
struct Split {
  double a = 1.0;      ///< J^-2/3
  Eigen::Matrix3d C;   ///< I + 2E
  Eigen::Matrix3d Ci;  ///< C^-1
  Eigen::Matrix3d Eb;  ///< isochoric strain Ebar
  Eigen::Matrix3d Sb;  ///< base stress at Ebar
  Eigen::Matrix3d P;   ///< Dev(Sbar) = Sbar - 1/3 (Sbar : C) C^-1
  double sb_c = 0.0;   ///< Sbar : C
};

Split split(const Law& base, const Eigen::Matrix3d& E) {
  Split s;
  const double am1 = isochoric_factor_minus_one(E);
  s.a = 1.0 + am1;
  s.C = 2.0 * E + Eigen::Matrix3d::Identity();
  s.Ci = s.C.inverse();
  s.Eb = s.a * E + 0.5 * am1 * Eigen::Matrix3d::Identity();
  s.Sb = base.stress(s.Eb);
  s.sb_c = s.Sb.cwiseProduct(s.C).sum();
  s.P = s.Sb - (s.sb_c / 3.0) * s.Ci;
  return s;
}

/// dEbar = a (dE - 1/3 (C^-1 : dE) C).
Eigen::Matrix3d isochoric_increment(const Split& s, const Eigen::Matrix3d& dE) {
  return s.a * (dE - (s.Ci.cwiseProduct(dE).sum() / 3.0) * s.C);
}

/// dS = da P + a (dSbar - 1/3 (dSbar : C + 2 Sbar : dE) C^-1 + 2/3 (Sbar : C) C^-1 dE C^-1).
Eigen::Matrix3d stress_increment(const Split& s, const Eigen::Matrix3d& dE, const Eigen::Matrix3d& dSb) {
  const double da = -2.0 / 3.0 * s.a * s.Ci.cwiseProduct(dE).sum();
  const double d_sb_c = dSb.cwiseProduct(s.C).sum() + 2.0 * s.Sb.cwiseProduct(dE).sum();
  return da * s.P + s.a * (dSb - (d_sb_c / 3.0) * s.Ci + (2.0 / 3.0 * s.sb_c) * (s.Ci * dE * s.Ci));
}

}  // namespace

UncoupledLaw::UncoupledLaw(std::shared_ptr<const Law> base) : base_(std::move(base)) {
  if (!base_) throw std::invalid_argument("UncoupledLaw: null base law");
  name_ = std::string(base_->name()) + "_uncoupled";
}

Eigen::Matrix3d UncoupledLaw::stress(const Eigen::Matrix3d& E) const {
  const Split s = split(*base_, E);
  return s.a * s.P;
}

Eigen::Matrix3d UncoupledLaw::apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
  const Split s = split(*base_, E);
  return stress_increment(s, dE, base_->apply_tangent(s.Eb, isochoric_increment(s, dE)));
}

Matrix6d UncoupledLaw::tangent(const Eigen::Matrix3d& E) const {
  const Split s = split(*base_, E);
  const Matrix6d Db = base_->tangent(s.Eb);
  Matrix6d D;
  for (int J = 0; J < 6; ++J) {
    const Eigen::Matrix3d dE = from_voigt_strain(Vector6d::Unit(J));
    const Eigen::Matrix3d dSb = from_voigt_stress(Db * to_voigt_strain(isochoric_increment(s, dE)));
    D.col(J) = to_voigt_stress(stress_increment(s, dE, dSb));
  }
  return D;
}

}  // namespace adamss::materials
