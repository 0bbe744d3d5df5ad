#include "solver/terms/fem/nodal_volume.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "solver/core/element_subset.hpp"
#include "solver/core/owned_nodes.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/nodal_constraint_term.hpp"
#include "solver/terms/fem/nodal_volume_p2.hpp"

namespace adamss::solver {
namespace {

constexpr const char* kTerm = "volume_preservation (nodal)";

/// The term for K-node elements (4: tetrahedron, 8: hexahedron); see the header for the math.
/// Nodes are numbered locally (0 .. nodes_.size() - 1) over the selected elements only.
template <int K>
class NodalVolumeTerm final : public NodalConstraintTerm {
 public:
  NodalVolumeTerm(const preprocess::Mesh& mesh, const NodalVolumeParams& params,
                  const std::vector<std::size_t>& selected);

  [[nodiscard]] std::string describe() const override {
    return "nodal, " + std::to_string(nodes_.size()) + " nodes on " + std::to_string(elements_.size()) +
           " elements, U " + volume_penalty_name(penalty_.form) + released_note();
  }

  void add_forces(const StateView& s, Eigen::Matrix3Xd& f) const override;
  void add_jacobian(const StateView& s, JacobianSink& sink) const override;
  void add_couplings(std::vector<std::vector<Index>>& adj) const override;
  [[nodiscard]] bool couplings_through_outer() const override { return true; }
  /// constrain_fixed_nodes: false. A node whose three coordinates are fixed or prescribed gives its
  /// share of each element's volume to the element's other nodes (w_ea = 0 for it, 1 / (number of
  /// free nodes of e) for those), so it carries no constraint, V_n = sum_e w_en V_e still sums to
  /// the total volume, and the free nodes' constraints hold the whole volume. An element with no
  /// free node (it cannot move) leaves the sum.
  void set_boundary_mask(const std::vector<std::uint8_t>& mask) override;
  /// `volumetric_stress` (Pa, positive in tension) per element: c_e = sum_{n in e} U'_n / K, the
  /// hydrostatic Cauchy stress that the element's forces -c_e dV_e/dx carry (the result writer
  /// adds it to the stress tensors; solver/run/results.hpp).
  void add_cell_fields(const StateView& s, std::size_t element_count,
                       std::map<std::string, Eigen::VectorXd>& fields) const override;

 private:
  /// Current nodal volume ratios J_n = V_n / V0_n.
  [[nodiscard]] std::vector<double> ratios(const Eigen::Matrix3Xd& x) const override;
  /// Node patches (elements around each node and their nodes' places in the patch).
  void build_patches();
  /// V0_n = sum_e w_en V0_e (volume0_) from the shares.
  void sum_reference_volumes();

