#include "solver/terms/adamss/material_friction.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/terms/adamss/axis_term_support.hpp"

namespace adamss::solver {
namespace {

constexpr std::array<const char*, 3> kAxisName{"fibre", "sheet", "normal"};

double sign_of(double s) {
  return s > 0.0 ? 1.0 : (s < 0.0 ? -1.0 : 0.0);
}

}  // namespace

template <int K>
Eigen::Vector3d MaterialFrictionKernel<K>::face_vector_area(std::size_t i, int q, const Mat3N<K>& x) const {
  const auto& c = face_corners[i][static_cast<std::size_t>(q)];
  const Eigen::Vector3d p0 = x.col(c[0]);
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  for (int n = 1; n + 1 < kFaceCorners; ++n) {
    a += (x.col(c[static_cast<std::size_t>(n)]) - p0).cross(x.col(c[static_cast<std::size_t>(n + 1)]) - p0);
  }
  return 0.5 * a;
}

template <int K>
Eigen::Vector3d MaterialFrictionKernel<K>::damping(std::size_t i, const Mat3N<K>& x) const {
  if (!face_scaling) return coefficient[i];
  const Eigen::Matrix3d z = x * chord[i];
  Eigen::Vector3d c;
  for (int l = 0; l < 3; ++l) {
    const Eigen::Vector3d zh = z.col(l).normalized();
    c[l] = 0.5 * coefficient[i][l] *
           (std::abs(face_vector_area(i, 2 * l, x).dot(zh)) + std::abs(face_vector_area(i, 2 * l + 1, x).dot(zh)));
  }
  return c;
}

template <int K>
void MaterialFrictionKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double /*t*/,
                                       Mat3N<K>& f) const {
  const Eigen::Matrix<double, K, 3>& d = chord[i];
  const Eigen::Matrix3d z = x * d;
  const Eigen::Matrix3d zd = v * d;
  const Eigen::Vector3d c = damping(i, x);
  for (int l = 0; l < 3; ++l) {
    if (c[l] == 0.0) continue;
    const Eigen::Vector3d zh = z.col(l).normalized();
    const Eigen::Vector3d fl = -c[l] * zd.col(l).dot(zh) * zh;  // f_{2l}
    f.noalias() += fl * d.col(l).transpose();
  }
}

template <int K>
void MaterialFrictionKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double /*t*/,
                                         MatJ<K>& dfdx, MatJ<K>& dfdv) const {
  const Eigen::Matrix<double, K, 3>& d = chord[i];
  const Eigen::Matrix3d z = x * d;
  const Eigen::Matrix3d zd = v * d;
  std::array<Eigen::Matrix3d, 9> mx, mv;
  for (auto& m : mx) m.setZero();
  for (auto& m : mv) m.setZero();
  for (int l = 0; l < 3; ++l) {
    const double len = z.col(l).norm();
    const Eigen::Vector3d zh = z.col(l) / len;
    const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - zh * zh.transpose();
    const Eigen::Vector3d zdl = zd.col(l);
    const double w = zdl.dot(zh);
    const auto ll = static_cast<std::size_t>(4 * l);  // index 3 l + l
    double c = coefficient[i][l];
    if (!face_scaling) {
      mx[ll] = -c * (zh * zdl.transpose() + w * Eigen::Matrix3d::Identity()) * proj / len;
      mv[ll] = -c * zh * zh.transpose();
      continue;
    }
    const double kd = coefficient[i][l];
    if (kd == 0.0) continue;
    // Face scaling: c = kd/2 (|a+ . zh| + |a- . zh|) and its gradient.
    Eigen::Vector3d grad_zeta = Eigen::Vector3d::Zero();  // dc / d zeta_l
    Mat3N<K> grad_corner = Mat3N<K>::Zero();              // dc / d x_b through the face corners
    c = 0.0;
    for (int side = 0; side < 2; ++side) {
      const int q = 2 * l + side;
      const Eigen::Vector3d a = face_vector_area(i, q, x);
      const double s = a.dot(zh);
      const double sg = sign_of(s);
      c += 0.5 * kd * std::abs(s);
      grad_zeta += 0.5 * kd * sg * proj * a / len;
      const auto& cn = face_corners[i][static_cast<std::size_t>(q)];
      for (int n = 0; n < kFaceCorners; ++n) {
        const int prev = cn[static_cast<std::size_t>((n + kFaceCorners - 1) % kFaceCorners)];
        const int next = cn[static_cast<std::size_t>((n + 1) % kFaceCorners)];
        grad_corner.col(cn[static_cast<std::size_t>(n)]) +=
            0.25 * kd * sg * zh.cross(Eigen::Vector3d(x.col(prev) - x.col(next)));
      }
    }
    const Eigen::Vector3d fdir = -w * zh;  // d f_{2l} / d c
    mx[ll] = -c * (zh * zdl.transpose() + w * Eigen::Matrix3d::Identity()) * proj / len + fdir * grad_zeta.transpose();
    mv[ll] = -c * zh * zh.transpose();
    // Corner part: df_a/dx_b += D(a,l) fdir grad_corner_b^T.
    for (int a = 0; a < K; ++a) {
      const double dal = d(a, l);
      if (dal == 0.0) continue;
      for (int b = 0; b < K; ++b) {
        dfdx.template block<3, 3>(3 * a, 3 * b) += (dal * fdir) * grad_corner.col(b).transpose();
      }
    }
  }
  add_chord_blocks<K>(d, mx, dfdx);
  add_chord_blocks<K>(d, mv, dfdv);
}

