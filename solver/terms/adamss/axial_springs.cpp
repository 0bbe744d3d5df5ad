#include "solver/terms/adamss/axial_springs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace adamss::solver {
namespace {

constexpr std::array<const char*, 3> kAxisName{"fibre", "sheet", "normal"};
/// A chord shorter than this fraction of its reference length counts as collapsed.
constexpr double kCollapse = 1e-12;
/// FD step of the face form's Jacobian, relative to the mean reference chord length.
constexpr double kFdStep = 1e-6;

constexpr const char* kTerm = "axial_springs";

/// Length of chord l, with the collapse check.
double chord_length(const Eigen::Vector3d& zeta, double l0, std::size_t element, int l) {
  const double rho = zeta.norm();
  if (!(rho > kCollapse * l0) || !std::isfinite(rho)) {
    throw NumericalError(std::string(kTerm) + ": element " + std::to_string(element) + ": the " +
                         kAxisName[static_cast<std::size_t>(l)] + " chord has collapsed (length " +
                         std::to_string(rho) + " m, reference " + std::to_string(l0) + " m)");
  }
  return rho;
}

void validate(const AxialSpringParams& p, const AxisFrames& frames, const std::vector<std::size_t>& entries) {
  for (int l = 0; l < 3; ++l) {
    const auto& k = p.k[static_cast<std::size_t>(l)];
    const std::string what = std::string(kAxisName[static_cast<std::size_t>(l)]) + " axis";
    if (p.scaling == SpringScaling::None) {
      double lmax = 0.0;
      for (const std::size_t e : entries) lmax = std::max(lmax, frames.length0[e][l]);
      validate_spring_polynomial(kTerm, l, what, k, 0.5 * lmax, "elongation (m)");
    } else {
      validate_spring_polynomial(kTerm, l, what, k, 0.5, "strain");
    }
  }
}

}  // namespace

// ---- conservative form (none / virtual) ----

template <int K>
Eigen::Vector3d AxialSpringKernel<K>::extension(std::size_t i, const Mat3N<K>& x) const {
  const Eigen::Matrix3d z = chords(i, x);
  Eigen::Vector3d out;
  for (int l = 0; l < 3; ++l) {
    out[l] = (chord_length(z.col(l), length0[i][l], element[i], l) - length0[i][l]) / unit[i][l];
  }
  return out;
}

template <int K>
double AxialSpringKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/) const {
  const Eigen::Vector3d ext = extension(i, x);
  double e = 0.0;
  for (int l = 0; l < 3; ++l) e += spring_energy(k[static_cast<std::size_t>(l)], ext[l]);
  return weight[i] * e;
}

template <int K>
void AxialSpringKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                  Mat3N<K>& f) const {
  const Eigen::Matrix3d z = chords(i, x);
  Eigen::Matrix3d g;  // column l = dE/dzeta_l
  for (int l = 0; l < 3; ++l) {
    const double rho = chord_length(z.col(l), length0[i][l], element[i], l);
    const double xl = (rho - length0[i][l]) / unit[i][l];
    const double s = weight[i] / unit[i][l] * spring_value(k[static_cast<std::size_t>(l)], xl);
    g.col(l) = (s / rho) * z.col(l);
  }
  f.noalias() -= g * chord[i].transpose();
}

template <int K>
void AxialSpringKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  const Eigen::Matrix3d z = chords(i, x);
  Eigen::Matrix<double, 9, 9> h = Eigen::Matrix<double, 9, 9>::Zero();
  for (int l = 0; l < 3; ++l) {
    const auto& kl = k[static_cast<std::size_t>(l)];
    const double rho = chord_length(z.col(l), length0[i][l], element[i], l);
    const double u = unit[i][l];
    const double xl = (rho - length0[i][l]) / u;
    const double s = weight[i] / u * spring_value(kl, xl);
    const double ds = weight[i] / (u * u) * spring_slope(kl, xl);
    const Eigen::Vector3d zh = z.col(l) / rho;
    const Eigen::Matrix3d pp = zh * zh.transpose();
    h.template block<3, 3>(3 * l, 3 * l) = ds * pp + (s / rho) * (Eigen::Matrix3d::Identity() - pp);
  }
  add_chord_hessian<K>(chord[i], h, dfdx);
}

// ---- face form ----

template <int K>
Eigen::Matrix<double, 3, 6> AxialFaceSpringKernel<K>::point_forces(std::size_t i, const Mat3N<K>& x) const {
  const Eigen::Matrix<double, 3, 6> xq = x * coefficients[i];
  Eigen::Matrix<double, 3, 6> fq;
  for (int l = 0; l < 3; ++l) {
    const Eigen::Vector3d zeta = xq.col(2 * l) - xq.col(2 * l + 1);
    const double l0 = length0[i][l];
    const double rho = chord_length(zeta, l0, element[i], l);
    const Eigen::Vector3d zh = zeta / rho;
    const double stress = spring_value(k[static_cast<std::size_t>(l)], (rho - l0) / l0);  // Pa
    const double a_plus = projected_face_area<K>(x, face[i][static_cast<std::size_t>(2 * l)], zh);
    const double a_minus = projected_face_area<K>(x, face[i][static_cast<std::size_t>(2 * l + 1)], zh);
    fq.col(2 * l) = -a_plus * stress * zh;
    fq.col(2 * l + 1) = a_minus * stress * zh;
  }
  return fq;
}

