#include "solver/terms/adamss/torsion_springs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace adamss::solver {
namespace {

constexpr std::array<const char*, 3> kAxisName{"fibre", "sheet", "normal"};
constexpr std::array<const char*, 3> kPairName{"fibre-sheet (0,1)", "fibre-normal (0,2)", "sheet-normal (1,2)"};
constexpr double kCollapse = 1e-12;    ///< chord collapse threshold, relative to l0
constexpr double kParallelSin = 1e-6;  ///< angle form: smallest admissible sin(alpha)
constexpr double kFdStep = 1e-6;       ///< face-form FD step, relative to the mean l0

constexpr const char* kTerm = "torsion_springs";

/// Unit chords and lengths of the three axes, with the collapse check.
struct Chords {
  Eigen::Matrix3d zh;
  Eigen::Vector3d rho;
};

Chords unit_chords(const Eigen::Matrix3d& z, const Eigen::Vector3d& l0, std::size_t element) {
  Chords c;
  for (int l = 0; l < 3; ++l) {
    const double rho = z.col(l).norm();
    if (!(rho > kCollapse * l0[l]) || !std::isfinite(rho)) {
      throw NumericalError(std::string(kTerm) + ": element " + std::to_string(element) + ": the " +
                           kAxisName[static_cast<std::size_t>(l)] + " chord has collapsed (length " +
                           std::to_string(rho) + " m)");
    }
    c.rho[l] = rho;
    c.zh.col(l) = z.col(l) / rho;
  }
  return c;
}

/// Delta and the derivatives phi' = dDelta/dc, phi'' of one pair.
struct PairArgument {
  double c = 0.0, delta = 0.0, d1 = 1.0, d2 = 0.0;
};

PairArgument pair_argument(TorsionForm form, double c, double rest, std::size_t element, int p) {
  PairArgument a;
  a.c = c;
  if (form == TorsionForm::Cosine) {
    a.delta = c - rest;
    return a;
  }
  const double s2 = 1.0 - c * c;
  const double s = s2 > 0.0 ? std::sqrt(s2) : 0.0;
  if (!(s >= kParallelSin)) {
    throw NumericalError(std::string(kTerm) + ": element " + std::to_string(element) + ": the " +
                         kPairName[static_cast<std::size_t>(p)] +
                         " axes have become (anti)parallel (cos = " + std::to_string(c) +
                         "); the angle form's derivative -1/sin(alpha) is undefined (use form 'cosine' or a smaller "
                         "time step)");
  }
  a.delta = std::acos(std::clamp(c, -1.0, 1.0)) - rest;
  a.d1 = -1.0 / s;
  a.d2 = -c / (s2 * s);
  return a;
}

void validate(const TorsionSpringParams& p) {
  for (int q = 0; q < 3; ++q) {
    validate_spring_polynomial(kTerm, q, std::string(kPairName[static_cast<std::size_t>(q)]) + " torsion",
                               p.k[static_cast<std::size_t>(q)], 0.5,
                               p.form == TorsionForm::Angle ? "angle change (rad)" : "cosine change");
  }
}

template <int K>
std::array<Index, K> stencil_of(const preprocess::Mesh& mesh, std::size_t e) {
  std::array<Index, K> st{};
  const Index* n = mesh.element(e);
  for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
  return st;
}

}  // namespace

const char* torsion_form_name(TorsionForm f) {
  return f == TorsionForm::Angle ? "angle" : "cosine";
}

TorsionForm parse_torsion_form(const std::string& name, const std::string& key) {
  if (name == "angle") return TorsionForm::Angle;
  if (name == "cosine") return TorsionForm::Cosine;
  throw InputError(key + ": unknown torsion form '" + name + "' (valid: angle, cosine)");
}

// ---- conservative form (none / virtual) ----

template <int K>
Eigen::Vector3d TorsionSpringKernel<K>::deviation(std::size_t i, const Mat3N<K>& x) const {
  const Chords ch = unit_chords(x * chord[i], length0[i], element[i]);
  Eigen::Vector3d out;
  for (int p = 0; p < 3; ++p) {
    const int l = kTorsionPairs[static_cast<std::size_t>(p)][0], m = kTorsionPairs[static_cast<std::size_t>(p)][1];
    out[p] = pair_argument(form, ch.zh.col(l).dot(ch.zh.col(m)), rest[i][p], element[i], p).delta;
  }
  return out;
}

template <int K>
double TorsionSpringKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/) const {
  const Eigen::Vector3d d = deviation(i, x);
  double e = 0.0;
  for (int p = 0; p < 3; ++p) e += spring_energy(k[static_cast<std::size_t>(p)], d[p]);
  return weight[i] * e;
}

