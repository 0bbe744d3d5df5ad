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

/// The kinematic part of the split: a, C, C^-1 and Ebar (Sb, P and sb_c not yet).
Split kinematics(const Eigen::Matrix3d& E) {
  Split s;
  const double am1 = isochoric_factor_minus_one(E);
  s.a = 1.0 + am1;
  s.C = 2.0 * E + Eigen::Matrix3d::Identity();
  s.Ci = s.C.inverse();
  s.Eb = s.a * E + 0.5 * am1 * Eigen::Matrix3d::Identity();
  return s;
}

/// The stress part, once s.Sb holds the base stress at Ebar.
void deviator(Split& s) {
  s.sb_c = s.Sb.cwiseProduct(s.C).sum();
  s.P = s.Sb - (s.sb_c / 3.0) * s.Ci;
}

Split split(const Law& base, const Eigen::Matrix3d& E) {
  Split s = kinematics(E);
  s.Sb = base.stress(s.Eb);
  deviator(s);
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

namespace {

/// The Voigt tangent from the split and the base tangent Db at Ebar: stress_increment written as
/// a 6 x 6 matrix acting on the Voigt strain e (engineering shear). With the stress-Voigt vectors
/// ci = C^-1, p = P, sb = Sbar and c_e = the strain-Voigt C (a symmetric A : dE = A_voigt . e, and
/// dSb : C = c_e . dSb):
///   dEbar = M e,  M = a (I - 1/3 c_e ci^T),   dSb = Db M e,
///   D = -2/3 a p ci^T + a Db M - a/3 ci (c_e^T Db M + 2 sb^T) + 2/3 a (Sbar : C) T,
/// T the Voigt form of dE -> C^-1 dE C^-1 (voigt_of_pair_tangent(C^-1, 0, 1/2)). Two rank-one
/// corrections and one 6 x 6 product instead of six tensor increments (about 5x fewer flops).
Matrix6d tangent_of(const Split& s, const Matrix6d& Db) {
  const Vector6d ci = to_voigt_stress(s.Ci), p = to_voigt_stress(s.P), sb = to_voigt_stress(s.Sb);
  const Vector6d ce = to_voigt_strain(s.C);
  // Db M = a (Db - 1/3 (Db c_e) ci^T)
  const Matrix6d db_m = s.a * (Db - (Db * ce / 3.0) * ci.transpose());
  const Eigen::Matrix<double, 1, 6> row = ce.transpose() * db_m + 2.0 * sb.transpose();
  Matrix6d D = s.a * db_m;
  D.noalias() -= (s.a / 3.0) * ci * row;
  D.noalias() -= (2.0 / 3.0 * s.a) * p * ci.transpose();
  D += (2.0 / 3.0 * s.a * s.sb_c) * voigt_of_pair_tangent(s.Ci, 0.0, 0.5);
  return D;
}

}  // namespace

Matrix6d UncoupledLaw::tangent(const Eigen::Matrix3d& E) const {
  Eigen::Matrix3d S;  // the tangent needs the base stress at Ebar anyway
  Matrix6d D;
  stress_and_tangent(E, S, D);
  return D;
}

void UncoupledLaw::stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
  Split s = kinematics(E);
  Matrix6d Db;
  base_->stress_and_tangent(s.Eb, s.Sb, Db);
  deviator(s);
  S = s.a * s.P;
  D = tangent_of(s, Db);
}

}  // namespace adamss::materials
