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

#if defined(__x86_64__) && defined(__GNUC__)
#define ADAMSS_X86_64_V3_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ADAMSS_X86_64_V3_CLONES
#endif

/// Bm^T (3K x 6; Bm's Voigt strain columns 11, 22, 33, 23, 13, 12): row 3b + j is dE_f for
/// delta x_b = e_j, from u = row j of F_f and g = g~_b (virtual_hex.hpp, the derivation). Kept
/// transposed so that add_material_stiffness_24 runs down contiguous columns of 3K entries.
template <int K>
void strain_displacement(const Eigen::Matrix3d& Ff, const Eigen::Matrix<double, 3, K>& gt,
                         Eigen::Matrix<double, 3 * K, 6>& bt) {
  for (int b = 0; b < K; ++b) {
    const double g0 = gt(0, b), g1 = gt(1, b), g2 = gt(2, b);
    for (int j = 0; j < 3; ++j) {
      const double u0 = Ff(j, 0), u1 = Ff(j, 1), u2 = Ff(j, 2);
      const int r = 3 * b + j;
      bt(r, 0) = u0 * g0;
      bt(r, 1) = u1 * g1;
      bt(r, 2) = u2 * g2;
      bt(r, 3) = u1 * g2 + u2 * g1;
      bt(r, 4) = u0 * g2 + u2 * g0;
      bt(r, 5) = u0 * g1 + u1 * g0;
    }
  }
}

/// out += Bm^T Dv Bm for one point of an 8-node stencil: bt = Bm^T (24 x 6), dv = -V0 D (6 x 6,
/// symmetric), out 24 x 24, all column-major. The whole matrix, not the upper blocks, in plain
/// loops over contiguous columns: (Bm^T Dv) column by column, then
/// out(:, j) += sum_k (Bm^T Dv)(:, k) Bm^T(j, k). Compiled twice: for x86-64-v3 (AVX2 + FMA: 4
/// doubles a packet, one instruction per multiply-add) and for the baseline x86-64 the build
/// targets; the loader picks the first the processor runs (GCC's target_clones: an ifunc resolved
/// by CPU features, not by model). bench_forces, Jacobian with its forces, one thread: 8-point
/// hexahedra 7.9 -> 6.5-6.9 us, one-point hexahedra 2.3-2.7 -> 1.7 us (bench/README.md).
ADAMSS_X86_64_V3_CLONES void add_material_stiffness_24(const double* bt, const double* dv, double* out) {
  constexpr int kN = 24;
  double bd[kN * 6];
  for (int k = 0; k < 6; ++k) {
    double* c = bd + kN * k;
    for (int i = 0; i < kN; ++i) c[i] = 0.0;
    for (int m = 0; m < 6; ++m) {
      const double w = dv[m + 6 * k];
      const double* b = bt + kN * m;
      for (int i = 0; i < kN; ++i) c[i] += b[i] * w;
    }
  }
  for (int j = 0; j < kN; ++j) {
    double* o = out + kN * j;
    for (int k = 0; k < 6; ++k) {
      const double w = bt[j + kN * k];
      const double* c = bd + kN * k;
      for (int i = 0; i < kN; ++i) o[i] += c[i] * w;
    }
  }
}

}  // namespace

template <int K>
void GradientLawKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  // -V0 [Bm^T D Bm + (g~ S_f g~^T) (x) I] summed over the item's points (virtual_hex.hpp).
  // Hexahedra: the material part whole, by add_material_stiffness_24 (AVX2 + FMA where the
  // processor has them); other stencils: its upper 3 x 3 blocks, mirrored at the end (on
  // tetrahedra 0.88 us a Jacobian against 1.0 us for the whole 12 x 12 through the loops).
  Eigen::Matrix<double, K, K> geo = Eigen::Matrix<double, K, K>::Zero();
  MatJ<K> kl;  // the upper blocks (not hexahedra)
  if constexpr (K != 8) kl.setZero();
  Eigen::Matrix<double, 3 * K, 6> bt;  // Bm^T
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
    D *= -v0;
    strain_displacement<K>(Ff, gt, bt);
    if constexpr (K == 8) {
      add_material_stiffness_24(bt.data(), D.data(), dfdx.data());
    } else {
      const Eigen::Matrix<double, 3 * K, 6> dbt = bt * D;  // (D Bm)^T, D symmetric
      // Bm^T D Bm is symmetric (D is, a hyperelastic law's tangent): the blocks a <= b only.
      for (int a = 0; a < K; ++a) {
        for (int b = a; b < K; ++b) {
          kl.template block<3, 3>(3 * a, 3 * b).noalias() +=
              bt.template middleRows<3>(3 * a).lazyProduct(dbt.template middleRows<3>(3 * b).transpose());
        }
      }
    }
    geo.noalias() -= v0 * (gt.transpose() * (Sf * gt));
  }
  if constexpr (K == 8) {
    for (int a = 0; a < K; ++a)
      for (int b = 0; b < K; ++b) dfdx.template block<3, 3>(3 * a, 3 * b).diagonal().array() += geo(a, b);
  } else {
    for (int a = 0; a < K; ++a) {
      for (int b = a; b < K; ++b) {
        kl.template block<3, 3>(3 * a, 3 * b).diagonal().array() += geo(a, b);
        dfdx.template block<3, 3>(3 * a, 3 * b) += kl.template block<3, 3>(3 * a, 3 * b);
        if (b != a) dfdx.template block<3, 3>(3 * b, 3 * a) += kl.template block<3, 3>(3 * a, 3 * b).transpose();
      }
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