template <int K>
void TorsionSpringKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                    Mat3N<K>& f) const {
  const Chords ch = unit_chords(x * chord[i], length0[i], element[i]);
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();  // column l = dE/dzeta_l
  for (int p = 0; p < 3; ++p) {
    const int l = kTorsionPairs[static_cast<std::size_t>(p)][0], m = kTorsionPairs[static_cast<std::size_t>(p)][1];
    const PairArgument a = pair_argument(form, ch.zh.col(l).dot(ch.zh.col(m)), rest[i][p], element[i], p);
    const double s = weight[i] * spring_value(k[static_cast<std::size_t>(p)], a.delta) * a.d1;
    g.col(l) += s * (ch.zh.col(m) - a.c * ch.zh.col(l)) / ch.rho[l];
    g.col(m) += s * (ch.zh.col(l) - a.c * ch.zh.col(m)) / ch.rho[m];
  }
  f.noalias() -= g * chord[i].transpose();
}

template <int K>
void TorsionSpringKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                      MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  const Chords ch = unit_chords(x * chord[i], length0[i], element[i]);
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 9, 9> h = Eigen::Matrix<double, 9, 9>::Zero();
  for (int p = 0; p < 3; ++p) {
    const int l = kTorsionPairs[static_cast<std::size_t>(p)][0], m = kTorsionPairs[static_cast<std::size_t>(p)][1];
    const auto& kp = k[static_cast<std::size_t>(p)];
    const Eigen::Vector3d ul = ch.zh.col(l), um = ch.zh.col(m);
    const double rl = ch.rho[l], rm = ch.rho[m];
    const PairArgument a = pair_argument(form, ul.dot(um), rest[i][p], element[i], p);
    const double c = a.c;
    const Eigen::Vector3d al = (um - c * ul) / rl;
    const Eigen::Vector3d am = (ul - c * um) / rm;
    const double q = spring_value(kp, a.delta);
    const double outer = weight[i] * (spring_slope(kp, a.delta) * a.d1 * a.d1 + q * a.d2);
    const double inner = weight[i] * q * a.d1;
    const Eigen::Matrix3d hll =
        -(ul * al.transpose() + al * ul.transpose()) / rl - c * (id - ul * ul.transpose()) / (rl * rl);
    const Eigen::Matrix3d hmm =
        -(um * am.transpose() + am * um.transpose()) / rm - c * (id - um * um.transpose()) / (rm * rm);
    const Eigen::Matrix3d hlm = ((id - um * um.transpose()) / rm - ul * am.transpose()) / rl;
    h.template block<3, 3>(3 * l, 3 * l) += outer * al * al.transpose() + inner * hll;
    h.template block<3, 3>(3 * m, 3 * m) += outer * am * am.transpose() + inner * hmm;
    h.template block<3, 3>(3 * l, 3 * m) += outer * al * am.transpose() + inner * hlm;
    h.template block<3, 3>(3 * m, 3 * l) += outer * am * al.transpose() + inner * hlm.transpose();
  }
  add_chord_hessian<K>(chord[i], h, dfdx);
}

// ---- face form ----

template <int K>
Eigen::Matrix<double, 3, 6> TorsionFaceSpringKernel<K>::point_forces(std::size_t i, const Mat3N<K>& x) const {
  const Eigen::Matrix<double, 3, 6> xq = x * coefficients[i];
  const Chords ch = unit_chords(axes_from_points(xq), length0[i], element[i]);
  // Stable sign: cosine f_{2l} = -a q zeta_hat_m (eq. 2.44); angle f_{2l} = +a q zeta_hat_m (eq. 2.51 flipped).
  const double sign = form == TorsionForm::Cosine ? -1.0 : 1.0;
  Eigen::Matrix<double, 3, 6> fq = Eigen::Matrix<double, 3, 6>::Zero();
  for (int p = 0; p < 3; ++p) {
    const int l = kTorsionPairs[static_cast<std::size_t>(p)][0], m = kTorsionPairs[static_cast<std::size_t>(p)][1];
    const Eigen::Vector3d ul = ch.zh.col(l), um = ch.zh.col(m);
    const PairArgument a = pair_argument(form, ul.dot(um), rest[i][p], element[i], p);
    const double q = sign * spring_value(k[static_cast<std::size_t>(p)], a.delta);  // Pa
    if (q == 0.0) continue;
    const auto& fc = face[i];
    fq.col(2 * l) += projected_face_area<K>(x, fc[static_cast<std::size_t>(2 * l)], ul) * q * um;
    fq.col(2 * l + 1) -= projected_face_area<K>(x, fc[static_cast<std::size_t>(2 * l + 1)], ul) * q * um;
    fq.col(2 * m) += projected_face_area<K>(x, fc[static_cast<std::size_t>(2 * m)], um) * q * ul;
    fq.col(2 * m + 1) -= projected_face_area<K>(x, fc[static_cast<std::size_t>(2 * m + 1)], um) * q * ul;
  }
  return fq;
}

template <int K>
void TorsionFaceSpringKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double /*t*/,
                                        Mat3N<K>& f) const {
  f.noalias() += point_forces(i, x) * coefficients[i].transpose();  // eq. 2.29
}

