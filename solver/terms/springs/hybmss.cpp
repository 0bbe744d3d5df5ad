#include "solver/terms/springs/hybmss.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <map>

#include "solver/core/element_subset.hpp"
#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {
namespace {

// alpha, beta, gamma of eq. 5.14 for VTK order: +-1/4 by the x, y, z bit of each corner, the
// trilinear shape-function gradients at the cell centre (element_rules.hpp).
constexpr std::array<double, 8> kAlpha = hex_centre_gradient(0);
constexpr std::array<double, 8> kBeta = hex_centre_gradient(1);
constexpr std::array<double, 8> kGamma = hex_centre_gradient(2);
static_assert(kAlpha[1] == 0.25 && kBeta[3] == 0.25 && kGamma[0] == -0.25);

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

std::vector<std::size_t> selected_cells(const preprocess::Mesh& mesh, const std::vector<std::size_t>* subset) {
  if (mesh.type != preprocess::ElementType::Hex8) {
    throw InputError("hybmss: needs a hexahedral mesh (mesh topology 'hex'); this mesh has tetrahedra");
  }
  return selected_elements(mesh, subset, "hybmss");
}

Mat3N<8> cell_nodes(const preprocess::Mesh& mesh, std::size_t e) {
  Mat3N<8> x;
  const Index* n = mesh.element(e);
  for (int a = 0; a < 8; ++a) x.col(a) = mesh.nodes.col(n[a]);
  return x;
}

double reference_volume(const preprocess::Mesh& mesh, std::size_t e) {
  const double v = hybmss_cell_volume(cell_nodes(mesh, e));
  if (!(v > 0.0)) {
    throw InputError("hybmss: element " + std::to_string(e) +
                     " has a non-positive volume a.(b x c) = " + std::to_string(v) + " m^3 (eq. 5.13)");
  }
  return v;
}

}  // namespace

HybmssSpringConstants hybmss_spring_constants(double shear_modulus, double A, double edge_length) {
  HybmssSpringConstants k;
  k.k_c = 3.0 * shear_modulus * edge_length / (4.0 + 3.0 * A);
  k.k_f = A * k.k_c;
  k.k_e = shear_modulus * edge_length * (8.0 + 3.0 * A) / (4.0 + 3.0 * A);
  return k;
}

double hybmss_shear_modulus(double youngs_modulus, double poisson_ratio) {
  return youngs_modulus / (2.0 * (1.0 + poisson_ratio));
}

