#include "solver/terms/fem/nodal_volume_p2.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/shape_functions_p2.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/nodal_constraint_term.hpp"

namespace adamss::solver {
namespace {

constexpr const char* kTerm = "volume_preservation (nodal, tet10)";
constexpr int kQ = 5;  // points of the degree-3 rule

/// The rule's shape-function gradients and its weights times the corner functions, w_q L_c(xi_q).
struct Rule {
  std::array<Eigen::Matrix<double, 10, 3>, kQ> gamma;
  std::array<std::array<double, 4>, kQ> wl{};
  Rule() {
    const auto& r = preprocess::tet10_volume_rule();
    gamma = preprocess::tet10_rule_gradients(r);
    for (std::size_t q = 0; q < kQ; ++q) {
      const Eigen::Vector4d l = preprocess::tet_barycentric(r[q].p);
      for (std::size_t c = 0; c < 4; ++c) wl[q][c] = r[q].w * l[static_cast<Eigen::Index>(c)];
    }
  }
};

const Rule& rule() {
  static const Rule kRule;
  return kRule;
}

/// v_ec (c = 0..3) of the element at x, and (when dv) their gradients.
void corner_volumes(const Mat3N<10>& x, std::array<double, 4>& v, std::array<Mat3N<10>, 4>* dv) {
  v.fill(0.0);
  if (dv)
    for (auto& d : *dv) d.setZero();
  for (std::size_t q = 0; q < kQ; ++q) {
    for (std::size_t c = 0; c < 4; ++c) {
      double j = 0.0;
      Mat3N<10> g = Mat3N<10>::Zero();
      add_determinant_term<10>(rule().wl[q][c], rule().gamma[q], x, j, g, nullptr);
      v[c] += j;
      if (dv) (*dv)[c] += g;
    }
  }
}

class QuadraticNodalVolumeTerm final : public NodalConstraintTerm {
 public:
  QuadraticNodalVolumeTerm(const preprocess::Mesh& mesh, const NodalVolumeParams& params,
                           const std::vector<std::size_t>& selected);

  [[nodiscard]] std::string describe() const override {
    return "nodal (P1 on the corners of tet10), " + std::to_string(volume0_.size()) + " corner nodes on " +
           std::to_string(elements_.size()) + " elements, U " + volume_penalty_name(penalty_.form);
  }
  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override;
  void add_jacobian(const StateView& s, JacobianSink& sink) const override;
  void add_couplings(std::vector<std::vector<Index>>& adj) const override;
  [[nodiscard]] bool couplings_through_outer() const override { return true; }
  /// `volumetric_stress` per element: the mean of p_e over the element, sum_c U'_c v_ec / V_e.
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const override;

 private:
  /// J_c of every corner (pressure) node.
  [[nodiscard]] std::vector<double> ratios(const Eigen::Matrix3Xd& x) const override;
  [[nodiscard]] Mat3N<10> positions(const Eigen::Matrix3Xd& x, std::size_t e) const {
    return element_positions<10>(x, elements_[e].data());
  }