template <int K>
void TorsionFaceSpringKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double t, MatJ<K>& dfdx,
                                          MatJ<K>& /*dfdv*/) const {
  add_local_fd_jacobian<K>(
      x, fd_step[i], [&](const Mat3N<K>& xp, Mat3N<K>& fp) { forces(i, xp, v, t, fp); }, dfdx);
}

template struct TorsionSpringKernel<4>;
template struct TorsionSpringKernel<8>;
template struct TorsionFaceSpringKernel<4>;
template struct TorsionFaceSpringKernel<8>;

// ---- factories ----

template <int K>
TorsionSpringKernel<K> make_torsion_spring_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                  const TorsionSpringParams& params,
                                                  const std::vector<std::size_t>* element_subset) {
  if (params.scaling == SpringScaling::Face) {
    throw InputError(std::string(kTerm) +
                     ": scaling 'face' is not conservative; use make_torsion_face_spring_kernel or "
                     "make_torsion_spring_term");
  }
  const std::vector<std::size_t> entries = select_frame_entries(kTerm, mesh, frames, K, element_subset);
  validate(params);
  TorsionSpringKernel<K> kern;
  kern.form = params.form;
  kern.k = params.k;
  const bool virt = params.scaling == SpringScaling::Virtual;
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    kern.element.push_back(e);
    kern.nodes.push_back(stencil_of<K>(mesh, e));
    kern.chord.push_back(chord_matrix<K>(frames.coefficients<K>()[k]));
    kern.length0.push_back(frames.length0[k]);
    kern.rest.push_back(params.form == TorsionForm::Angle ? frames.angle0[k] : frames.cos_angle0[k]);
    kern.weight.push_back(virt ? frames.volume0[k] : 1.0);
  }
  return kern;
}

template <int K>
TorsionFaceSpringKernel<K> make_torsion_face_spring_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                           const TorsionSpringParams& params,
                                                           const std::vector<std::size_t>* element_subset) {
  if (params.scaling != SpringScaling::Face) {
    throw InputError(std::string(kTerm) + ": make_torsion_face_spring_kernel needs scaling 'face', got '" +
                     spring_scaling_name(params.scaling) + "'");
  }
  const std::vector<std::size_t> entries = select_frame_entries(kTerm, mesh, frames, K, element_subset);
  validate(params);
  TorsionFaceSpringKernel<K> kern;
  kern.form = params.form;
  kern.k = params.k;
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    kern.element.push_back(e);
    kern.nodes.push_back(stencil_of<K>(mesh, e));
    kern.coefficients.push_back(frames.coefficients<K>()[k]);
    kern.face.push_back(frames.face[k]);
    kern.length0.push_back(frames.length0[k]);
    kern.rest.push_back(params.form == TorsionForm::Angle ? frames.angle0[k] : frames.cos_angle0[k]);
    kern.fd_step.push_back(kFdStep * frames.length0[k].mean());
  }
  return kern;
}

template TorsionSpringKernel<4> make_torsion_spring_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                              const TorsionSpringParams&,
                                                              const std::vector<std::size_t>*);
template TorsionSpringKernel<8> make_torsion_spring_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                              const TorsionSpringParams&,
                                                              const std::vector<std::size_t>*);
template TorsionFaceSpringKernel<4> make_torsion_face_spring_kernel<4>(const preprocess::Mesh&, const AxisFrames&,
                                                                       const TorsionSpringParams&,
                                                                       const std::vector<std::size_t>*);
template TorsionFaceSpringKernel<8> make_torsion_face_spring_kernel<8>(const preprocess::Mesh&, const AxisFrames&,
                                                                       const TorsionSpringParams&,
                                                                       const std::vector<std::size_t>*);

namespace {
template <int K>
std::unique_ptr<ForceTerm> make_term_k(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                       const TorsionSpringParams& params, const std::vector<std::size_t>* subset) {
  if (params.scaling == SpringScaling::Face) {
    return std::make_unique<StencilTerm<TorsionFaceSpringKernel<K>, K>>(
        make_torsion_face_spring_kernel<K>(mesh, frames, params, subset));
  }
  return std::make_unique<StencilTerm<TorsionSpringKernel<K>, K>>(
      make_torsion_spring_kernel<K>(mesh, frames, params, subset));
}
}  // namespace

std::unique_ptr<ForceTerm> make_torsion_spring_term(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                    const TorsionSpringParams& params,
                                                    const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) return make_term_k<4>(mesh, frames, params, element_subset);
  return make_term_k<8>(mesh, frames, params, element_subset);
}

SpringSet table_2_2_springs() {
  SpringSet s;
  s.name = "table_2_2";
  s.axial.scaling = SpringScaling::Virtual;
  s.axial.k = {{{6358.0, 0.0, 768000.0}, {0.0, 0.0, 288525.0}, {305.0, 0.0, 5699.0}}};
  s.torsion.scaling = SpringScaling::Virtual;
  s.torsion.form = TorsionForm::Cosine;
  s.torsion.k = {{{3355.0, 0.0, 97374.0}, {97374.0, 0.0, 3355.0}, {45896.0, 0.0, 2261.0}}};
  return s;
}

}  // namespace adamss::solver
