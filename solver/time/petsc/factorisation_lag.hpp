#pragma once
// When a new operator may keep the last factorisation as its preconditioner (lagged
// factorisations of the single-precision path, jacobian_solver.hpp).
//
// The single-precision factor M of an operator A_0 already serves as the right preconditioner of
// flexible GMRES on the double-precision operator (single_precision_factor.hpp). A later Newton
// operator A_k (the next iteration's, the next load step's) differs from A_0 by the change of the
// tangent along the path; M then still clusters the spectrum of A_k M^{-1} near 1, and FGMRES
// reaches the refinement tolerance in more iterations instead of a new factorisation. Each extra
// iteration costs one single-precision solve t_s and one product with A_k; a factorisation costs
// t_f (on the 1 mm heart t_f / t_s is about 26, on biv-inflation.yaml about 25).
//
// The rule is the ski-rental one (rent until the rent paid equals the price, then buy): the
// excess of the lagged solves since the last factorisation,
//     E = sum over lagged solves of  t_solve (n - n_0)^+ / n,
// with n the solve's iterations and n_0 those of the first solve after that factorisation (what
// a fresh factor needs), is the time the stale factor has cost; once E >= t_f the next new
// operator is factorised. Whatever the path, the time spent is then at most twice that of the
// best choice in hindsight between factorising and lagging for each stretch. A lagged solve
// that does not converge within its iteration cap is redone after factorising its operator.
// On several ranks the caller feeds it the slowest rank's times (jacobian_solver.cpp), so that
// every rank decides alike.
//
// The price is the last factorisation's measured time; the first one of a pattern includes its
// analysis (and METIS's order), so the first stretch lags somewhat longer than the rule intends.
//
// Measured times make the decisions vary from run to run (and with the number of ranks). A fixed
// price in iterations (`set_price_iterations(K)`, -adamss_lag_price_its K) counts the account in
// iterations instead: E = sum of (n - n_0)^+, and the next operator is factorised once E >= K.
// The decisions then follow the iteration counts alone (K = t_f / t_s prices a factorisation as
// the time-based rule would: about 25 on the hearts above).
//
// Measured on biv-inflation.yaml (2 ranks; bench/README.md): 41 -> 14 factorisations (65 Newton
// iterations under modified Newton either way), whole process 61.3 -> 49.6 s (A/B 0.81); the
// heart at 1 mm 88 -> 38 factorisations, 44 min 41 s -> 40 min 28 s.
namespace adamss::solver {

class FactorisationLag {
 public:
  /// Price every factorisation at `iterations` lagged iterations beyond a fresh factor's count
  /// and ignore the measured times; 0 (the default) prices it at its measured time.
  void set_price_iterations(int iterations) { price_iterations_ = iterations > 0 ? iterations : 0; }
  /// A new factorisation took `seconds`: the excess starts again.
  void factorised(double seconds) {
    price_ = price_iterations_ > 0 ? static_cast<double>(price_iterations_) : seconds;
    excess_ = 0.0;
    fresh_iterations_ = -1;
    refactor_ = false;
  }
  /// The first solve after a factorisation took `iterations` (n_0).
  void fresh_solve(int iterations) {
    if (fresh_iterations_ < 0) fresh_iterations_ = iterations;
  }
  /// A solve with an older factorisation took `iterations` in `seconds`.
  void lagged_solve(int iterations, double seconds) {
    const int base = fresh_iterations_ < 0 ? 0 : fresh_iterations_;
    if (iterations > base) {
      const double extra = static_cast<double>(iterations - base);
      excess_ += price_iterations_ > 0 ? extra : seconds * extra / iterations;
    }
    if (excess_ >= price_) refactor_ = true;
  }
  /// Whether the next new operator is to be factorised rather than preconditioned by the last
  /// factorisation.
  [[nodiscard]] bool refactor() const { return refactor_; }
  /// The lagged solves' excess so far (s; iterations with a price in iterations).
  [[nodiscard]] double excess() const { return excess_; }

 private:
  int price_iterations_ = 0;
  double price_ = 0.0;
  double excess_ = 0.0;
  int fresh_iterations_ = -1;
  bool refactor_ = false;
};

}  // namespace adamss::solver