double hybmss_kappa(double youngs_modulus, double poisson_ratio) {
  return youngs_modulus * (4.0 * poisson_ratio - 1.0) / (2.0 * (1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

void validate_hybmss_params(const HybmssParams& p) {
  if (!(p.youngs_modulus > 0.0) || !std::isfinite(p.youngs_modulus)) {
    throw InputError("hybmss.youngs_modulus: must be a positive pressure (Pa), got " +
                     std::to_string(p.youngs_modulus));
  }
  if (!(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5)) {
    throw InputError("hybmss.poisson_ratio: must lie in (-1, 0.5), got " + std::to_string(p.poisson_ratio));
  }
  if (!(p.A >= 0.0) || !std::isfinite(p.A)) {
    throw InputError("hybmss.A: the ratio k_f/k_c must be a finite number >= 0 (0 = HybMSS-FD), got " +
                     std::to_string(p.A));
  }
}

double hybmss_cell_volume(const Mat3N<8>& x, Mat3N<8>* gradient) {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = a, c = a;
  for (int n = 0; n < 8; ++n) {
    a += kAlpha[static_cast<std::size_t>(n)] * x.col(n);
    b += kBeta[static_cast<std::size_t>(n)] * x.col(n);
    c += kGamma[static_cast<std::size_t>(n)] * x.col(n);
  }
  const Eigen::Vector3d bc = b.cross(c), ca = c.cross(a), ab = a.cross(b);
  if (gradient != nullptr) {
    for (int n = 0; n < 8; ++n) {
      const auto k = static_cast<std::size_t>(n);
      gradient->col(n) = kAlpha[k] * bc + kBeta[k] * ca + kGamma[k] * ab;
    }
  }
  return a.dot(bc);
}

EdgeSpringKernel make_hybmss_spring_kernel(const preprocess::Mesh& mesh, const HybmssParams& params,
                                           const std::vector<std::size_t>* element_subset) {
  validate_hybmss_params(params);
  std::map<std::array<Index, 2>, double> springs;  // sorted node pair -> summed stiffness
  // A collapsed edge of a degenerate hexahedron (a wedge of the ellipsoid's apex ring: repeated
  // node) joins a node to itself: no spring.
  auto add = [&springs](Index a, Index b, double k) {
    if (a != b) springs[{std::min(a, b), std::max(a, b)}] += k;
  };
  for (const std::size_t e : selected_cells(mesh, element_subset)) {
    const double le = std::cbrt(reference_volume(mesh, e));
    const HybmssSpringConstants k =
        hybmss_spring_constants(hybmss_shear_modulus(params.youngs_modulus, params.poisson_ratio), params.A, le);
    const Index* n = mesh.element(e);
    for (const auto& p : preprocess::kHexEdges) add(n[p[0]], n[p[1]], 0.25 * k.k_e);
    if (params.A > 0.0)
      for (const auto& p : preprocess::kHexFaceDiagonals) add(n[p[0]], n[p[1]], 0.5 * k.k_f);
    for (const auto& p : preprocess::kHexCellDiagonals) add(n[p[0]], n[p[1]], k.k_c);
  }
  return edge_springs_from_sums(springs, mesh.nodes, "hybmss_springs");
}

double HybmssVolumeKernel::energy(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& /*v*/, double /*t*/) const {
  const double dv = hybmss_cell_volume(x) - volume0[i];
  return 0.5 * kappa / volume0[i] * dv * dv;
}

void HybmssVolumeKernel::forces(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& /*v*/, double /*t*/,
                                Mat3N<8>& f) const {
  Mat3N<8> g;
  const double vol = hybmss_cell_volume(x, &g);
  f.noalias() -= (kappa * (vol - volume0[i]) / volume0[i]) * g;
}

void HybmssVolumeKernel::jacobian(std::size_t i, const Mat3N<8>& x, const Mat3N<8>& /*v*/, double /*t*/, MatJ<8>& dfdx,
                                  MatJ<8>& /*dfdv*/) const {
  Mat3N<8> g;
  const double vol = hybmss_cell_volume(x, &g);
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = a, c = a;
  for (int n = 0; n < 8; ++n) {
    a += kAlpha[static_cast<std::size_t>(n)] * x.col(n);
    b += kBeta[static_cast<std::size_t>(n)] * x.col(n);
    c += kGamma[static_cast<std::size_t>(n)] * x.col(n);
  }
  const double s = kappa / volume0[i];
  const double dv = vol - volume0[i];
  for (int n = 0; n < 8; ++n) {
    const auto un = static_cast<std::size_t>(n);
    for (int m = 0; m < 8; ++m) {
      const auto um = static_cast<std::size_t>(m);
      const Eigen::Vector3d w = (kAlpha[un] * kBeta[um] - kBeta[un] * kAlpha[um]) * c -
                                (kAlpha[un] * kGamma[um] - kGamma[un] * kAlpha[um]) * b +
                                (kBeta[un] * kGamma[um] - kGamma[un] * kBeta[um]) * a;
      // df_n/dx_m = -s [ g_n g_m^T + dv H_nm ],  H_nm = -[w]x
      dfdx.block<3, 3>(3 * n, 3 * m) -= s * (g.col(n) * g.col(m).transpose() - dv * cross_matrix(w));
    }
  }
}

HybmssVolumeKernel make_hybmss_volume_kernel(const preprocess::Mesh& mesh, const HybmssParams& params,
                                             const std::vector<std::size_t>* element_subset) {
  validate_hybmss_params(params);
  HybmssVolumeKernel kern;
  kern.kappa = hybmss_kappa(params.youngs_modulus, params.poisson_ratio);
  for (const std::size_t e : selected_cells(mesh, element_subset)) {
    std::array<Index, 8> st{};
    const Index* n = mesh.element(e);
    for (int a = 0; a < 8; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.cells.push_back(st);
    kern.volume0.push_back(reference_volume(mesh, e));
  }
  return kern;
}

std::vector<std::unique_ptr<ForceTerm>> make_hybmss_terms(const preprocess::Mesh& mesh, const HybmssParams& params,
                                                          const std::vector<std::size_t>* element_subset) {
  std::vector<std::unique_ptr<ForceTerm>> out;
  out.push_back(
      std::make_unique<StencilTerm<EdgeSpringKernel, 2>>(make_hybmss_spring_kernel(mesh, params, element_subset)));
  HybmssVolumeKernel vol = make_hybmss_volume_kernel(mesh, params, element_subset);
  if (vol.kappa != 0.0) out.push_back(std::make_unique<StencilTerm<HybmssVolumeKernel, 8>>(std::move(vol)));
  return out;
}

}  // namespace adamss::solver