  std::vector<std::array<Index, 10>> elements_;  ///< global node indices
  std::vector<std::array<int, 4>> corner_;       ///< local corner (pressure node) index of corners 0..3
  std::vector<std::size_t> mesh_element_;
  std::vector<Index> corner_node_;  ///< global node of each pressure node (V0_c: volume0_)
  /// Elements around each pressure node (CSR) and the sorted global nodes of its patch.
  std::vector<std::size_t> around_start_, around_, patch_start_;
  std::vector<Index> patch_;
};

QuadraticNodalVolumeTerm::QuadraticNodalVolumeTerm(const preprocess::Mesh& mesh, const NodalVolumeParams& params,
                                                   const std::vector<std::size_t>& selected)
    : NodalConstraintTerm(params, kTerm) {
  std::vector<int> local_of(mesh.node_count(), -1);
  for (const std::size_t e : selected) {
    std::array<Index, 10> g{};
    for (int a = 0; a < 10; ++a) g[static_cast<std::size_t>(a)] = mesh.element(e)[a];
    std::array<int, 4> l{};
    for (std::size_t c = 0; c < 4; ++c) {
      int& loc = local_of[static_cast<std::size_t>(g[c])];
      if (loc < 0) {
        loc = static_cast<int>(corner_node_.size());
        corner_node_.push_back(g[c]);
        volume0_.push_back(0.0);
      }
      l[c] = loc;
    }
    std::array<double, 4> v{};
    corner_volumes(element_positions<10>(mesh.nodes, g.data()), v, nullptr);
    for (std::size_t c = 0; c < 4; ++c) {
      if (!std::isfinite(v[c]) || !(v[c] > 0.0)) {
        throw InputError(std::string(kTerm) + ": element " + std::to_string(e) + " has a corner volume of " +
                         std::to_string(v[c]) + " m^3 (must be > 0: an inverted or tangled element)");
      }
      volume0_[static_cast<std::size_t>(l[c])] += v[c];
    }
    elements_.push_back(g);
    corner_.push_back(l);
    mesh_element_.push_back(e);
  }
  const std::size_t nc = corner_node_.size();
  constraints_built();
  around_start_.assign(nc + 1, 0);
  for (const auto& l : corner_)
    for (const int c : l) ++around_start_[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 0; c < nc; ++c) around_start_[c + 1] += around_start_[c];
  around_.resize(around_start_[nc]);
  std::vector<std::size_t> fill(around_start_.begin(), around_start_.end() - 1);
  for (std::size_t e = 0; e < corner_.size(); ++e)
    for (const int c : corner_[e]) around_[fill[static_cast<std::size_t>(c)]++] = e;
  patch_start_.assign(nc + 1, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::size_t p0 = patch_.size();
    for (std::size_t j = around_start_[c]; j < around_start_[c + 1]; ++j)
      patch_.insert(patch_.end(), elements_[around_[j]].begin(), elements_[around_[j]].end());
    std::sort(patch_.begin() + static_cast<std::ptrdiff_t>(p0), patch_.end());
    patch_.erase(std::unique(patch_.begin() + static_cast<std::ptrdiff_t>(p0), patch_.end()), patch_.end());
    patch_start_[c + 1] = patch_.size();
  }
}

std::vector<double> QuadraticNodalVolumeTerm::ratios(const Eigen::Matrix3Xd& x) const {
  std::vector<double> jc(volume0_.size(), 0.0);
  std::array<double, 4> v{};
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    corner_volumes(positions(x, e), v, nullptr);
    for (std::size_t c = 0; c < 4; ++c) jc[static_cast<std::size_t>(corner_[e][c])] += v[c];
  }
  for (std::size_t c = 0; c < jc.size(); ++c) jc[c] /= volume0_[c];
  return jc;
}

void QuadraticNodalVolumeTerm::add_forces(const StateView& s, Eigen::Matrix3Xd& f) const {
  const std::vector<double> slope = slopes(s.x, s.t);  // U'_c + lambda_c
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const Mat3N<10> x = positions(s.x, e);
    Mat3N<10> g = Mat3N<10>::Zero();
    double unused = 0.0;
    for (std::size_t q = 0; q < kQ; ++q) {
      double pq = 0.0;  // w_q p_e(xi_q)
      for (std::size_t c = 0; c < 4; ++c) pq += rule().wl[q][c] * slope[static_cast<std::size_t>(corner_[e][c])];
      add_determinant_term<10>(pq, rule().gamma[q], x, unused, g, nullptr);
    }
    for (std::size_t a = 0; a < 10; ++a) f.col(elements_[e][a]) -= g.col(static_cast<Eigen::Index>(a));
  }
}

