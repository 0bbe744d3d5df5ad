#include "solver/terms/adamss/virtual_hex.hpp"

#include <string>

#include "common/error.hpp"

namespace adamss::solver {

template <int K>
double GradientLawKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/) const {
  const Eigen::Matrix3d F = deformation_gradient(i, x);
  return volume0[i] * law->energy(fibre_strain(i, F));
}

template <int K>
void GradientLawKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                  Mat3N<K>& f) const {
  const Eigen::Matrix3d F = deformation_gradient(i, x);
  const Eigen::Matrix3d& B = frame[i];
  const Eigen::Matrix3d S = materials::from_fibre_frame(B, law->stress(fibre_strain(i, F)));
  const Eigen::Matrix3d P = F * S;
  // f_a = -V0 P g_a for all a at once: -V0 P G^T.
  f.noalias() -= volume0[i] * P * gradient[i].transpose();
}

template <int K>
void GradientLawKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  const Eigen::Matrix3d F = deformation_gradient(i, x);
  const Eigen::Matrix3d& B = frame[i];
  const Eigen::Matrix3d Ef = fibre_strain(i, F);
  const Eigen::Matrix3d S = materials::from_fibre_frame(B, law->stress(Ef));
  const Eigen::Matrix<double, K, 3>& G = gradient[i];
  const double v0 = volume0[i];
  const Eigen::Matrix<double, 3, K> gt = G.transpose();  // column a = g_a
  const Eigen::Matrix<double, 3, K> sg = S * gt;         // column a = S g_a
  for (int b = 0; b < K; ++b) {
    const Eigen::Vector3d gb = gt.col(b);
    for (int j = 0; j < 3; ++j) {
      // dE = sym(F^T e_j g_b^T); F^T e_j = row j of F.
      const Eigen::Vector3d fj = F.row(j).transpose();
      const Eigen::Matrix3d dE = 0.5 * (fj * gb.transpose() + gb * fj.transpose());
      const Eigen::Matrix3d dS =
          materials::from_fibre_frame(B, law->apply_tangent(Ef, materials::to_fibre_frame(B, dE)));
      // df_a = -V0 [ (g_b . S g_a) e_j + F dS g_a ] for all a: 3 x K.
      Eigen::Matrix<double, 3, K> df = F * (dS * gt);
      df.row(j) += gb.transpose() * sg;
      df *= -v0;
      for (int a = 0; a < K; ++a) dfdx.template block<3, 1>(3 * a, 3 * b + j) += df.col(a);
    }
  }
}

template struct GradientLawKernel<4>;
template struct GradientLawKernel<8>;

template <int K>
GradientLawKernel<K> make_virtual_hex_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                             const std::shared_ptr<const materials::Law>& law,
                                             const std::vector<std::size_t>* element_subset) {
  if (!law) throw InputError("virtual_hexahedron: no constitutive law given");
  GradientLawKernel<K> kern;
  kern.law = law;
  const auto& grads = frames.template nodal_gradient<K>();
  for (const std::size_t k : select_frame_entries("virtual_hexahedron", mesh, frames, K, element_subset)) {
    std::array<Index, K> st{};
    const Index* n = mesh.element(frames.element[k]);
    for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.elements.push_back(st);
    kern.gradient.push_back(grads[k]);
    kern.frame.push_back(frames.frame[k]);
    kern.volume0.push_back(frames.volume0[k]);
  }
  return kern;
}

template GradientLawKernel<4> make_virtual_hex_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                         const std::shared_ptr<const materials::Law>&,
                                                         const std::vector<std::size_t>*);
template GradientLawKernel<8> make_virtual_hex_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                         const std::shared_ptr<const materials::Law>&,
                                                         const std::vector<std::size_t>*);

std::unique_ptr<ForceTerm> make_virtual_hex_term(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                 const std::shared_ptr<const materials::Law>& law,
                                                 const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) {
    return std::make_unique<StencilTerm<GradientLawKernel<4>, 4>>(
        make_virtual_hex_kernel<4>(mesh, frames, law, element_subset));
  }
  return std::make_unique<StencilTerm<GradientLawKernel<8>, 8>>(
      make_virtual_hex_kernel<8>(mesh, frames, law, element_subset));
}

}  // namespace adamss::solver
