#include "solver/terms/adamss/volume_preservation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "solver/core/element_subset.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {
namespace {

/// Cross-product matrix [v]_x: [v]_x w = v x w.
Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// cof(F) = det(F) F^{-T}, columns F_1 x F_2, F_2 x F_0, F_0 x F_1.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& f) {
  Eigen::Matrix3d c;
  c.col(0) = f.col(1).cross(f.col(2));
  c.col(1) = f.col(2).cross(f.col(0));
  c.col(2) = f.col(0).cross(f.col(1));
  return c;
}

/// The hexahedron's volume Hessian in closed form. With F_g = x Gamma_g at the 8 Gauss points
/// (weight 1/8 each), the block (a, b) of d^2 V / dx^2 is
///   H_ab = -(1/8) sum_g [F_g (gamma_ga x gamma_gb)]_x = -[x w_ab]_x,
///   w_ab = (1/8) sum_g Gamma_g (gamma_ga x gamma_gb)    (an 8-vector, gamma_ga = row a of Gamma_g),
/// because F_g v = x (Gamma_g v) is linear in x. The 28 vectors w_ab (a < b) depend only on the
/// reference cube, so the Hessian costs one 3 x 8 product per pair instead of 8 (the trilinear
/// volume is a cubic in x, its Hessian linear); H_ba = H_ab^T = -H_ab (skew blocks), H_aa = 0.
struct HexVolumeHessianTable {
  std::array<Eigen::Matrix<double, 8, 1>, 28> w;
  HexVolumeHessianTable() {
    int k = 0;
    for (int a = 0; a < 8; ++a) {
      for (int b = a + 1; b < 8; ++b, ++k) {
        w[k].setZero();
        for (const auto& g : hex_gauss_gradients()) {
          const Eigen::Vector3d ga = g.row(a).transpose(), gb = g.row(b).transpose();
          w[k] += g * ga.cross(gb) / 8.0;
        }
      }
    }
  }
};

/// Adds c d^2V/dx^2 of a hexahedron at x (HexVolumeHessianTable).
void add_hex_volume_hessian(double c, const Mat3N<8>& x, MatJ<8>& hess) {
  static const HexVolumeHessianTable kTable;
  int k = 0;
  for (int a = 0; a < 8; ++a) {
    for (int b = a + 1; b < 8; ++b, ++k) {
      const Eigen::Vector3d u = -c * (x * kTable.w[k]);
      const Eigen::Matrix3d h = skew(u);
      hess.template block<3, 3>(3 * a, 3 * b) += h;
      hess.template block<3, 3>(3 * b, 3 * a) -= h;  // h^T = -h
    }
  }
}