template <int K>
void AxialFaceSpringKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                      Mat3N<K>& f) const {
  f.noalias() += point_forces(i, x) * coefficients[i].transpose();  // f_a = sum_q C_aq f_q (eq. 2.29)
}

template <int K>
void AxialFaceSpringKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx,
                                        MatJ<K>& /*dfdv*/) const {
  add_local_fd_jacobian<K>(
      x, fd_step[i], [&](const Mat3N<K>& xp, Mat3N<K>& fp) { forces(i, xp, v, t, fp); }, dfdx);
}

template struct AxialSpringKernel<4>;
template struct AxialSpringKernel<8>;
template struct AxialFaceSpringKernel<4>;
template struct AxialFaceSpringKernel<8>;

// ---- factories ----

template <int K>
AxialSpringKernel<K> make_axial_spring_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                              const AxialSpringParams& params,
                                              const std::vector<std::size_t>* element_subset) {
  if (params.scaling == SpringScaling::Face) {
    throw InputError(
        std::string(kTerm) +
        ": scaling 'face' is not conservative; use make_axial_face_spring_kernel or make_axial_spring_term");
  }
  const std::vector<std::size_t> entries = select_frame_entries(kTerm, mesh, frames, K, element_subset);
  validate(params, frames, entries);
  AxialSpringKernel<K> kern;
  kern.scaling = params.scaling;
  kern.k = params.k;
  const bool virt = params.scaling == SpringScaling::Virtual;
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    std::array<Index, K> st{};
    const Index* n = mesh.element(e);
    for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.element.push_back(e);
    kern.nodes.push_back(st);
    kern.chord.push_back(chord_matrix<K>(frames.coefficients<K>()[k]));
    kern.length0.push_back(frames.length0[k]);
    kern.unit.push_back(virt ? frames.length0[k] : Eigen::Vector3d::Ones());
    kern.weight.push_back(virt ? frames.volume0[k] : 1.0);
  }
  return kern;
}

template <int K>
AxialFaceSpringKernel<K> make_axial_face_spring_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                       const AxialSpringParams& params,
                                                       const std::vector<std::size_t>* element_subset) {
  if (params.scaling != SpringScaling::Face) {
    throw InputError(std::string(kTerm) + ": make_axial_face_spring_kernel needs scaling 'face', got '" +
                     spring_scaling_name(params.scaling) + "'");
  }
  const std::vector<std::size_t> entries = select_frame_entries(kTerm, mesh, frames, K, element_subset);
  validate(params, frames, entries);
  AxialFaceSpringKernel<K> kern;
  kern.k = params.k;
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    std::array<Index, K> st{};
    const Index* n = mesh.element(e);
    for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.element.push_back(e);
    kern.nodes.push_back(st);
    kern.coefficients.push_back(frames.coefficients<K>()[k]);
    kern.face.push_back(frames.face[k]);
    kern.length0.push_back(frames.length0[k]);
    kern.fd_step.push_back(kFdStep * frames.length0[k].mean());
  }
  return kern;
}

template AxialSpringKernel<4> make_axial_spring_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                          const AxialSpringParams&, const std::vector<std::size_t>*);
template AxialSpringKernel<8> make_axial_spring_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                          const AxialSpringParams&, const std::vector<std::size_t>*);
template AxialFaceSpringKernel<4> make_axial_face_spring_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                                   const AxialSpringParams&,
                                                                   const std::vector<std::size_t>*);
template AxialFaceSpringKernel<8> make_axial_face_spring_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                                   const AxialSpringParams&,
                                                                   const std::vector<std::size_t>*);

namespace {
template <int K>
std::unique_ptr<ForceTerm> make_term_k(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                       const AxialSpringParams& params, const std::vector<std::size_t>* subset) {
  if (params.scaling == SpringScaling::Face) {
    return std::make_unique<StencilTerm<AxialFaceSpringKernel<K>, K>>(
        make_axial_face_spring_kernel<K>(mesh, frames, params, subset));
  }
  return std::make_unique<StencilTerm<AxialSpringKernel<K>, K>>(
      make_axial_spring_kernel<K>(mesh, frames, params, subset));
}
}  // namespace

std::unique_ptr<ForceTerm> make_axial_spring_term(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                  const AxialSpringParams& params,
                                                  const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) return make_term_k<4>(mesh, frames, params, element_subset);
  return make_term_k<8>(mesh, frames, params, element_subset);
}

}  // namespace adamss::solver
