#include "solver/terms/adamss/hourglass.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"

namespace adamss::solver {
namespace {

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// Natural corner coordinates of the VTK hexahedron: 0 (---), 1 (+--), 2 (++-), 3 (-+-),
/// 4 (--+), 5 (+-+), 6 (+++), 7 (-++).
constexpr double kXi[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
constexpr double kEta[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
constexpr double kZeta[8] = {-1, -1, -1, -1, 1, 1, 1, 1};

}  // namespace

Eigen::Matrix<double, 8, 4> hourglass_vectors(const Mat3N<8>& x_ref) {
  Eigen::Matrix<double, 8, 4> h;
  Eigen::Matrix<double, 8, 3> dn;  // dN_a/dxi at the centre: xi_a / 8, ...
  for (int a = 0; a < 8; ++a) {
    h(a, 0) = kXi[a] * kEta[a];
    h(a, 1) = kEta[a] * kZeta[a];
    h(a, 2) = kZeta[a] * kXi[a];
    h(a, 3) = kXi[a] * kEta[a] * kZeta[a];
    dn(a, 0) = kXi[a] / 8.0;
    dn(a, 1) = kEta[a] / 8.0;
    dn(a, 2) = kZeta[a] / 8.0;
  }
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
    // V0 = the 2x2x2 Gauss integral of det(dX/dxi) (exact for the trilinear element).
    double v0 = 0.0;
    const double gp = 1.0 / std::sqrt(3.0);
    for (int q = 0; q < 8; ++q) {
      const double s[3] = {(q & 1) ? gp : -gp, (q & 2) ? gp : -gp, (q & 4) ? gp : -gp};
      Eigen::Matrix<double, 8, 3> dn;
      for (int a = 0; a < 8; ++a) {
        const double n[3] = {kXi[a], kEta[a], kZeta[a]};
        for (int d = 0; d < 3; ++d) {
          double v = n[d] / 8.0;
          for (int o = 0; o < 3; ++o)
            if (o != d) v *= 1.0 + n[o] * s[o];
          dn(a, d) = v;
        }
      }
      v0 += (x * dn).determinant();
    }
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
