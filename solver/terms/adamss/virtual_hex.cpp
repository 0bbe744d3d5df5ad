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

/// Four doubles, one AVX2 register in the x86-64-v3 clone, two SSE2 ones in the baseline (GCC
/// vector extensions: the same source for both). Loaded and stored through memcpy: Eigen's fixed
/// matrices are aligned to 16 bytes here, not 32.
/// GCC warns (-Wpsabi) that passing such a vector by value has a different ABI with and without
/// AVX; the helpers below are always inlined into one function, so no call crosses that boundary
/// (the warning is off until after add_material_stiffness_24).
using Packet = double __attribute__((vector_size(32)));
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

[[gnu::always_inline]] inline Packet load(const double* p) {
  Packet v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store(double* p, Packet v) {
  __builtin_memcpy(p, &v, sizeof v);
}

/// Columns 4 (P - 1) .. 4 P - 1 of add_material_stiffness_24's upper part, two at a time: rows
/// 0 .. 4 P - 1, the two columns' 2 P packets held in registers over the six Voigt components
/// (P fixed at compile time; 2 x 6 accumulators at most, within AVX2's 16 registers).
template <int P>
[[gnu::always_inline]] inline void upper_columns(const Packet* bd, const double* bt, double* out, bool add) {
  constexpr int kN = 24;
  for (int j = 4 * (P - 1); j < 4 * P; j += 2) {
    double* o0 = out + kN * j;
    double* o1 = o0 + kN;
    Packet a0[P], a1[P];
    for (int q = 0; q < P; ++q) {
      a0[q] = add ? load(o0 + 4 * q) : Packet{};
      a1[q] = add ? load(o1 + 4 * q) : Packet{};
    }
    for (int k = 0; k < 6; ++k) {
      const double w0 = bt[j + kN * k], w1 = bt[j + 1 + kN * k];
      for (int q = 0; q < P; ++q) {
        const Packet c = bd[6 * k + q];
        a0[q] += c * w0;
        a1[q] += c * w1;
      }
    }
    for (int q = 0; q < P; ++q) {
      store(o0 + 4 * q, a0[q]);
      store(o1 + 4 * q, a1[q]);
    }
  }
}

/// out (+)= Bm^T Dv Bm for one point of an 8-node stencil, upper part only: bt = Bm^T (24 x 6),
/// dv = -V0 D (6 x 6, symmetric), out 24 x 24, all column-major; `add` false stores instead of
/// adding (the first point, so that out needs no zeroing). Column j gets rows 0 .. 4 (j/4 + 1) - 1
/// (its diagonal's packet of four and everything above); add_symmetric_24 mirrors the rest once
/// all points are summed: 504 four-wide multiply-adds a point instead of 864 for the whole matrix.
/// First Bm^T Dv (36 packets), then out(:, j) += sum_k (Bm^T Dv)(:, k) Bm^T(j, k), two columns at
/// a time in registers. Compiled twice: for x86-64-v3 (AVX2 + FMA: a packet is one register, a
/// multiply-add one instruction) and for the baseline x86-64 the build targets; the loader picks
/// the first the processor runs (GCC's target_clones: an ifunc resolved by CPU features, not by
/// model). bench_forces, Jacobian with its forces, one thread, 8-point hexahedra: 7.9 us (3 x 3
/// blocks, SSE2) -> 6.8 us (the whole matrix, AVX2) -> 6.2 us (this; bench/README.md).
ADAMSS_X86_64_V3_CLONES void add_material_stiffness_24(const double* bt, const double* dv, double* out, bool add) {
  constexpr int kN = 24;
  Packet bd[6 * 6];  // Bm^T Dv: column k's packet q at 6 k + q
  for (int q = 0; q < 6; ++q) {
    Packet b[6];
    for (int m = 0; m < 6; ++m) b[m] = load(bt + kN * m + 4 * q);
    for (int k = 0; k < 6; ++k) {
      Packet c = b[0] * dv[6 * k];
      for (int m = 1; m < 6; ++m) c += b[m] * dv[m + 6 * k];
      bd[6 * k + q] = c;
    }
  }
  upper_columns<1>(bd, bt, out, add);
  upper_columns<2>(bd, bt, out, add);
  upper_columns<3>(bd, bt, out, add);
  upper_columns<4>(bd, bt, out, add);
  upper_columns<5>(bd, bt, out, add);
  upper_columns<6>(bd, bt, out, add);
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/// out += km + the transpose of km's upper part where add_material_stiffness_24 left km out (rows
/// i >= 4 (j/4 + 1) of column j): the symmetric 24 x 24 whose upper part km holds.
void add_symmetric_24(const double* km, double* out) {
  constexpr int kN = 24;
  for (int j = 0; j < kN; ++j) {
    const int upper = 4 * (j / 4 + 1);
    for (int i = 0; i < upper; ++i) out[i + kN * j] += km[i + kN * j];
    for (int i = upper; i < kN; ++i) out[i + kN * j] += km[j + kN * i];
  }
}

}  // namespace

template <int K>
void GradientLawKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  // -V0 [Bm^T D Bm + (g~ S_f g~^T) (x) I] summed over the item's points (virtual_hex.hpp).
  // Hexahedra: the material part's upper part, by add_material_stiffness_24 (AVX2 + FMA where the
  // processor has them), mirrored by add_symmetric_24; other stencils: its upper 3 x 3 blocks,
  // mirrored at the end (on tetrahedra 0.88 us a Jacobian against 1.0 us for the whole 12 x 12
  // through plain loops).
  Eigen::Matrix<double, K, K> geo = Eigen::Matrix<double, K, K>::Zero();
  MatJ<K> kl;  // the upper part (hexahedra) or the upper blocks (other stencils)
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
      add_material_stiffness_24(bt.data(), D.data(), kl.data(), p != i * np);  // the first point stores
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
    add_symmetric_24(kl.data(), dfdx.data());
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
