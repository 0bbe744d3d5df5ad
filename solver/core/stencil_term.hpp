#pragma once
// StencilTerm: the shared assembler for terms that act on fixed-size stencils.
//
// A kernel describes one kind of local interaction (an element, a spring, a
// face) on N nodes; the assembler gathers the stencil's positions and
// velocities into fixed-size matrices, calls the kernel, and scatters the
// local results into the global force vector or the Jacobian sink. Local
// storage is fixed-size, so nothing is allocated in the item loop.
//
// Kernel contract (K is the kernel type, N its stencil size):
//   static constexpr bool kHasEnergy, kHasJacobian;
//   std::string name() const;
//   std::size_t size() const;                                  // number of items
//   std::array<Index, N> stencil(std::size_t item) const;
//   double energy(std::size_t item, const Mat3N& x, const Mat3N& v, double t) const;
//   void forces(std::size_t item, const Mat3N& x, const Mat3N& v, double t, Mat3N& f) const;
//   void jacobian(std::size_t item, const Mat3N& x, const Mat3N& v, double t,
//                 MatJ& dfdx, MatJ& dfdv) const;               // MatJ = 3N x 3N, local (a,b) block at (3a, 3b)
// (energy/jacobian may be left undefined when the matching flag is false.)
// Optional: void add_forces_bulk(const StateView& s, Eigen::Matrix3Xd& f) const;
//                                                            // all items at once (a vectorised
//                                                            // loop); add_forces then uses it
//           void end_step(const StateView& s, double dt);   // state update after a step
//           void save_state(StateArchive&) const; void load_state(const StateArchive&);
//                                                            // that state, for checkpoints
//           VolumeMultipliers multipliers; double gap(i, x, t) const; double penalty_slope(i, x, t) const;
//                                                            // augmented Lagrangian: J_i - r and U'(J_i; r)
//                                                            // (solver/core/augmented_lagrangian.hpp)
#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/core/force_term.hpp"
#include "solver/core/owned_nodes.hpp"

namespace adamss::solver {

template <int N>
using Mat3N = Eigen::Matrix<double, 3, N>;
template <int N>
using MatJ = Eigen::Matrix<double, 3 * N, 3 * N>;

template <class Kernel, int N>
class StencilTerm final : public ForceTerm {
 public:
  explicit StencilTerm(Kernel kernel) : kernel_(std::move(kernel)) {}

  [[nodiscard]] std::string name() const override { return kernel_.name(); }
  [[nodiscard]] bool has_energy() const override { return Kernel::kHasEnergy; }
  [[nodiscard]] bool has_jacobian() const override { return Kernel::kHasJacobian; }
  [[nodiscard]] const Kernel& kernel() const { return kernel_; }
  [[nodiscard]] Kernel& kernel() { return kernel_; }

  /// Forwards to `kernel.end_step(s, dt)` when the kernel has internal state.
  void end_step(const StateView& s, double dt) override {
    if constexpr (requires { kernel_.end_step(s, dt); }) kernel_.end_step(s, dt);
  }
  /// Forwards to the kernel's save_state / load_state when it has internal state.
  void save_state(StateArchive& archive) const override {
    if constexpr (requires { kernel_.save_state(archive); }) kernel_.save_state(archive);
  }
  void load_state(const StateArchive& archive) override {
    if constexpr (requires { kernel_.load_state(archive); }) kernel_.load_state(archive);
  }
  /// Forwards to `kernel.add_cell_fields(s, element_count, fields)` when the kernel has output fields.
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const override {
    if constexpr (requires { kernel_.add_cell_fields(s, element_count, fields); })
      kernel_.add_cell_fields(s, element_count, fields);
  }
  /// Forwards to `kernel.add_cell_tensors(s, element_count, fields)` when the kernel has tensor fields.
  void add_cell_tensors(const StateView& s, std::size_t element_count,
                        std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>>& fields) const override {
    if constexpr (requires { kernel_.add_cell_tensors(s, element_count, fields); })
      kernel_.add_cell_tensors(s, element_count, fields);
  }
  [[nodiscard]] std::string describe() const override { return std::to_string(kernel_.size()) + " items"; }