/// Adds scale * V(x) to J and scale * dV/dx to dJ (and the Hessian when hess).
template <int K>
void add_volume(double scale, const Mat3N<K>& x, double& J, Mat3N<K>& dJ, MatJ<K>* hess) {
  // The exact volume quadrature of element_rules.hpp: tet one term, X Gamma = (x1-x0, x2-x0, x3-x0),
  // weight 1/6; hex the shape-function gradients at the 2x2x2 Gauss points of [0,1]^3, 1/8 each.
  if constexpr (K == 4) {
    static const Eigen::Matrix<double, 4, 3> kTetGamma = tet_shape_gradients();
    add_determinant_term<4>(scale / 6.0, kTetGamma, x, J, dJ, hess);
  } else if constexpr (K == 27) {
    // The triquadratic hexahedron: the 3x3x3 Gauss rule, exact for its det(dx/dr) of degree <= 5
    // per direction (preprocess/mesh/shape_functions_q2.hpp); J = V / V0 is the Q2-P0 mean dilatation.
    const auto& grads = preprocess::hex27_gauss_gradients();
    for (int q = 0; q < 27; ++q) {
      add_determinant_term<27>(scale * preprocess::hex27_gauss_weight(q), grads[static_cast<std::size_t>(q)], x, J, dJ,
                               hess);
    }
  } else if constexpr (K == 10) {
    // The quadratic tetrahedron: the 5-point degree-3 rule, exact for its cubic det(dx/dr)
    // (preprocess/mesh/shape_functions_p2.hpp); J = V / V0 is then the P2-P0 mean dilatation.
    static const auto kGrads = preprocess::tet10_rule_gradients(preprocess::tet10_volume_rule());
    for (std::size_t q = 0; q < kGrads.size(); ++q)
      add_determinant_term<10>(scale * preprocess::tet10_volume_rule()[q].w, kGrads[q], x, J, dJ, hess);
  } else {
    for (const auto& g : hex_gauss_gradients()) add_determinant_term<8>(scale / 8.0, g, x, J, dJ, nullptr);
    if (hess) add_hex_volume_hessian(scale, x, *hess);
  }
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

template <int K>
void add_determinant_term(double c, const Eigen::Matrix<double, K, 3>& gamma, const Mat3N<K>& x, double& J,
                          Mat3N<K>& dJ, MatJ<K>* hess) {
  const Eigen::Matrix3d F = x * gamma;
  const Eigen::Matrix3d cof = cofactor(F);
  J += c * F.col(0).dot(cof.col(0));  // det F = F_0 . (F_1 x F_2)
  dJ.noalias() += c * cof * gamma.transpose();
  if (hess) {
    for (int a = 0; a < K; ++a) {
      const Eigen::Vector3d ga = gamma.row(a).transpose();
      for (int b = a + 1; b < K; ++b) {
        const Eigen::Matrix3d h = -c * skew(F * ga.cross(Eigen::Vector3d(gamma.row(b).transpose())));
        hess->template block<3, 3>(3 * a, 3 * b) += h;
        hess->template block<3, 3>(3 * b, 3 * a) += h.transpose();
      }
    }
  }
}

template void add_determinant_term<4>(double, const Eigen::Matrix<double, 4, 3>&, const Mat3N<4>&, double&, Mat3N<4>&,
                                      MatJ<4>*);
template void add_determinant_term<8>(double, const Eigen::Matrix<double, 8, 3>&, const Mat3N<8>&, double&, Mat3N<8>&,
                                      MatJ<8>*);
template void add_determinant_term<10>(double, const Eigen::Matrix<double, 10, 3>&, const Mat3N<10>&, double&,
                                       Mat3N<10>&, MatJ<10>*);
template void add_determinant_term<27>(double, const Eigen::Matrix<double, 27, 3>&, const Mat3N<27>&, double&,
                                       Mat3N<27>&, MatJ<27>*);

/// The values that define the course; r must be finite and > 0 at all of them.
void check_volume_ratio(const TimeCourse& r, const std::string& who) {
  std::vector<double> vals;
  switch (r.kind) {
    case TimeCourse::Kind::Constant:
      vals = {r.value};
      break;
    case TimeCourse::Kind::Ramp:
      vals = {r.from, r.to};
      break;
    case TimeCourse::Kind::Table:
      vals = r.values;
      if (vals.empty()) throw InputError(who + ": r (target volume ratio) table is empty");
      break;
    case TimeCourse::Kind::Twitch:
      throw InputError(who +
                       ": r (target volume ratio) cannot be a twitch course (it returns to 0, a zero target "
                       "volume); use a ramp or a table");
  }
  for (double v : vals) {
    if (!std::isfinite(v) || !(v > 0.0)) {
      throw InputError(who + ": r (target volume ratio V_target/V0) must be finite and > 0, got " + fmt(v) + " (" +
                       r.describe() + ")");
    }
  }
}

void check_volume_penalty(double p, const std::string& who) {
  if (!std::isfinite(p) || !(p > 0.0)) {
    throw InputError(who + ": p (volume penalty coefficient, Pa) must be finite and > 0, got " + fmt(p));
  }
}

const char* volume_distribution_name(VolumeDistribution d) {
  return d == VolumeDistribution::Anisotropic ? "anisotropic" : "isotropic";
}

template <int K>
double element_volume_of(const Mat3N<K>& x) {
  double v = 0.0;
  Mat3N<K> dv = Mat3N<K>::Zero();
  add_volume<K>(1.0, x, v, dv, nullptr);
  return v;
}

template <int K>
Mat3N<K> element_volume_gradient(const Mat3N<K>& x) {
  double v = 0.0;
  Mat3N<K> dv = Mat3N<K>::Zero();
  add_volume<K>(1.0, x, v, dv, nullptr);
  return dv;
}

template <int K>
void element_volume_derivatives(const Mat3N<K>& x, double& v, Mat3N<K>& dv, MatJ<K>& hess) {
  v = 0.0;
  dv.setZero();
  hess.setZero();
  add_volume<K>(1.0, x, v, dv, &hess);
}

template void element_volume_derivatives<4>(const Mat3N<4>&, double&, Mat3N<4>&, MatJ<4>&);
template void element_volume_derivatives<8>(const Mat3N<8>&, double&, Mat3N<8>&, MatJ<8>&);
template void element_volume_derivatives<10>(const Mat3N<10>&, double&, Mat3N<10>&, MatJ<10>&);
template void element_volume_derivatives<27>(const Mat3N<27>&, double&, Mat3N<27>&, MatJ<27>&);
template double element_volume_of<4>(const Mat3N<4>&);
template double element_volume_of<8>(const Mat3N<8>&);
template double element_volume_of<10>(const Mat3N<10>&);
template double element_volume_of<27>(const Mat3N<27>&);
template Mat3N<4> element_volume_gradient<4>(const Mat3N<4>&);
template Mat3N<8> element_volume_gradient<8>(const Mat3N<8>&);
template Mat3N<10> element_volume_gradient<10>(const Mat3N<10>&);
template Mat3N<27> element_volume_gradient<27>(const Mat3N<27>&);

template <int K>
void VolumeKernel<K>::evaluate(std::size_t i, const Mat3N<K>& x, double& J, Mat3N<K>& dJ, MatJ<K>* hess) const {
  J = 0.0;
  dJ.setZero();
  if (distribution == VolumeDistribution::Anisotropic) {
    add_determinant_term<K>(1.0, gradient[i], x, J, dJ, hess);
  } else {
    add_volume<K>(1.0 / volume0[i], x, J, dJ, hess);
  }
}

template <int K>
double VolumeKernel<K>::volume_ratio(std::size_t i, const Mat3N<K>& x) const {
  double J = 0.0;
  Mat3N<K> dJ;
  evaluate(i, x, J, dJ, nullptr);
  return J;
}

template <int K>
double VolumeKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t) const {
  const double J = volume_ratio(i, x), r = ratio(t);
  const double al = multipliers[i] * (J - r);  // augmented Lagrangian, 0 for the plain penalty
  if (form != VolumePenaltyForm::Quadratic) return volume0[i] * (VolumePenalty{form, p}.value(J, r) + al);
  return volume0[i] * (p * (J - r) * (J - r) + al);
}