  std::vector<std::array<Index, K>> elements_;  ///< global node indices
  std::vector<std::array<int, K>> local_;       ///< local node indices of each element
  std::vector<std::size_t> mesh_element_;       ///< mesh element index of each element
  std::vector<Index> nodes_;                    ///< global index of each local node (V0_n: volume0_)
  // Node patches, CSR over local nodes: the elements around node n are
  // around_[around_start_[n] .. around_start_[n + 1]); the patch nodes (global indices, in the
  // order of their local ones) patch_[patch_start_[n] .. patch_start_[n + 1]); place_[j][a] is
  // where node a of element around_[j] sits in node n's patch.
  std::vector<std::size_t> around_start_, around_, patch_start_;
  std::vector<Index> patch_;
  std::vector<std::array<int, K>> place_;
  std::vector<double> element_volume0_;       ///< V0_e (m^3)
  std::vector<std::array<double, K>> share_;  ///< w_ea: node a's share of V_e (1/K; see set_boundary_mask)
};

template <int K>
NodalVolumeTerm<K>::NodalVolumeTerm(const preprocess::Mesh& mesh, const NodalVolumeParams& params,
                                    const std::vector<std::size_t>& selected)
    : NodalConstraintTerm(params, kTerm) {
  std::vector<int> local_of(mesh.node_count(), -1);
  for (const std::size_t e : selected) {
    std::array<Index, K> g{};
    std::array<int, K> l{};
    const Index* n = mesh.element(e);
    for (int a = 0; a < K; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      g[ua] = n[a];
      int& loc = local_of[static_cast<std::size_t>(n[a])];
      if (loc < 0) {
        loc = static_cast<int>(nodes_.size());
        nodes_.push_back(n[a]);
        volume0_.push_back(0.0);
      }
      l[ua] = loc;
    }
    const double v0 = element_volume_of<K>(element_positions<K>(mesh.nodes, n));
    if (!std::isfinite(v0) || !(v0 > 0.0)) {
      throw InputError(std::string(kTerm) + ": element " + std::to_string(e) + " has reference volume " +
                       std::to_string(v0) + " m^3 (must be > 0: an inverted or flat element)");
    }
    element_volume0_.push_back(v0);
    std::array<double, K> w{};
    w.fill(1.0 / K);
    share_.push_back(w);
    elements_.push_back(g);
    local_.push_back(l);
    mesh_element_.push_back(e);
  }
  sum_reference_volumes();
  constraints_built();
  build_patches();
}

template <int K>
void NodalVolumeTerm<K>::sum_reference_volumes() {
  std::fill(volume0_.begin(), volume0_.end(), 0.0);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    for (std::size_t a = 0; a < K; ++a)
      volume0_[static_cast<std::size_t>(local_[e][a])] += share_[e][a] * element_volume0_[e];
  }
}

template <int K>
void NodalVolumeTerm<K>::build_patches() {
  const std::size_t nn = nodes_.size();
  around_start_.assign(nn + 1, 0);
  for (const auto& l : local_)
    for (const int n : l) ++around_start_[static_cast<std::size_t>(n) + 1];
  for (std::size_t n = 0; n < nn; ++n) around_start_[n + 1] += around_start_[n];
  around_.resize(around_start_[nn]);
  std::vector<std::size_t> fill(around_start_.begin(), around_start_.end() - 1);
  for (std::size_t e = 0; e < local_.size(); ++e)
    for (const int n : local_[e]) around_[fill[static_cast<std::size_t>(n)]++] = e;
  patch_start_.assign(nn + 1, 0);
  place_.resize(around_.size());
  std::vector<int> members;
  for (std::size_t n = 0; n < nn; ++n) {
    members.clear();
    for (std::size_t j = around_start_[n]; j < around_start_[n + 1]; ++j)
      members.insert(members.end(), local_[around_[j]].begin(), local_[around_[j]].end());
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    for (std::size_t j = around_start_[n]; j < around_start_[n + 1]; ++j) {
      for (int a = 0; a < K; ++a) {
        const int m = local_[around_[j]][static_cast<std::size_t>(a)];
        place_[j][static_cast<std::size_t>(a)] =
            static_cast<int>(std::lower_bound(members.begin(), members.end(), m) - members.begin());
      }
    }
    for (const int m : members) patch_.push_back(nodes_[static_cast<std::size_t>(m)]);
    patch_start_[n + 1] = patch_.size();
  }
}

template <int K>
std::vector<double> NodalVolumeTerm<K>::ratios(const Eigen::Matrix3Xd& x) const {
  std::vector<double> jn(nodes_.size(), 0.0);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const double ve = element_volume_of<K>(element_positions<K>(x, elements_[e].data()));
    for (std::size_t a = 0; a < K; ++a) {
      jn[static_cast<std::size_t>(local_[e][a])] += share_[e][a] * ve;
    }
  }
  for (std::size_t n = 0; n < nodes_.size(); ++n) jn[n] = active(n) ? jn[n] / volume0_[n] : 1.0;
  return jn;
}

template <int K>
void NodalVolumeTerm<K>::add_forces(const StateView& s, Eigen::Matrix3Xd& f) const {
  const std::vector<double> jn = slopes(s.x, s.t);  // U'_n + lambda_n
  // On several MPI ranks (solver/core/owned_nodes.hpp) only the elements touching this rank's
  // particles; their forces are then those of the whole loop, summed in the same element order.
  const OwnedNodes* owned = owned_force_nodes();
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    if (owned != nullptr &&
        std::none_of(elements_[e].begin(), elements_[e].end(), [&](Index n) { return owned->contains(n); }))
      continue;
    double c = 0.0;  // c_e = sum_{n in e} w_en U'_n
    for (std::size_t a = 0; a < K; ++a) {
      c += share_[e][a] * jn[static_cast<std::size_t>(local_[e][a])];
    }
    const Mat3N<K> dv = element_volume_gradient<K>(element_positions<K>(s.x, elements_[e].data()));
    for (int a = 0; a < K; ++a) f.col(elements_[e][static_cast<std::size_t>(a)]) -= c * dv.col(a);
  }
}

