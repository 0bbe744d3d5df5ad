#pragma once
// Time integration of M a = f(x, v, t) (seed 000 sec. 2.5): the System, the Integrator
// interface, the one table of integrators and the factory.
//
// System evaluates the accelerations a = M^{-1} f with the boundary conditions
// applied (constrained coordinates get the acceleration their condition dictates)
// and imposes the conditions on a state. Integrators advance a State by one step; the
// explicit ones (forces only, no Jacobian, no cavity volume constraint) are
//   forward_euler     eqs. 2.129-2.130: v+ = v + h a(x, v, t), x+ = x + h v (first order,
//                     energy grows on an undamped oscillator: |1 + i w h| > 1)
//   symplectic_euler  v+ = v + h a(x, v, t), x+ = x + h v+ (semi-implicit Euler; symplectic,
//                     energy error bounded, stable for h < 2 / w_max)
//   abm3              third-order Adams-Bashforth-Moulton predictor-corrector with step
//                     doubling/halving (sec. 2.5.4, eqs. 2.133-2.141), see abm3.hpp
// and the implicit ones backward_euler, backward_euler_newton and static (implicit.hpp) need
// every term's Jacobian and solve linear systems with PETSc.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/core/time_split.hpp"

namespace adamss::solver {

class ForceExchange;  // solver/time/petsc/force_exchange.hpp

class System {
 public:
  explicit System(Model& model);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  /// f(x, v, t) summed over the model's terms into `f` (N, 3 x n); counts evaluations. On several
  /// MPI ranks each rank computes its own particles' forces and the ranks exchange them
  /// (solver/core/owned_nodes.hpp): every rank gets the whole vector, equal bit for bit to one
  /// rank's.
  void forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double t, Eigen::Matrix3Xd& f);
  /// a = f / m on free coordinates; constrained ones from Constraints::constrain_acceleration.
  /// The raw forces of the last call stay available in last_forces().
  void accelerations(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double t, Eigen::Matrix3Xd& a);
  /// A whole symplectic Euler step t -> t + h on s: v += h f(x, v, t) / m, the velocity controls
  /// of t + h, x += h v, the full impose of t + h. Without velocity controls the two updates run
  /// as one pass (node_loops.hpp kick_drift; the same bits).
  void symplectic_euler_step(State& s, double h);
  /// Imposes fixed and controlled coordinates on s at time s.t.
  void impose(State& s) const;

  [[nodiscard]] const Eigen::Matrix3Xd& last_forces() const { return f_; }
  [[nodiscard]] std::size_t evaluations() const { return evaluations_; }
  /// The wall time of the force evaluations so far (times().forces; the other parts stay zero).
  [[nodiscard]] const TimeSplit& times() const { return times_; }
  [[nodiscard]] Model& model() { return model_; }
  [[nodiscard]] const Model& model() const { return model_; }
  /// Positions at which fixed coordinates are held (the state at t = 0).
  void set_fixed_positions(const Eigen::Matrix3Xd& x) { x_fixed_ = x; }
  [[nodiscard]] const Eigen::Matrix3Xd& fixed_positions() const { return x_fixed_; }

 private:
  Model& model_;
  Eigen::VectorXd inv_mass_;
  Eigen::VectorXd inv_mass3_;  // inv_mass_ per coordinate (node_loops.hpp)
  Eigen::Matrix3Xd f_;
  Eigen::Matrix3Xd x_fixed_;
  std::size_t evaluations_ = 0;
  TimeSplit times_;
  std::unique_ptr<ForceExchange> exchange_;  ///< several MPI ranks only
};