template <int K>
void VolumeKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t, Mat3N<K>& f) const {
  double J = 0.0;
  Mat3N<K> dJ;
  evaluate(i, x, J, dJ, nullptr);
  if (form != VolumePenaltyForm::Quadratic) {
    f.noalias() -= (volume0[i] * (VolumePenalty{form, p}.slope(J, ratio(t)) + multipliers[i])) * dJ;
    return;
  }
  f.noalias() -= (volume0[i] * (2.0 * p * (J - ratio(t)) + multipliers[i])) * dJ;
}

template <int K>
void VolumeKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t, MatJ<K>& dfdx,
                               MatJ<K>& /*dfdv*/) const {
  double J = 0.0;
  Mat3N<K> dJ;
  MatJ<K> hess = MatJ<K>::Zero();
  evaluate(i, x, J, dJ, &hess);
  const Eigen::Map<const Eigen::Matrix<double, 3 * K, 1>> g(dJ.data());
  if (form != VolumePenaltyForm::Quadratic) {
    const VolumePenalty u{form, p};
    const double r = ratio(t);
    dfdx.noalias() -= (volume0[i] * u.curvature(J, r)) * (g * g.transpose());
    dfdx.noalias() -= (volume0[i] * (u.slope(J, r) + multipliers[i])) * hess;
    return;
  }
  const double c = -2.0 * p * volume0[i];
  dfdx.noalias() += c * (g * g.transpose());
  dfdx.noalias() += (c * (J - ratio(t)) - volume0[i] * multipliers[i]) * hess;
}

template <int K>
void VolumeKernel<K>::add_cell_fields(const StateView& s, std::size_t element_count,
                                      std::map<std::string, Eigen::VectorXd>& fields) const {
  Eigen::VectorXd& q = fields["volumetric_stress"];
  if (q.size() != static_cast<Eigen::Index>(element_count))
    q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(element_count));
  const VolumePenalty u{form, p};
  const double r = ratio(s.t);
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Mat3N<K> x = element_positions<K>(s.x, elements[i].data());
    q[static_cast<Eigen::Index>(mesh_element[i])] += u.slope(volume_ratio(i, x), r) + multipliers[i];
  }
}

template struct VolumeKernel<4>;
template struct VolumeKernel<8>;
template struct VolumeKernel<10>;
template struct VolumeKernel<27>;