void QuadraticNodalVolumeTerm::add_jacobian(const StateView& s, JacobianSink& sink) const {
  const std::vector<double> jc = ratios(s.x);
  const double r = ratio_(s.t);
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  std::vector<std::array<Mat3N<10>, 4>> dv(elements_.size());
  MatJ<10> hess;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const Mat3N<10> x = positions(s.x, e);
    std::array<double, 4> v{};
    corner_volumes(x, v, &dv[e]);
    hess.setZero();
    Mat3N<10> unused_g = Mat3N<10>::Zero();
    double unused = 0.0;
    for (std::size_t q = 0; q < kQ; ++q) {
      double pq = 0.0;
      for (std::size_t c = 0; c < 4; ++c) {
        const auto lc = static_cast<std::size_t>(corner_[e][c]);
        pq += rule().wl[q][c] * (penalty_.slope(jc[lc], r) + mult_[lc]);
      }
      add_determinant_term<10>(pq, rule().gamma[q], x, unused, unused_g, &hess);
    }
    for (std::size_t a = 0; a < 10; ++a) {
      for (std::size_t b = 0; b < 10; ++b) {
        if (a != b) sink.add_block(elements_[e][a], elements_[e][b], -hess.block<3, 3>(3 * a, 3 * b), zero);
      }
    }
  }
  Eigen::Matrix3Xd g;
  for (std::size_t c = 0; c < volume0_.size(); ++c) {
    const std::size_t p0 = patch_start_[c], m = patch_start_[c + 1] - p0;
    g.setZero(3, static_cast<Eigen::Index>(m));
    for (std::size_t j = around_start_[c]; j < around_start_[c + 1]; ++j) {
      const std::size_t e = around_[j];
      const auto lc = static_cast<std::size_t>(std::find(corner_[e].begin(), corner_[e].end(), static_cast<int>(c)) -
                                               corner_[e].begin());
      for (std::size_t a = 0; a < 10; ++a) {
        const auto at = static_cast<std::size_t>(std::lower_bound(patch_.begin() + static_cast<std::ptrdiff_t>(p0),
                                                                  patch_.begin() + static_cast<std::ptrdiff_t>(p0 + m),
                                                                  elements_[e][a]) -
                                                 (patch_.begin() + static_cast<std::ptrdiff_t>(p0)));
        g.col(static_cast<Eigen::Index>(at)) += dv[e][lc].col(static_cast<Eigen::Index>(a));
      }
    }
    // -(U''_c / V0_c) g_c g_c^T on the corner's patch, as one outer product (JacobianSink::add_outer).
    sink.add_outer(&patch_[p0], static_cast<int>(m), g.data(), -penalty_.curvature(jc[c], r) / volume0_[c]);
  }
}

void QuadraticNodalVolumeTerm::add_couplings(std::vector<std::vector<Index>>& adj) const {
  for (std::size_t c = 0; c < volume0_.size(); ++c) {
    for (std::size_t p = patch_start_[c]; p < patch_start_[c + 1]; ++p) {
      auto& row = adj[static_cast<std::size_t>(patch_[p])];
      row.insert(row.end(), patch_.begin() + static_cast<std::ptrdiff_t>(patch_start_[c]),
                 patch_.begin() + static_cast<std::ptrdiff_t>(patch_start_[c + 1]));
    }
  }
}

void QuadraticNodalVolumeTerm::add_cell_fields(const StateView& s, std::size_t element_count,
                                               std::map<std::string, Eigen::VectorXd>& fields) const {
  Eigen::VectorXd& out = fields["volumetric_stress"];
  const auto n = static_cast<Eigen::Index>(element_count);
  if (out.size() != n) out = Eigen::VectorXd::Zero(n);
  const std::vector<double> slope = slopes(s.x, s.t);  // U'_c + lambda_c
  std::array<double, 4> v{};
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    corner_volumes(positions(s.x, e), v, nullptr);
    double num = 0.0, den = 0.0;
    for (std::size_t c = 0; c < 4; ++c) {
      num += slope[static_cast<std::size_t>(corner_[e][c])] * v[c];
      den += v[c];
    }
    out[static_cast<Eigen::Index>(mesh_element_[e])] += num / den;
  }
}

}  // namespace

std::unique_ptr<ForceTerm> make_quadratic_nodal_volume_term(const preprocess::Mesh& mesh,
                                                            const NodalVolumeParams& params,
                                                            const std::vector<std::size_t>& selected) {
  if (!params.constrain_fixed_nodes) {
    throw InputError(std::string(kTerm) +
                     ": constrain_fixed_nodes: false is built for linear tetrahedra and hexahedra, not for the tet10 "
                     "corner projection (P2-P1 does not lock with the fixed nodes constrained)");
  }
  return std::make_unique<QuadraticNodalVolumeTerm>(mesh, params, selected);
}

}  // namespace adamss::solver
