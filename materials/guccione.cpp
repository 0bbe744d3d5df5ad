#include "materials/guccione.hpp"

#include "materials/params.hpp"

namespace adamss::materials {

GuccioneParams guccione_land_problem1() {
  return {2000.0, 8.0, 2.0, 4.0};
}
GuccioneParams guccione_land_problem3() {
  return guccione_land_problem1();
}
GuccioneParams guccione_land_problem2() {
  return {10000.0, 1.0, 1.0, 1.0};
}

Guccione::Guccione(const GuccioneParams& p) : p_(p) {
  check_non_negative("guccione", "C", p.C);
  check_non_negative("guccione", "b_f", p.b_f);
  check_non_negative("guccione", "b_t", p.b_t);
  check_non_negative("guccione", "b_fs", p.b_fs);
  B_ << p.b_f, p.b_fs, p.b_fs,  //
      p.b_fs, p.b_t, p.b_t,     //
      p.b_fs, p.b_t, p.b_t;
}

Eigen::Matrix3d Guccione::stress(const Eigen::Matrix3d& E) const {
  const Eigen::Matrix3d A = B_.cwiseProduct(E);
  const double Q = A.cwiseProduct(E).sum();
  return p_.C * std::exp(Q) * A;
}

namespace {

/// D = C e^Q (2 a a^T + diag(b)), a = Voigt(A), b = Voigt(B) with the shear half (S = C e^Q A).
Matrix6d guccione_tangent(const Eigen::Matrix3d& B, const Eigen::Matrix3d& A, double scale) {
  const Vector6d a = to_voigt_stress(A);
  Vector6d diag = to_voigt_stress(B);
  diag.tail<3>() *= 0.5;
  Matrix6d D = 2.0 * a * a.transpose();
  D.diagonal() += diag;
  return scale * D;
}

}  // namespace

Matrix6d Guccione::tangent(const Eigen::Matrix3d& E) const {
  const Eigen::Matrix3d A = B_.cwiseProduct(E);
  return guccione_tangent(B_, A, p_.C * std::exp(A.cwiseProduct(E).sum()));
}

void Guccione::stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
  const Eigen::Matrix3d A = B_.cwiseProduct(E);
  const double scale = p_.C * std::exp(A.cwiseProduct(E).sum());
  S = scale * A;
  D = guccione_tangent(B_, A, scale);
}

Eigen::Matrix3d Guccione::apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const {
  const Eigen::Matrix3d A = B_.cwiseProduct(E);
  const double scale = p_.C * std::exp(A.cwiseProduct(E).sum());
  return scale * (B_.cwiseProduct(dE) + 2.0 * A.cwiseProduct(dE).sum() * A);
}

}  // namespace adamss::materials