/// What one call of Integrator::step did.
struct StepReport {
  double dt = 0.0;                    ///< step actually taken (s)
  double next_dt = 0.0;               ///< step the integrator proposes next (s)
  int evaluations = 0;                ///< force evaluations used, including rejected attempts
  int rejected = 0;                   ///< attempts rejected (ABM3 halvings)
  double error = 0.0;                 ///< ABM3 predictor-corrector difference (m), 0 otherwise
  int newton_iterations = 0;          ///< implicit/static: Newton iterations of the accepted attempt
  int linear_iterations = 0;          ///< implicit/static: Krylov iterations of the accepted attempt
  int reformations = 0;               ///< implicit/static: operators assembled and factorised, accepted attempt
  int augmentations = 0;              ///< static: augmented-Lagrangian multiplier updates of the accepted attempt
  int continuation_solves = 0;        ///< static: re-solves after raising a continued penalty, accepted attempt
  double constraint_violation = 0.0;  ///< static with multipliers: max |J - r| after the last update
  double damping_work = 0.0;          ///< static with static_damping: energy the regularisation took (J)
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// Advances s by one step of (at most) `dt`; updates s.t. Forces and terms' end_step
  /// hooks are the caller's (run loop's) business except for the force evaluations.
  virtual StepReport step(State& s, double dt) = 0;
  /// True if the integrator chooses its own step size (then `dt` of step() is a proposal).
  [[nodiscard]] virtual bool adaptive() const { return false; }
  /// Checkpoint/restart: everything the next step() depends on besides the state passed to it
  /// (multistep history, current step size, predictors), written into `archive` so that
  /// load_state on a fresh integrator of the same scene continues bit for bit. The one-step
  /// explicit schemes have none (the default).
  virtual void save_state(StateArchive& /*archive*/) const {}
  /// Restores what save_state wrote; InputError naming the checkpoint and key if it does not fit.
  virtual void load_state(const StateArchive& /*archive*/) {}
  /// The wall time of the linear algebra so far: Jacobian assemblies, factorisations and solves
  /// (solver/core/time_split.hpp; forces are System::times()'s). None for the explicit schemes.
  [[nodiscard]] virtual TimeSplit linear_times() const { return {}; }
  /// What solves the linear systems ("GMRES + gamg, 103 428 unknowns"), for the run log; empty for
  /// the explicit schemes.
  [[nodiscard]] virtual std::string linear_solver() const { return {}; }
};

/// Settings of the adaptive ABM3 scheme (sec. 2.5.4).
struct Abm3Settings {
  double error_min = 1e-9;  ///< m: all |x_corrected - x_predicted| below this -> double the step
  double error_max = 1e-7;  ///< m: any above this -> halve the step and redo it
  double dt_min = 1e-9;     ///< s: halving below this stops the run (NumericalError)
  double dt_max = 1e-3;     ///< s: doubling never exceeds this
};

struct ImplicitSettings;

/// The integrators a scene can name (`integrator.type`): integrator_table() is the one list of
/// them; scene parsing, the run loop, checkpoints and make_integrator all read it.
enum class IntegratorType { ForwardEuler, SymplecticEuler, Abm3, BackwardEuler, BackwardEulerNewton, Static };

struct IntegratorInfo {
  const char* name;  ///< the scene's spelling
  IntegratorType type;
  bool is_explicit;          ///< no Jacobian: cannot hold a cavity volume constraint
  bool stable_step_limited;  ///< a fixed explicit step: dt must stay below h_c = L/c (eq. 2.150)
  bool clips_last_step;      ///< the run loop shortens the last step to land on t_end (not ABM3,
                             ///< whose step size is part of its multistep state)
};

/// Every integrator, in the order of their checkpoint index.
[[nodiscard]] const std::vector<IntegratorInfo>& integrator_table();
/// The row named `name`; InputError listing the names otherwise.
[[nodiscard]] const IntegratorInfo& integrator_info(const std::string& name);
/// The row of `type`.
[[nodiscard]] const IntegratorInfo& integrator_info(IntegratorType type);
/// The names of integrator_table(), in its order.
[[nodiscard]] std::vector<std::string> integrator_names();

/// Builds the integrator named `name` (integrator_table(); the implicit ones are in
/// solver/time/implicit.hpp). Throws InputError listing the names for an unknown one.
std::unique_ptr<Integrator> make_integrator(const std::string& name, System& system, const Abm3Settings& abm = {},
                                            const ImplicitSettings* implicit = nullptr);

}  // namespace adamss::solver
