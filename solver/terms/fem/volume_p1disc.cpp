#include "solver/terms/fem/volume_p1disc.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "preprocess/mesh/shape_functions_q2.hpp"
#include "solver/core/element_subset.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"

namespace adamss::solver {

namespace {

constexpr int kK = LinearDilatationKernel::kNodes;
constexpr int kP = LinearDilatationKernel::kModes;

/// psi(q) = (1, r - 1/2, s - 1/2, t - 1/2) at Gauss point q.
Eigen::Matrix<double, 1, kP> basis(int q) {
  const Eigen::Vector3d p = preprocess::hex27_gauss_point(q);
  return {1.0, p.x() - 0.5, p.y() - 0.5, p.z() - 0.5};
}

/// det(x Gamma_q) for the 27 points, and c_lq = w_q psi_l(q) (the determinant-term coefficients of b).
struct PointDets {
  Eigen::Matrix<double, kK, 1> det;
  std::array<Mat3N<kK>, kK> ddet;  ///< d det / dx, 3 x 27 per point
};

void point_dets(const Mat3N<kK>& x, PointDets& out, bool gradients) {
  const auto& grads = preprocess::hex27_gauss_gradients();
  for (int q = 0; q < kK; ++q) {
    double d = 0.0;
    Mat3N<kK> dd = Mat3N<kK>::Zero();
    add_determinant_term<kK>(1.0, grads[static_cast<std::size_t>(q)], x, d, dd, nullptr);
    out.det[q] = d;
    if (gradients) out.ddet[static_cast<std::size_t>(q)] = dd;
  }
}

double coefficient(int l, int q) {
  return preprocess::hex27_gauss_weight(q) * basis(q)[l];
}

/// b_l = sum_q c_lq det(x Gamma_q) (m^3), the moments of J against the basis.
Eigen::Matrix<double, kP, 1> moments(const PointDets& pd) {
  Eigen::Matrix<double, kP, 1> b = Eigen::Matrix<double, kP, 1>::Zero();
  for (int q = 0; q < kK; ++q) {
    for (int l = 0; l < kP; ++l) b[l] += coefficient(l, q) * pd.det[q];
  }
  return b;
}

/// [v]_x, with [v]_x d = v x d.
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Gamma stacked by point: G(3q + j, b) = d N_b / d xi_j at Gauss point q (81 x 27), the same for
/// every element.
const Eigen::Matrix<double, 3 * kK, kK>& stacked_gradients() {
  static const Eigen::Matrix<double, 3 * kK, kK> kStacked = [] {
    Eigen::Matrix<double, 3 * kK, kK> m;
    const auto& grads = preprocess::hex27_gauss_gradients();
    for (int q = 0; q < kK; ++q) m.middleRows<3>(3 * q) = grads[static_cast<std::size_t>(q)].transpose();
    return m;
  }();
  return kStacked;
}

/// dfdx -= sum_q c_q d^2 det(x Gamma_q) / dx^2 (the second term of df/dx above, with c_q =
/// sum_l lambda_l c_lq). Block (a, b) of the Hessian of det(x Gamma_q) is
/// -[F_q (gamma_qa x gamma_qb)]_x (volume_preservation.hpp), so block (a, b) gains [w_ab]_x with
///   w_ab = sum_q c_q F_q (gamma_qa x gamma_qb) = sum_q (c_q F_q [gamma_qa]_x) gamma_qb,
/// and with A(3a + i, 3q + j) = (c_q F_q [gamma_qa]_x)_ij all the w_ab are one product
/// W = A G (81 x 81 times 81 x 27; W(3a + i, b) = w_ab,i): 177 000 multiply-adds per element in
/// one dense product, instead of 27 x 351 cross products, each scattered into two 3 x 3 blocks.
/// (w_ba = -w_ab, so block (b, a) = [w_ab]_x^T, the Hessian's symmetry; w_aa = 0.)
void add_weighted_determinant_hessians(const Eigen::Matrix<double, kK, 1>& c, const Mat3N<kK>& x, MatJ<kK>& dfdx) {
  const auto& grads = preprocess::hex27_gauss_gradients();
  Eigen::Matrix<double, 3 * kK, 3 * kK> a;
  for (int q = 0; q < kK; ++q) {
    const Eigen::Matrix<double, kK, 3>& gamma = grads[static_cast<std::size_t>(q)];
    const Eigen::Matrix3d cf = c[q] * (x * gamma);
    for (int n = 0; n < kK; ++n) {
      const Eigen::Vector3d g = gamma.row(n).transpose();
      a.block<3, 3>(3 * n, 3 * q).noalias() = cf * cross_matrix(g);
    }
  }
  Eigen::Matrix<double, 3 * kK, kK> w;
  w.noalias() = a * stacked_gradients();
  // Block (n, b) from w_nb with b > n, block (b, n) its transpose: the matrix stays symmetric to the
  // last bit (w_bn = -w_nb only to rounding), so symmetric loads keep symmetric Newton iterates.
  for (int n = 0; n < kK; ++n) {
    for (int b = n + 1; b < kK; ++b) {
      const Eigen::Matrix3d h = cross_matrix(w.block<3, 1>(3 * n, b));  // [w_nb]_x
      dfdx.block<3, 3>(3 * n, 3 * b) += h;
      dfdx.block<3, 3>(3 * b, 3 * n) += h.transpose();
    }
  }
}

}  // namespace

Eigen::Matrix<double, kK, 1> LinearDilatationKernel::projected_dilatation(std::size_t i, const Mat3N<kK>& x) const {
  PointDets pd;
  point_dets(x, pd, false);
  return projection[i] * moments(pd);
}

double LinearDilatationKernel::energy(std::size_t i, const Mat3N<kK>& x, const Mat3N<kK>& /*v*/, double t) const {
  const Eigen::Matrix<double, kK, 1> theta = projected_dilatation(i, x);
  const double r = ratio(t);
  double e = 0.0;
  for (int q = 0; q < kK; ++q) {
    const double lambda = multipliers[i * kK + static_cast<std::size_t>(q)];
    e += point_volume[i][static_cast<std::size_t>(q)] * (penalty.value(theta[q], r) + lambda * (theta[q] - r));
  }
  return e;
}

void LinearDilatationKernel::forces(std::size_t i, const Mat3N<kK>& x, const Mat3N<kK>& /*v*/, double t,
                                    Mat3N<kK>& f) const {
  PointDets pd;
  point_dets(x, pd, true);
  const Eigen::Matrix<double, kK, 1> theta = projection[i] * moments(pd);
  const double r = ratio(t);
  Eigen::Matrix<double, kP, 1> lambda = Eigen::Matrix<double, kP, 1>::Zero();
  for (int q = 0; q < kK; ++q) {
    lambda += point_volume[i][static_cast<std::size_t>(q)] * pressure_slope(i, q, theta[q], r) *
              projection[i].row(q).transpose();
  }
  for (int q = 0; q < kK; ++q) {
    double c = 0.0;
    for (int l = 0; l < kP; ++l) c += lambda[l] * coefficient(l, q);
    f.noalias() -= c * pd.ddet[static_cast<std::size_t>(q)];
  }
}

void LinearDilatationKernel::jacobian(std::size_t i, const Mat3N<kK>& x, const Mat3N<kK>& /*v*/, double t,
                                      MatJ<kK>& dfdx, MatJ<kK>& /*dfdv*/) const {
  PointDets pd;
  point_dets(x, pd, true);
  Eigen::Matrix<double, 3 * kK, kP> D = Eigen::Matrix<double, 3 * kK, kP>::Zero();  // db_l/dx as columns
  for (int q = 0; q < kK; ++q) {
    const Eigen::Map<const Eigen::Matrix<double, 3 * kK, 1>> g(pd.ddet[static_cast<std::size_t>(q)].data());
    for (int l = 0; l < kP; ++l) D.col(l) += coefficient(l, q) * g;
  }
  const Eigen::Matrix<double, kK, 1> theta = projection[i] * moments(pd);
  const double r = ratio(t);
  Eigen::Matrix<double, kP, 1> lambda = Eigen::Matrix<double, kP, 1>::Zero();
  Eigen::Matrix<double, kP, kP> k4 = Eigen::Matrix<double, kP, kP>::Zero();
  for (int q = 0; q < kK; ++q) {
    const double vq = point_volume[i][static_cast<std::size_t>(q)];
    const Eigen::Matrix<double, kP, 1> a = projection[i].row(q).transpose();
    lambda += vq * pressure_slope(i, q, theta[q], r) * a;
    k4.noalias() += vq * penalty.curvature(theta[q], r) * (a * a.transpose());
  }
  dfdx.noalias() -= D * k4 * D.transpose();
  Eigen::Matrix<double, kK, 1> c;
  for (int q = 0; q < kK; ++q) {
    c[q] = 0.0;
    for (int l = 0; l < kP; ++l) c[q] += lambda[l] * coefficient(l, q);
  }
  add_weighted_determinant_hessians(c, x, dfdx);
}

void LinearDilatationKernel::add_cell_fields(const StateView& s, std::size_t element_count,
                                             std::map<std::string, Eigen::VectorXd>& fields) const {
  Eigen::VectorXd& out = fields["volumetric_stress"];
  if (out.size() != static_cast<Eigen::Index>(element_count))
    out = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(element_count));
  const double r = ratio(s.t);
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Mat3N<kK> x = element_positions<kK>(s.x, elements[i].data());
    const Eigen::Matrix<double, kK, 1> theta = projected_dilatation(i, x);
    double sum = 0.0, vol = 0.0;
    for (int q = 0; q < kK; ++q) {
      const double vq = point_volume[i][static_cast<std::size_t>(q)];
      sum += vq * pressure_slope(i, q, theta[q], r);
      vol += vq;
    }
    out[static_cast<Eigen::Index>(mesh_element[i])] += sum / vol;
  }
}