template <int K>
void NodalVolumeTerm<K>::add_jacobian(const StateView& s, JacobianSink& sink) const {
  std::vector<double> jn = ratios(s.x);
  const double r = ratio_(s.t);
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  // -sum_e c_e H_e on the element stencils; keep dV_e/dx for the patch sums.
  std::vector<Mat3N<K>> dv(elements_.size());
  MatJ<K> hess;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    double c = 0.0, v = 0.0;
    for (int a = 0; a < K; ++a) {
      const auto un = static_cast<std::size_t>(local_[e][static_cast<std::size_t>(a)]);
      if (active(un)) c += share_[e][static_cast<std::size_t>(a)] * (penalty_.slope(jn[un], r) + mult_[un]);
    }
    element_volume_derivatives<K>(element_positions<K>(s.x, elements_[e].data()), v, dv[e], hess);
    for (int a = 0; a < K; ++a) {
      if (!sink.accepts(&elements_[e][static_cast<std::size_t>(a)], 1)) continue;  // another MPI rank's row
      for (int b = 0; b < K; ++b) {
        if (a == b) continue;  // H_aa = 0
        sink.add_block(elements_[e][static_cast<std::size_t>(a)], elements_[e][static_cast<std::size_t>(b)],
                       -c * hess.template block<3, 3>(3 * a, 3 * b), zero);
      }
    }
  }
  // -(U''_n / V0_n) g_n g_n^T on each node's patch, as one outer product (JacobianSink::add_outer).
  Eigen::Matrix3Xd g;
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    if (!active(n)) continue;  // a released constraint (constrain_fixed_nodes: false)
    const std::size_t p0 = patch_start_[n], m = patch_start_[n + 1] - p0;
    g.setZero(3, static_cast<Eigen::Index>(m));
    for (std::size_t j = around_start_[n]; j < around_start_[n + 1]; ++j) {
      const std::size_t e = around_[j];
      const auto& le = local_[e];
      const double wn =
          share_[e][static_cast<std::size_t>(std::find(le.begin(), le.end(), static_cast<int>(n)) - le.begin())];
      for (int a = 0; a < K; ++a) g.col(place_[j][static_cast<std::size_t>(a)]) += wn * dv[e].col(a);
    }
    sink.add_outer(&patch_[p0], static_cast<int>(m), g.data(), -penalty_.curvature(jn[n], r) / volume0_[n]);
  }
}

template <int K>
void NodalVolumeTerm<K>::set_boundary_mask(const std::vector<std::uint8_t>& mask) {
  if (constrain_fixed_) return;
  const auto fixed = [&](int local) {
    const auto n = static_cast<std::size_t>(nodes_[static_cast<std::size_t>(local)]);
    return n < mask.size() && (mask[n] & 7U) == 7U;
  };
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    int free = 0;
    for (const int l : local_[e]) free += fixed(l) ? 0 : 1;
    for (std::size_t a = 0; a < K; ++a) share_[e][a] = free == 0 || fixed(local_[e][a]) ? 0.0 : 1.0 / free;
  }
  sum_reference_volumes();
  for (std::size_t n = 0; n < nodes_.size(); ++n) active_[n] = volume0_[n] > 0.0 ? 1 : 0;
}

template <int K>
void NodalVolumeTerm<K>::add_cell_fields(const StateView& s, std::size_t element_count,
                                         std::map<std::string, Eigen::VectorXd>& fields) const {
  Eigen::VectorXd& q = fields["volumetric_stress"];
  const auto n = static_cast<Eigen::Index>(element_count);
  if (q.size() != n) q = Eigen::VectorXd::Zero(n);
  const std::vector<double> jn = slopes(s.x, s.t);  // U'_n + lambda_n
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    double c = 0.0;
    for (std::size_t a = 0; a < K; ++a) {
      c += share_[e][a] * jn[static_cast<std::size_t>(local_[e][a])];
    }
    q[static_cast<Eigen::Index>(mesh_element_[e])] += c;
  }
}

template <int K>
void NodalVolumeTerm<K>::add_couplings(std::vector<std::vector<Index>>& adj) const {
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    for (std::size_t p = patch_start_[n]; p < patch_start_[n + 1]; ++p) {
      auto& row = adj[static_cast<std::size_t>(patch_[p])];
      row.insert(row.end(), patch_.begin() + static_cast<std::ptrdiff_t>(patch_start_[n]),
                 patch_.begin() + static_cast<std::ptrdiff_t>(patch_start_[n + 1]));
    }
  }
}

}  // namespace

std::unique_ptr<ForceTerm> make_nodal_volume_term(const preprocess::Mesh& mesh, const NodalVolumeParams& params,
                                                  const std::vector<std::size_t>* element_subset) {
  check_volume_penalty(params.penalty.p, kTerm);
  check_volume_ratio(params.ratio, kTerm);
  check_augmented_lagrangian(params.augmented, kTerm);
  const std::vector<std::size_t> selected = selected_elements(mesh, element_subset, kTerm);
  if (selected.empty()) throw InputError(std::string(kTerm) + ": no elements selected");
  if (mesh.type == preprocess::ElementType::Tet4) return std::make_unique<NodalVolumeTerm<4>>(mesh, params, selected);
  if (mesh.type == preprocess::ElementType::Tet10) return make_quadratic_nodal_volume_term(mesh, params, selected);
  if (mesh.type == preprocess::ElementType::Hex27) {
    throw InputError(std::string(kTerm) +
                     ": distribution nodal is not built for triquadratic hexahedra (hex27); use distribution linear "
                     "(the Q2-P1disc element)");
  }
  return std::make_unique<NodalVolumeTerm<8>>(mesh, params, selected);
}

}  // namespace adamss::solver
