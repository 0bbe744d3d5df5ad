#include "solver/core/force_term.hpp"

#include "common/error.hpp"

namespace adamss::solver {

void JacobianSink::add_stencil(const Index* nodes, int n, const double* dfdx, const double* dfdv) {
  const Eigen::Index ld = 3 * static_cast<Eigen::Index>(n);
  using Block = Eigen::Map<const Eigen::Matrix3d, 0, Eigen::OuterStride<>>;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const Eigen::Index off = 3 * (static_cast<Eigen::Index>(b) * ld + a);
      add_block(nodes[a], nodes[b], Block(dfdx + off, Eigen::OuterStride<>(ld)),
                Block(dfdv + off, Eigen::OuterStride<>(ld)));
    }
  }
}

void JacobianSink::add_outer(const Index* nodes, int n, const double* g, double c) {
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  for (int a = 0; a < n; ++a) {
    if (!accepts(nodes + a, 1)) continue;  // another MPI rank's row
    const Eigen::Map<const Eigen::Vector3d> ga(g + 3 * a);
    for (int b = 0; b < n; ++b) {
      const Eigen::Map<const Eigen::Vector3d> gb(g + 3 * b);
      add_block(nodes[a], nodes[b], c * ga * gb.transpose(), zero);
    }
  }
}

void require_jacobians(const std::vector<std::unique_ptr<ForceTerm>>& terms, const std::string& solver_name) {
  std::string missing;
  for (const auto& t : terms) {
    if (!t->has_jacobian()) missing += (missing.empty() ? "" : ", ") + t->name();
  }
  if (!missing.empty()) {
    throw InputError(solver_name + " needs the Jacobian of every force term, but these are explicit-only: " + missing +
                     " (use an explicit integrator or another form of these terms)");
  }
}

std::vector<CavityConstraintTerm*> cavity_constraints(const std::vector<std::unique_ptr<ForceTerm>>& terms) {
  std::vector<CavityConstraintTerm*> out;
  for (const auto& t : terms)
    if (CavityConstraintTerm* c = t->cavity_constraint()) out.push_back(c);
  return out;
}

std::vector<ForceTerm*> augmented_terms(const std::vector<std::unique_ptr<ForceTerm>>& terms) {
  std::vector<ForceTerm*> out;
  for (const auto& t : terms)
    if (t->augmented_lagrangian().enabled) out.push_back(t.get());
  return out;
}

double total_energy(const std::vector<std::unique_ptr<ForceTerm>>& terms, const StateView& s) {
  double e = 0.0;
  for (const auto& t : terms)
    if (t->has_energy()) e += t->energy(s);
  return e;
}

}  // namespace adamss::solver