template <int K>
VolumeKernel<K> make_volume_kernel(const preprocess::Mesh& mesh, const AxisFrames* frames, const VolumeParams& params,
                                   const std::vector<std::size_t>* element_subset) {
  check_volume_penalty(params.p, "volume_preservation");
  check_volume_ratio(params.ratio, "volume_preservation");
  const preprocess::ElementType want = K == 4    ? preprocess::ElementType::Tet4
                                       : K == 10 ? preprocess::ElementType::Tet10
                                       : K == 27 ? preprocess::ElementType::Hex27
                                                 : preprocess::ElementType::Hex8;
  if (mesh.type != want) {
    throw InputError("volume_preservation: mesh element type " + std::string(preprocess::element_type_name(mesh.type)) +
                     " does not match a " + std::to_string(K) + "-node kernel");
  }
  const bool aniso = params.distribution == VolumeDistribution::Anisotropic;
  if ((K == 10 || K == 27) && aniso) {
    throw InputError(std::string("volume_preservation: quadratic ") +
                     (K == 10 ? "tetrahedra (tet10) take distribution nodal (P2-P1) or isotropic (P2-P0)"
                              : "hexahedra (hex27) take distribution linear (Q2-P1disc) or isotropic (Q2-P0)") +
                     "; the anisotropic distribution needs the axis frames of linear elements");
  }
  if (aniso && !frames) {
    throw InputError(
        "volume_preservation: the anisotropic distribution needs axis frames (fibres); none given (use "
        "distribution isotropic for a mesh without fibres)");
  }
  if (aniso && frames->type != want) {
    throw InputError("volume_preservation: axis-frame element type does not match the mesh");
  }
  // The selected elements, checked against the mesh; the isotropic items run in ascending order.
  std::vector<std::size_t> selected = selected_elements(mesh, element_subset, "volume_preservation");
  std::sort(selected.begin(), selected.end());
  selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
  VolumeKernel<K> kern;
  kern.distribution = params.distribution;
  kern.p = params.p;
  kern.form = params.form;
  kern.ratio = params.ratio;
  check_augmented_lagrangian(params.augmented, "volume_preservation");
  kern.multipliers.settings = params.augmented;
  auto push = [&](std::size_t e, double v0) {
    if (!std::isfinite(v0) || !(v0 > 0.0)) {
      throw InputError("volume_preservation: element " + std::to_string(e) + " has reference volume " + fmt(v0) +
                       " m^3 (must be > 0)");
    }
    std::array<Index, K> st{};
    const Index* n = mesh.element(e);
    for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.elements.push_back(st);
    kern.mesh_element.push_back(e);
    kern.volume0.push_back(v0);
  };
  if constexpr (K == 4 || K == 8) {
    if (aniso) {
      const auto& grads = frames->template nodal_gradient<K>();
      for (const std::size_t k : select_frame_entries("volume_preservation", mesh, *frames, K, element_subset)) {
        push(frames->element[k], frames->volume0[k]);
        kern.gradient.push_back(grads[k]);
      }
      kern.multipliers.resize(kern.size());
      return kern;
    }
  }
  for (const std::size_t e : selected) push(e, element_volume_of<K>(element_positions<K>(mesh.nodes, mesh.element(e))));
  kern.multipliers.resize(kern.size());
  return kern;
}

template VolumeKernel<4> make_volume_kernel<4>(const preprocess::Mesh&, const AxisFrames*, const VolumeParams&,
                                               const std::vector<std::size_t>*);
template VolumeKernel<8> make_volume_kernel<8>(const preprocess::Mesh&, const AxisFrames*, const VolumeParams&,
                                               const std::vector<std::size_t>*);
template VolumeKernel<10> make_volume_kernel<10>(const preprocess::Mesh&, const AxisFrames*, const VolumeParams&,
                                                 const std::vector<std::size_t>*);
template VolumeKernel<27> make_volume_kernel<27>(const preprocess::Mesh&, const AxisFrames*, const VolumeParams&,
                                                 const std::vector<std::size_t>*);

std::unique_ptr<ForceTerm> make_volume_term(const preprocess::Mesh& mesh, const AxisFrames* frames,
                                            const VolumeParams& params,
                                            const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) {
    return std::make_unique<StencilTerm<VolumeKernel<4>, 4>>(
        make_volume_kernel<4>(mesh, frames, params, element_subset));
  }
  if (mesh.type == preprocess::ElementType::Tet10) {
    return std::make_unique<StencilTerm<VolumeKernel<10>, 10>>(
        make_volume_kernel<10>(mesh, frames, params, element_subset));
  }
  if (mesh.type == preprocess::ElementType::Hex27) {
    return std::make_unique<StencilTerm<VolumeKernel<27>, 27>>(
        make_volume_kernel<27>(mesh, frames, params, element_subset));
  }
  return std::make_unique<StencilTerm<VolumeKernel<8>, 8>>(make_volume_kernel<8>(mesh, frames, params, element_subset));
}

}  // namespace adamss::solver