  // Augmented Lagrangian (solver/core/augmented_lagrangian.hpp), for a kernel with a
  // `VolumeMultipliers multipliers` member and gap(i, x, t) = J_i - r, penalty_slope(i, x, t) = U'(J_i; r);
  // or, with several multipliers per item, update_multipliers(i, x, t) (and gap the item's largest).
  [[nodiscard]] AugmentedLagrangian augmented_lagrangian() const override {
    if constexpr (requires { kernel_.multipliers.settings; }) return kernel_.multipliers.settings;
    return {};
  }
  [[nodiscard]] double constraint_violation(const StateView& s) const override {
    double worst = 0.0;
    if constexpr (requires { kernel_.multipliers.settings; }) {
      Mat3N<N> x, v;
      for (std::size_t i = 0; i < kernel_.size(); ++i) {
        gather(s, kernel_.stencil(i), x, v);
        worst = std::max(worst, std::abs(kernel_.gap(i, x, s.t)));
      }
    }
    return worst;
  }
  void update_multipliers(const StateView& s) override {
    if constexpr (requires { kernel_.multipliers.settings; }) {
      if (kernel_.multipliers.lambda.empty()) return;
      Mat3N<N> x, v;
      for (std::size_t i = 0; i < kernel_.size(); ++i) {
        gather(s, kernel_.stencil(i), x, v);
        if constexpr (requires { kernel_.update_multipliers(i, x, s.t); }) {
          kernel_.update_multipliers(i, x, s.t);  // several multipliers per item
        } else {
          kernel_.multipliers.lambda[i] += kernel_.penalty_slope(i, x, s.t);
        }
      }
    }
  }
  [[nodiscard]] std::vector<double> multipliers() const override {
    if constexpr (requires { kernel_.multipliers.settings; }) return kernel_.multipliers.lambda;
    return {};
  }
  void set_multipliers(const std::vector<double>& lambda) override {
    if constexpr (requires { kernel_.multipliers.settings; }) kernel_.multipliers.assign(lambda);
  }

  [[nodiscard]] double energy(const StateView& s) const override {
    if constexpr (Kernel::kHasEnergy) {
      double e = 0.0;
      Mat3N<N> x, v;
      for (std::size_t i = 0; i < kernel_.size(); ++i) {
        gather(s, kernel_.stencil(i), x, v);
        e += kernel_.energy(i, x, v, s.t);
      }
      return e;
    } else {
      throw std::logic_error("force term '" + name() + "' has no energy");
    }
  }

  /// Forces of all items. Items are evaluated in parallel (OpenMP) into a per-item buffer,
  /// then summed per node in a fixed order (increasing item index) -- the result is the same
  /// bit for bit whatever the number of threads. Small terms run serially.
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override {
    if constexpr (requires { kernel_.add_forces_bulk(s, f); }) {
      if (kernel_.size() > 0) kernel_.add_forces_bulk(s, f);
    } else {
      add_forces_per_item(s, f);
    }
  }

