#include "solver/terms/adamss/hourglass.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {
namespace {

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// Reference volume V0 = the 2x2x2 Gauss integral of det(dX/dxi) over the natural cube
/// (exact for the trilinear element).
double reference_volume(const Mat3N<8>& x) {
  double v0 = 0.0;
  for (int q = 0; q < 8; ++q) v0 += (x * hex_natural_shape_gradients(hex_natural_gauss_point(q))).determinant();
  return v0;
}

}  // namespace

Eigen::Matrix<double, 8, 4> hourglass_vectors(const Mat3N<8>& x_ref) {
  Eigen::Matrix<double, 8, 4> h;
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d c = hex_natural_corner(a);  // (xi_a, eta_a, zeta_a)
    h(a, 0) = c[0] * c[1];
    h(a, 1) = c[1] * c[2];
    h(a, 2) = c[2] * c[0];
    h(a, 3) = c[0] * c[1] * c[2];
  }
  // dN_a/dxi at the centre: xi_a / 8, ...
  const Eigen::Matrix<double, 8, 3> dn = hex_natural_shape_gradients(Eigen::Vector3d::Zero());
  const Eigen::Matrix3d jac = x_ref * dn;  // dX/dxi at the centre
  const double det = jac.determinant();
  if (!std::isfinite(det) || !(det > 0.0)) {
    throw InputError("hourglass: element with a singular or inverted centre Jacobian (det " + fmt(det) + " m^3)");
  }
  const Eigen::Matrix<double, 8, 3> b = dn * jac.inverse();  // column i = b_i = dN/dX_i (1/m)
  // gamma_alpha = h_alpha - sum_i (h_alpha . X_i) b_i, X_i = row i of x_ref.
  return h - b * (x_ref * h);
}

double HourglassKernel::energy(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& /*v*/, double /*t*/) const {
  return 0.5 * stiffness[i] * (x * gamma[i]).squaredNorm();
}

void HourglassKernel::forces(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& /*v*/, double /*t*/, Mat3N<8>& f) const {
  const Eigen::Matrix<double, 3, 4> q = x * gamma[i];
  f.noalias() -= stiffness[i] * (q * gamma[i].transpose());
}

void HourglassKernel::jacobian(std::size_t i, const Mat3N<8>& /*x*/, const Mat3N<8>& /*v*/, double /*t*/, MatJ<8>& dfdx,
                               MatJ<8>& /*dfdv*/) const {
  const Eigen::Matrix<double, 8, 8> gg = gamma[i] * gamma[i].transpose();
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) dfdx.block<3, 3>(3 * a, 3 * b).diagonal().array() -= stiffness[i] * gg(a, b);
}

HourglassKernel make_hourglass_kernel(const preprocess::Mesh& mesh, const HourglassParams& params,
                                      const std::vector<std::size_t>* element_subset) {
  if (!std::isfinite(params.fraction) || !(params.fraction > 0.0)) {
    throw InputError("hourglass: fraction (stiffness relative to the material modulus) must be finite and > 0, got " +
                     fmt(params.fraction));
  }
  if (!std::isfinite(params.modulus) || !(params.modulus > 0.0)) {
    throw InputError("hourglass: modulus (the material's small-strain modulus, Pa) must be finite and > 0, got " +
                     fmt(params.modulus));
  }
  if (mesh.type != preprocess::ElementType::Hex8) {
    throw InputError(std::string("hourglass: needs a hexahedral mesh (topology hex); this mesh has ") +
                     preprocess::element_type_name(mesh.type) + " elements, which have no hourglass modes");
  }
  const std::size_t ne = mesh.element_count();
  std::vector<std::size_t> all;
  if (!element_subset) {
    all.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) all[e] = e;
    element_subset = &all;
  }
  HourglassKernel k;
  k.elements.reserve(element_subset->size());
  k.gamma.reserve(element_subset->size());
  k.stiffness.reserve(element_subset->size());
  for (const std::size_t e : *element_subset) {
    if (e >= ne) {
      throw InputError("hourglass: element " + std::to_string(e) + " out of range (mesh has " + std::to_string(ne) +
                       ")");
    }
    std::array<Index, 8> nodes{};
    Mat3N<8> x;
    const Index* c = mesh.element(e);
    for (int a = 0; a < 8; ++a) {
      nodes[static_cast<std::size_t>(a)] = c[a];
      x.col(a) = mesh.nodes.col(c[a]);
    }
    Eigen::Matrix<double, 8, 4> g;
    try {
      g = hourglass_vectors(x);
    } catch (const InputError& err) {
      throw InputError(std::string(err.what()) + " at element " + std::to_string(e));
    }
    const double v0 = reference_volume(x);
    if (!std::isfinite(v0) || !(v0 > 0.0)) {
      throw InputError("hourglass: element " + std::to_string(e) + " has reference volume " + fmt(v0) +
                       " m^3 (must be > 0)");
    }
    const double l2 = std::pow(v0, 2.0 / 3.0);
    k.elements.push_back(nodes);
    k.gamma.push_back(g);
    k.stiffness.push_back(params.fraction * params.modulus * v0 / (64.0 * l2));
  }
  return k;
}

std::unique_ptr<ForceTerm> make_hourglass_term(const preprocess::Mesh& mesh, const HourglassParams& params,
                                               const std::vector<std::size_t>* element_subset) {
  return std::make_unique<StencilTerm<HourglassKernel, 8>>(make_hourglass_kernel(mesh, params, element_subset));
}

}  // namespace adamss::solver
