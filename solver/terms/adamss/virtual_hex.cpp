#include "solver/terms/adamss/virtual_hex.hpp"

#include <string>

#include "common/error.hpp"

namespace adamss::solver {

template <int K>
double GradientLawKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/) const {
  double e = 0.0;
  const auto np = static_cast<std::size_t>(points);
  for (std::size_t p = i * np; p < (i + 1) * np; ++p)
    e += volume0[p] * law->energy(fibre_strain(p, deformation_gradient(p, x)));
  return e;
}

template <int K>
void GradientLawKernel<K>::add_cell_tensors(
    const StateView& s, std::size_t element_count,
    std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>>& fields) const {
  using Tensors = Eigen::Matrix<double, 9, Eigen::Dynamic>;
  const auto n = static_cast<Eigen::Index>(element_count);
  const auto field = [&](const char* name) -> Tensors& {
    Tensors& t = fields[name];
    if (t.cols() != n) t = Tensors::Zero(9, n);
    return t;
  };
  Tensors &pk2 = field("stress_pk2"), &cauchy = field("stress_cauchy");
  const auto put = [](Tensors& t, Eigen::Index e, const Eigen::Matrix3d& m) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t(3 * r + c, e) += m(r, c);
  };
  const auto np = static_cast<std::size_t>(points);
  Mat3N<K> x;
  for (std::size_t i = 0; i < elements.size() && i < element_index.size(); ++i) {
    for (int a = 0; a < K; ++a) x.col(a) = s.x.col(elements[i][static_cast<std::size_t>(a)]);
    double weight = 0.0;
    Eigen::Matrix3d sg = Eigen::Matrix3d::Zero(), sc = Eigen::Matrix3d::Zero();
    for (std::size_t p = i * np; p < (i + 1) * np; ++p) {
      const Eigen::Matrix3d F = deformation_gradient(p, x);
      const Eigen::Matrix3d S = materials::from_fibre_frame(frame[p], law->stress(fibre_strain(p, F)));
      sg += volume0[p] * S;
      sc += volume0[p] * (F * S * F.transpose()) / F.determinant();
      weight += volume0[p];
    }
    const auto e = static_cast<Eigen::Index>(element_index[i]);
    put(pk2, e, sg / weight);
    put(cauchy, e, sc / weight);
  }
}

template <int K>
void GradientLawKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                  Mat3N<K>& f) const {
  const auto np = static_cast<std::size_t>(points);
  for (std::size_t p = i * np; p < (i + 1) * np; ++p) {
    const Eigen::Matrix3d F = deformation_gradient(p, x);
    const Eigen::Matrix3d S = materials::from_fibre_frame(frame[p], law->stress(fibre_strain(p, F)));
    // f_a = -V0 P g_a for all a at once: -V0 P G^T.
    f.noalias() -= (volume0[p] * (F * S)) * gradient[p].transpose();
  }
}

namespace {

/// Bm (6 x 3K, Voigt strain rows 11, 22, 33, 23, 13, 12): column 3b + j is dE_f for
/// delta x_b = e_j, from u = row j of F_f and g = g~_b (virtual_hex.hpp, the derivation).
template <int K>
void strain_displacement(const Eigen::Matrix3d& Ff, const Eigen::Matrix<double, 3, K>& gt,
                         Eigen::Matrix<double, 6, 3 * K>& bm) {
  for (int b = 0; b < K; ++b) {
    const double g0 = gt(0, b), g1 = gt(1, b), g2 = gt(2, b);
    for (int j = 0; j < 3; ++j) {
      const double u0 = Ff(j, 0), u1 = Ff(j, 1), u2 = Ff(j, 2);
      auto c = bm.col(3 * b + j);
      c(0) = u0 * g0;
      c(1) = u1 * g1;
      c(2) = u2 * g2;
      c(3) = u1 * g2 + u2 * g1;
      c(4) = u0 * g2 + u2 * g0;
      c(5) = u0 * g1 + u1 * g0;
    }
  }
}

}  // namespace

template <int K>
void GradientLawKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  // -V0 [Bm^T D Bm + (g~ S_f g~^T) (x) I] summed over the item's points (virtual_hex.hpp).
  Eigen::Matrix<double, K, K> geo = Eigen::Matrix<double, K, K>::Zero();
  MatJ<K> kl = MatJ<K>::Zero();  // the upper blocks, mirrored at the end
  Eigen::Matrix<double, 6, 3 * K> bm;
  const auto np = static_cast<std::size_t>(points);
  for (std::size_t p = i * np; p < (i + 1) * np; ++p) {
    const Eigen::Matrix3d& B = frame[p];
    const Eigen::Matrix3d Ff = deformation_gradient(p, x) * B;
    const Eigen::Matrix3d Ef = materials::green_strain<double>(Ff);
    const Eigen::Matrix<double, 3, K> gt = B.transpose() * gradient[p].transpose();  // column a = g~_a
    const double v0 = volume0[p];
    Eigen::Matrix3d Sf;
    materials::Matrix6d D;
    law->stress_and_tangent(Ef, Sf, D);
    strain_displacement<K>(Ff, gt, bm);
    const Eigen::Matrix<double, 6, 3 * K> dbm = (-v0) * (D * bm);
    // Bm^T D Bm is symmetric (D is, a hyperelastic law's tangent): the blocks a <= b only.
    for (int a = 0; a < K; ++a) {
      for (int b = a; b < K; ++b) {
        kl.template block<3, 3>(3 * a, 3 * b).noalias() +=
            bm.template middleCols<3>(3 * a).transpose().lazyProduct(dbm.template middleCols<3>(3 * b));
      }
    }
    geo.noalias() -= v0 * (gt.transpose() * (Sf * gt));
  }
  for (int a = 0; a < K; ++a) {
    for (int b = a; b < K; ++b) {
      kl.template block<3, 3>(3 * a, 3 * b).diagonal().array() += geo(a, b);
      dfdx.template block<3, 3>(3 * a, 3 * b) += kl.template block<3, 3>(3 * a, 3 * b);
      if (b != a) dfdx.template block<3, 3>(3 * b, 3 * a) += kl.template block<3, 3>(3 * a, 3 * b).transpose();
    }
  }
}

template struct GradientLawKernel<4>;
template struct GradientLawKernel<8>;
template struct GradientLawKernel<10>;
template struct GradientLawKernel<27>;

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
    kern.element_index.push_back(frames.element[k]);
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