  /// The generic path: the kernel's forces() item by item (what add_forces does for kernels
  /// without add_forces_bulk; tests compare the two). Inside an OwnedForceScope only the items
  /// touching the owned particles, summed into those particles only (solver/core/owned_nodes.hpp).
  void add_forces_per_item(const StateView& s, Eigen::Matrix3Xd& f) const {
    const std::size_t n = kernel_.size();
    if (n == 0) return;
    const OwnedNodes* owned = owned_force_nodes();
    const ScatterTable& table = prepare_scatter(owned);
    const std::size_t m = owned != nullptr ? table.items.size() : n;
    local_.resize(3 * N, static_cast<Eigen::Index>(m));
    const auto ni = static_cast<std::ptrdiff_t>(m);
    const bool par = m >= kParallelMin;
    LowestFailure failure;
#pragma omp parallel for schedule(static) if (par)
    for (std::ptrdiff_t ii = 0; ii < ni; ++ii) {
      const std::size_t i = owned != nullptr ? table.items[static_cast<std::size_t>(ii)] : static_cast<std::size_t>(ii);
      Mat3N<N> x, v, fl;
      gather(s, kernel_.stencil(i), x, v);
      fl.setZero();
      try {
        kernel_.forces(i, x, v, s.t, fl);
      } catch (...) {
        failure.record(static_cast<std::ptrdiff_t>(i));
      }
      local_.col(ii) = Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(fl.data());
    }
    failure.rethrow();
    const auto rows = static_cast<std::ptrdiff_t>(table.node.size());
#pragma omp parallel for schedule(static) if (par)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      Eigen::Vector3d acc = Eigen::Vector3d::Zero();
      for (std::size_t k = table.begin[static_cast<std::size_t>(r)]; k < table.begin[static_cast<std::size_t>(r) + 1];
           ++k) {
        const std::size_t slot = table.slot[k];  // (position in the evaluated items) * N + a
        acc +=
            local_.template block<3, 1>(static_cast<Eigen::Index>(3 * (slot % N)), static_cast<Eigen::Index>(slot / N));
      }
      f.col(table.node[static_cast<std::size_t>(r)]) += acc;
    }
  }

  /// Jacobian blocks of all items. Items are evaluated in parallel (OpenMP) a chunk at a time
  /// into per-item local matrices, which are then handed to the sink in item order, one
  /// add_stencil per item: the sums are the same bit for bit whatever the number of threads.
  /// Items the sink does not accept (no particle of this MPI rank) are skipped.
  void add_jacobian(const StateView& s, JacobianSink& sink) const override {
    if constexpr (Kernel::kHasJacobian) {
      const std::size_t n = kernel_.size();
      for (std::size_t first = 0; first < n; first += kJacobianChunk) {
        const std::size_t count = std::min(kJacobianChunk, n - first);
        jac_x_.resize(count);
        jac_v_.resize(count);
        const auto nc = static_cast<std::ptrdiff_t>(count);
        LowestFailure failure;
#pragma omp parallel for schedule(static) if (count >= kParallelMin)
        for (std::ptrdiff_t c = 0; c < nc; ++c) {
          const auto cu = static_cast<std::size_t>(c);
          const std::array<Index, N> st = kernel_.stencil(first + cu);
          if (!sink.accepts(st.data(), N)) continue;  // another MPI rank's rows only
          Mat3N<N> x, v;
          gather(s, st, x, v);
          jac_x_[cu].setZero();
          jac_v_[cu].setZero();
          try {
            kernel_.jacobian(first + cu, x, v, s.t, jac_x_[cu], jac_v_[cu]);
          } catch (...) {
            failure.record(c);
          }
        }
        failure.rethrow();
        for (std::size_t c = 0; c < count; ++c) {
          const std::array<Index, N> st = kernel_.stencil(first + c);
          if (sink.accepts(st.data(), N)) sink.add_stencil(st.data(), N, jac_x_[c].data(), jac_v_[c].data());
        }
      }
    } else {
      throw std::logic_error("force term '" + name() + "' has no Jacobian (explicit integrators only)");
    }
  }

 private:
  /// The lowest-numbered item whose kernel call threw inside a parallel loop; rethrown after the
  /// loop, so the error reported does not depend on the number of threads. record() is called
  /// from the catch block.
  class LowestFailure {
   public:
    void record(std::ptrdiff_t item) {
#pragma omp critical(adamss_stencil_failure)
      if (item_ < 0 || item < item_) {
        item_ = item;
        error_ = std::current_exception();
      }
    }
    void rethrow() const {
      if (error_) std::rethrow_exception(error_);
    }

