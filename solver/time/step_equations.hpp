#pragma once
// The nonlinear equations of one implicit step ending at t1 = t + h, each written once (seed 000
// sec. 2.5.5, eqs. 2.142-2.149). A Newton iteration (bordered_newton.hpp, damped_newton.hpp)
// solves R(u) = 0 for the unknown u; it sees the equations through StepEquations:
//
//   StaticEquations          u = x, R(x) = f(x, 0, t1): quasi-static equilibrium at the load
//                            step t1 (every load is a time course, so time is the load
//                            parameter); operator A = -dR/dx = -K. With a viscous
//                            regularisation zeta > 0 (integrator.static_damping; the idea of
//                            Abaqus' *STATIC, STABILIZE): R(x) = f(x, 0, t1) - c M (x - x_n),
//                            c = zeta / h, x_n the last converged step, M the lumped masses;
//                            A = -K + c M. A drag -zeta M v on the step's mean velocity
//                            v = (x - x_n)/h: it vanishes at rest, so held loads still end at
//                            the plain equilibrium, and c M keeps A positive definite where K
//                            has a zero or negative eigenvalue (a local instability) once
//                            c m exceeds it. Its work in the step, c sum m |x - x_n|^2, is
//                            what StepReport::damping_work reports.
//   BackwardEulerEquations   u = v (the end-of-step velocity), x(v) = x0 + h v,
//                            R(v) = h f(x(v), v, t1) - M (v - v0): backward Euler, eqs.
//                            2.142-2.144; operator A = -dR/dv = M - h D - h^2 K
//
// with K = dF/dx, D = dF/dv and the fixed and controlled coordinates eliminated (R is zero
// there). A cavity volume gradient g = dV/dx enters R through the pressure multiplier as
// P g(x(u)), so its derivative with respect to P, in the unknowns' units, is (dx/du) g.
#include <Eigen/Core>

#include "solver/time/integrator.hpp"

namespace adamss::solver {

class JacobianSolver;

class StepEquations {
 public:
  virtual ~StepEquations() = default;
  /// r = R(u), zero on the fixed coordinates; one force evaluation (counted).
  virtual void residual(const Eigen::Matrix3Xd& u, Eigen::Matrix3Xd& r) = 0;
  /// The positions x(u) at the u of the last residual() call.
  [[nodiscard]] virtual const Eigen::Matrix3Xd& positions(const Eigen::Matrix3Xd& u) const = 0;
  /// Assembles A = -dR/du at the u of the last residual() call (not eliminated).
  virtual void assemble_operator(const Eigen::Matrix3Xd& u) = 0;
  /// g (a position-space gradient) times dx/du, in place: identity (static) or h (backward Euler).
  virtual void scale_by_dx_du(Eigen::Matrix3Xd& g) const = 0;
  /// The largest position change |dx/du du|_inf (m) of an update du.
  [[nodiscard]] virtual double position_change(const Eigen::Matrix3Xd& du) const = 0;
};

class StaticEquations final : public StepEquations {
 public:
  /// `evaluations` is incremented for every force evaluation.
  StaticEquations(System& system, JacobianSolver& linear, double t1, int& evaluations);
  /// Adds the viscous regularisation -c M (x - x_n) (file comment); c = zeta / h in 1/s^2 (0:
  /// none). `x_n` must outlive the object.
  void set_damping(double c, const Eigen::Matrix3Xd& x_n);
  void residual(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& r) override;
  [[nodiscard]] const Eigen::Matrix3Xd& positions(const Eigen::Matrix3Xd& x) const override { return x; }
  void assemble_operator(const Eigen::Matrix3Xd& x) override;
  void scale_by_dx_du(Eigen::Matrix3Xd& /*g*/) const override {}
  [[nodiscard]] double position_change(const Eigen::Matrix3Xd& dx) const override;

 private:
  System& sys_;
  JacobianSolver& linear_;
  double t1_;
  int& evaluations_;
  Eigen::Matrix3Xd v_;                     // zero: equilibrium has no velocities
  const Eigen::Matrix3Xd* x_n_ = nullptr;  // the last converged positions
  Eigen::VectorXd cm_;                     // c m per node (N/m), the operator's diagonal part
};

class BackwardEulerEquations final : public StepEquations {
 public:
  /// The step from (x0, v0) over h to t1 (the references must outlive the object).
  BackwardEulerEquations(System& system, JacobianSolver& linear, const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& v0,
                         double t1, double h, int& evaluations);
  void residual(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& r) override;
  [[nodiscard]] const Eigen::Matrix3Xd& positions(const Eigen::Matrix3Xd& /*v*/) const override { return x_; }
  void assemble_operator(const Eigen::Matrix3Xd& v) override;
  void scale_by_dx_du(Eigen::Matrix3Xd& g) const override { g *= h_; }
  [[nodiscard]] double position_change(const Eigen::Matrix3Xd& dv) const override;

  /// The linearised step (eq. 2.148, the Baraff-Witkin form): one solve of
  /// (M - h D - h^2 K) dv = h (f0 + h K v0) with K, D, f0 at (x0, v0, t1), dv = vp - v0 on the
  /// fixed coordinates; v = v0 + dv. False if the linear solve fails.
  bool linearised_step(const Eigen::Matrix3Xd& vp, Eigen::Matrix3Xd& v);

 private:
  void assemble_at(const StateView& at);  // M - h D - h^2 K at `at`

  System& sys_;
  JacobianSolver& linear_;
  const Eigen::Matrix3Xd& x0_;
  const Eigen::Matrix3Xd& v0_;
  double t1_, h_;
  int& evaluations_;
  Eigen::Matrix3Xd f_, x_;
};

/// The end-of-step velocity backward Euler starts from: v0 on the free coordinates; on a fixed
/// one the velocity that makes x1 = x0 + h v1 land on the prescribed position pres.x, or the
/// prescribed velocity pres.v of a velocity control.
[[nodiscard]] Eigen::Matrix3Xd backward_euler_start(const Model& model, const std::vector<Eigen::Index>& fixed,
                                                    const State& pres, const Eigen::Matrix3Xd& x0,
                                                    const Eigen::Matrix3Xd& v0, double h);

}  // namespace adamss::solver