double LinearDilatationKernel::gap(std::size_t i, const Mat3N<kK>& x, double t) const {
  return (projected_dilatation(i, x).array() - ratio(t)).abs().maxCoeff();
}

void LinearDilatationKernel::update_multipliers(std::size_t i, const Mat3N<kK>& x, double t) {
  if (multipliers.lambda.empty()) return;
  const Eigen::Matrix<double, kK, 1> theta = projected_dilatation(i, x);
  const double r = ratio(t);
  for (int q = 0; q < kK; ++q) multipliers.lambda[i * kK + static_cast<std::size_t>(q)] += penalty.slope(theta[q], r);
}

std::unique_ptr<ForceTerm> make_linear_dilatation_term(const preprocess::Mesh& mesh, VolumePenalty penalty,
                                                       TimeCourse ratio, const std::vector<std::size_t>* element_subset,
                                                       const AugmentedLagrangian& augmented) {
  const std::string who = "volume_preservation (distribution linear)";
  if (mesh.type != preprocess::ElementType::Hex27) {
    throw InputError(who +
                     ": the linear (P1-discontinuous) dilatation is built for triquadratic hexahedra (hex27), "
                     "this mesh has " +
                     preprocess::element_type_name(mesh.type) + " elements");
  }
  check_volume_penalty(penalty.p, who);
  check_volume_ratio(ratio, who);
  check_augmented_lagrangian(augmented, who);
  LinearDilatationKernel kern;
  kern.multipliers.settings = augmented;
  kern.penalty = penalty;
  kern.ratio = std::move(ratio);
  const auto& grads = preprocess::hex27_gauss_gradients();
  std::vector<std::size_t> selected = selected_elements(mesh, element_subset, who);
  std::sort(selected.begin(), selected.end());
  selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
  for (const std::size_t e : selected) {
    const Index* n = mesh.element(e);
    std::array<Index, kK> st{};
    Mat3N<kK> x0;
    for (int a = 0; a < kK; ++a) {
      st[static_cast<std::size_t>(a)] = n[a];
      x0.col(a) = mesh.nodes.col(n[a]);
    }
    std::array<double, kK> vq{};
    Eigen::Matrix<double, kK, kP> psi;
    Eigen::Matrix<double, kP, kP> m = Eigen::Matrix<double, kP, kP>::Zero();
    for (int q = 0; q < kK; ++q) {
      const double det = (x0 * grads[static_cast<std::size_t>(q)]).determinant();
      if (!(det > 0.0)) {
        std::ostringstream os;
        os << who << ": element " << e << " is inverted or flat at Gauss point " << q << " (det J = " << det << ")";
        throw InputError(os.str());
      }
      vq[static_cast<std::size_t>(q)] = preprocess::hex27_gauss_weight(q) * det;
      psi.row(q) = basis(q);
      m.noalias() += vq[static_cast<std::size_t>(q)] * (psi.row(q).transpose() * psi.row(q));
    }
    kern.elements.push_back(st);
    kern.mesh_element.push_back(e);
    kern.point_volume.push_back(vq);
    kern.projection.emplace_back(psi * m.inverse());
  }
  if (kern.elements.empty()) throw InputError(who + ": no elements selected");
  kern.multipliers.resize(kern.elements.size() * kK);
  return std::make_unique<StencilTerm<LinearDilatationKernel, kK>>(std::move(kern));
}

}  // namespace adamss::solver