template struct MaterialFrictionKernel<4>;
template struct MaterialFrictionKernel<8>;

template <int K>
MaterialFrictionKernel<K> make_material_friction_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                        const MaterialFrictionParams& params,
                                                        const std::vector<std::size_t>* element_subset) {
  const bool eta = params.coefficient == MaterialFrictionParams::Coefficient::Viscosity;
  const std::string key = eta ? "material_friction.viscosity" : "material_friction.kd";
  for (int l = 0; l < 3; ++l) {
    const double val = params.value[l];
    if (!std::isfinite(val) || val < 0.0) {
      throw InputError(key + "[" + kAxisName[static_cast<std::size_t>(l)] + "]: must be a finite number >= 0 (" +
                       (eta ? "Pa s" : "N s/m^3") + "), got " + std::to_string(val));
    }
  }
  const std::vector<std::size_t> entries = select_frame_entries("material_friction", mesh, frames, K, element_subset);
  MaterialFrictionKernel<K> kern;
  kern.face_scaling = params.scaling == MaterialFrictionParams::Scaling::Face;
  const auto& coeffs = frames.template coefficients<K>();
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    kern.elements.push_back(element_stencil<K>(mesh, e));
    kern.element.push_back(e);
    kern.chord.push_back(chord_matrix<K>(coeffs[k]));
    Eigen::Vector3d kd = params.value;
    if (eta) kd = kd.cwiseQuotient(frames.length0[k]);  // k_d,l = eta_l / l0_l
    if (kern.face_scaling) {
      kern.coefficient.push_back(kd);
      std::array<std::array<std::uint8_t, MaterialFrictionKernel<K>::kFaceCorners>, 6> corners{};
      for (std::size_t q = 0; q < 6; ++q) {
        const std::size_t face = frames.face[k][q];
        for (std::size_t n = 0; n < corners[q].size(); ++n) {
          if constexpr (K == 4) {
            corners[q][n] = static_cast<std::uint8_t>(preprocess::kTetFaces[face][n]);
          } else {
            corners[q][n] = static_cast<std::uint8_t>(preprocess::kHexFaces[face][n]);
          }
        }
      }
      kern.face_corners.push_back(corners);
    } else {
      // c_l = R_v A_l^0 k_d,l (eq. 2.111); R_v A_l^0 = V0 / l0_l for the cuboid virtual hexahedron.
      kern.coefficient.push_back(frames.volume_ratio[k] * frames.virtual_face_area0[k].cwiseProduct(kd));
    }
  }
  return kern;
}

template MaterialFrictionKernel<4> make_material_friction_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                                    const MaterialFrictionParams&,
                                                                    const std::vector<std::size_t>*);
template MaterialFrictionKernel<8> make_material_friction_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                                    const MaterialFrictionParams&,
                                                                    const std::vector<std::size_t>*);

std::unique_ptr<ForceTerm> make_material_friction_term(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                       const MaterialFrictionParams& params,
                                                       const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) {
    return std::make_unique<StencilTerm<MaterialFrictionKernel<4>, 4>>(
        make_material_friction_kernel<4>(mesh, frames, params, element_subset));
  }
  return std::make_unique<StencilTerm<MaterialFrictionKernel<8>, 8>>(
      make_material_friction_kernel<8>(mesh, frames, params, element_subset));
}

}  // namespace adamss::solver