   private:
    std::ptrdiff_t item_ = -1;
    std::exception_ptr error_;
  };

  static void gather(const StateView& s, const std::array<Index, N>& st, Mat3N<N>& x, Mat3N<N>& v) {
    for (int a = 0; a < N; ++a) {
      x.col(a) = s.x.col(st[static_cast<std::size_t>(a)]);
      v.col(a) = s.v.col(st[static_cast<std::size_t>(a)]);
    }
  }

  /// The node -> (item, slot) table that sums the item forces per node, in item order: over every
  /// item, or for an owned range over the items touching it (`items`) and into its particles only.
  struct ScatterTable {
    std::vector<Index> node;
    std::vector<std::size_t> begin, slot;
    std::vector<std::size_t> items;  ///< owned range only: the items evaluated
    std::size_t item_count = 0;      ///< kernel_.size() when built
    Index first = 0, last = -1;      ///< the owned range it was built for
    bool ready = false;
  };

  /// The table for the whole evaluation or for `owned`, built once (one of each is kept: a term
  /// evaluated both inside and outside a scope, the cavity constraint's unit pressure, does not
  /// rebuild it at every call).
  const ScatterTable& prepare_scatter(const OwnedNodes* owned) const {
    ScatterTable& t = owned != nullptr ? owned_table_ : full_table_;
    const Index b = owned != nullptr ? owned->begin : 0, e = owned != nullptr ? owned->end : -1;
    const std::size_t n = kernel_.size();
    if (t.ready && t.item_count == n && t.first == b && t.last == e) return t;
    t.items.clear();
    std::vector<std::pair<Index, std::size_t>> pairs;  // (node, position * N + a), in item order
    pairs.reserve(n * N);
    for (std::size_t i = 0; i < n; ++i) {
      const std::array<Index, N> st = kernel_.stencil(i);
      if (owned != nullptr) {
        if (std::none_of(st.begin(), st.end(), [&](Index a) { return owned->contains(a); })) continue;
        t.items.push_back(i);
      }
      const std::size_t pos = owned != nullptr ? t.items.size() - 1 : i;
      for (int a = 0; a < N; ++a) {
        const Index node = st[static_cast<std::size_t>(a)];
        if (owned == nullptr || owned->contains(node)) pairs.emplace_back(node, pos * N + static_cast<std::size_t>(a));
      }
    }
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
    t.node.clear();
    t.begin.clear();
    t.slot.resize(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (k == 0 || pairs[k].first != pairs[k - 1].first) {
        t.node.push_back(pairs[k].first);
        t.begin.push_back(k);
      }
      t.slot[k] = pairs[k].second;
    }
    t.begin.push_back(pairs.size());
    t.item_count = n;
    t.first = b;
    t.last = e;
    t.ready = true;
    return t;
  }

  static constexpr std::size_t kParallelMin = 256;
  /// Items per parallel batch of add_jacobian. The batch's local Jacobians (2 x 9 N^2 doubles an
  /// item: 2.4 MB for 256 hexahedra) stay in the cache between the kernel that writes them and
  /// the sink that reads them. 1024 took Land problem 1's 16 assemblies from 0.103 to 0.126 s (one
  /// thread; the first assembly also page-faults in 4 x 3 MB); biv-inflation-coarse.yaml (2
  /// threads) is the same either way (11.78 against 11.85 s, 3 pairs).
  static constexpr std::size_t kJacobianChunk = 256;
  Kernel kernel_;
  // Work space of add_forces (not thread-safe across concurrent calls on the same term).
  mutable Eigen::Matrix<double, 3 * N, Eigen::Dynamic> local_;
  mutable ScatterTable full_table_, owned_table_;
  mutable std::vector<MatJ<N>> jac_x_, jac_v_;  ///< a chunk's local Jacobians (add_jacobian)
};

}  // namespace adamss::solver
