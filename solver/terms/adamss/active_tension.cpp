#include "solver/terms/adamss/active_tension.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/error.hpp"
#include "materials/kinematics.hpp"
#include "solver/terms/adamss/axis_term_support.hpp"

namespace adamss::solver {
namespace {

void require_finite(double value, const std::string& what) {
  if (!std::isfinite(value)) throw InputError(what + ": must be a finite number, got " + std::to_string(value));
}

constexpr const char* form_name(ActiveTensionParams::Form f) {
  switch (f) {
    case ActiveTensionParams::Form::Stress:
      return "stress";
    case ActiveTensionParams::Form::Tension:
      return "tension";
    case ActiveTensionParams::Form::Force:
      return "force";
  }
  return "?";
}

/// Validates the shared inputs and builds the schedule for `items` items.
ActivationSchedule make_schedule(const ActiveTensionParams& params, const std::vector<std::size_t>& element_of_item) {
  validate_time_course(params.course, "active_tension.course");
  const std::size_t n = element_of_item.size();
  if (!params.delay.empty() && params.delay.size() != n) {
    throw InputError("active_tension.delay: has " + std::to_string(params.delay.size()) + " entries but the term has " +
                     std::to_string(n) + " elements (give one per element or none)");
  }
  ActivationSchedule s;
  s.course = params.course;
  s.delay.assign(n, 0.0);
  for (std::size_t i = 0; i < params.delay.size(); ++i) {
    const double d = params.delay[i];
    if (!std::isfinite(d) || d < 0.0) {
      throw InputError("active_tension.delay[" + std::to_string(i) + "] (element " +
                       std::to_string(element_of_item[i]) + "): must be a finite number >= 0 (s), got " +
                       std::to_string(d));
    }
    s.delay[i] = d;
  }
  return s;
}

Eigen::Vector3d fractions(const ActiveTensionParams& params) {
  const std::array<std::pair<double, const char*>, 2> f{
      {{params.sheet_fraction, "sheet_fraction"}, {params.normal_fraction, "normal_fraction"}}};
  for (const auto& [val, key] : f) {
    if (!std::isfinite(val) || val < 0.0) {
      throw InputError(std::string("active_tension.") + key + ": must be a finite number >= 0, got " +
                       std::to_string(val));
    }
  }
  return {1.0, params.sheet_fraction, params.normal_fraction};
}

}  // namespace

ActivationSchedule make_activation_schedule(const ActiveTensionParams& params,
                                            const std::vector<std::size_t>& element_of_item) {
  return make_schedule(params, element_of_item);
}

Eigen::Vector3d active_fractions(const ActiveTensionParams& params) {
  return fractions(params);
}

void validate_time_course(const TimeCourse& course, const std::string& what) {
  switch (course.kind) {
    case TimeCourse::Kind::Constant:
      require_finite(course.value, what + ".value");
      break;
    case TimeCourse::Kind::Ramp:
      require_finite(course.from, what + ".from");
      require_finite(course.to, what + ".to");
      require_finite(course.start, what + ".start");
      require_finite(course.duration, what + ".duration");
      if (course.duration < 0.0) throw InputError(what + ".duration: must be >= 0 (s)");
      break;
    case TimeCourse::Kind::Table:
      if (course.times.empty() || course.times.size() != course.values.size()) {
        throw InputError(what + ": a table needs as many values as times and at least one point");
      }
      for (std::size_t k = 0; k < course.times.size(); ++k) {
        require_finite(course.times[k], what + ".times[" + std::to_string(k) + "]");
        require_finite(course.values[k], what + ".values[" + std::to_string(k) + "]");
        if (k > 0 && !(course.times[k] > course.times[k - 1])) {
          throw InputError(what + ".times: must increase strictly (entry " + std::to_string(k) + ")");
        }
      }
      break;
    case TimeCourse::Kind::Twitch:
      require_finite(course.peak, what + ".peak");
      require_finite(course.onset, what + ".onset");
      require_finite(course.rise, what + ".rise");
      require_finite(course.decay, what + ".decay");
      if (!(course.rise > 0.0) || !(course.decay > 0.0)) {
        throw InputError(what + ": twitch rise and decay must be > 0 (s)");
      }
      require_finite(course.period, what + ".period");
      if (course.period < 0.0 || (course.period > 0.0 && course.period < course.rise + course.decay)) {
        throw InputError(what + ".period: must be 0 (one twitch) or >= rise + decay (s)");
      }
      break;
  }
}

// ---------------------------------------------------------------- active stress

template <int K>
Eigen::Matrix3d ActiveStressKernel<K>::active_stress(std::size_t i, double t) const {
  const Eigen::Matrix3d& b = frame[i];
  return schedule.tension(i, t) * (b * fraction.asDiagonal() * b.transpose());
}

template <int K>
double ActiveStressKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t) const {
  const Eigen::Matrix3d F = x * gradient[i];
  const Eigen::Matrix3d ef = materials::green_strain<double>(F * frame[i]);  // fibre frame
  return volume0[i] * schedule.tension(i, t) * fraction.dot(ef.diagonal());
}

template <int K>
void ActiveStressKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t,
                                   Mat3N<K>& f) const {
  const double tension = schedule.tension(i, t);
  if (tension == 0.0) return;
  const Eigen::Matrix3d F = x * gradient[i];
  f.noalias() -= volume0[i] * (F * active_stress(i, t)) * gradient[i].transpose();
}

template <int K>
void ActiveStressKernel<K>::jacobian(std::size_t i, const Mat3N<K>& /*x*/, const Mat3N<K>& /*v*/, double t,
                                     MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  if (schedule.tension(i, t) == 0.0) return;
  const Eigen::Matrix<double, K, 3>& g = gradient[i];
  // H(a, b) = -V0 g_a . S_a g_b; d f_a / d x_b = H(a, b) I.
  const Eigen::Matrix<double, K, K> h = -volume0[i] * (g * active_stress(i, t) * g.transpose());
  for (int a = 0; a < K; ++a)
    for (int b = 0; b < K; ++b) dfdx.template block<3, 3>(3 * a, 3 * b).diagonal().array() += h(a, b);
}

// ---------------------------------------------------------------- axis forms

template <int K, bool kCurrentArea>
double ActiveAxisKernel<K, kCurrentArea>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/,
                                                 double t) const {
  if constexpr (kCurrentArea) {
    throw std::logic_error("active_tension: the current-area form has no energy");
  } else {
    const Eigen::Matrix3d z = x * chord[i];
    return schedule.tension(i, t) * coefficient[i].dot(z.colwise().norm().transpose());
  }
}

template <int K, bool kCurrentArea>
void ActiveAxisKernel<K, kCurrentArea>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t,
                                               Mat3N<K>& f) const {
  const double tension = schedule.tension(i, t);
  if (tension == 0.0) return;
  const Eigen::Matrix<double, K, 3>& d = chord[i];
  const Eigen::Matrix3d z = x * d;
  for (int l = 0; l < 3; ++l) {
    const double c = coefficient[i][l];
    if (c == 0.0) continue;
    double mag = c * tension;
    if constexpr (kCurrentArea) mag *= z.col((l + 1) % 3).cross(z.col((l + 2) % 3)).norm();  // A_l^t
    const Eigen::Vector3d fl = -mag * z.col(l).normalized();                                 // f_{2l}
    f.noalias() += fl * d.col(l).transpose();
  }
}

template <int K, bool kCurrentArea>
void ActiveAxisKernel<K, kCurrentArea>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& /*v*/, double t,
                                                 MatJ<K>& dfdx, MatJ<K>& /*dfdv*/) const {
  const double tension = schedule.tension(i, t);
  if (tension == 0.0) return;
  const Eigen::Matrix<double, K, 3>& d = chord[i];
  const Eigen::Matrix3d z = x * d;
  std::array<Eigen::Matrix3d, 9> m;
  for (auto& b : m) b.setZero();
  for (int l = 0; l < 3; ++l) {
    const double c = coefficient[i][l] * tension;
    if (c == 0.0) continue;
    const double len = z.col(l).norm();
    const Eigen::Vector3d zh = z.col(l) / len;
    const Eigen::Matrix3d proj = (Eigen::Matrix3d::Identity() - zh * zh.transpose()) / len;
    if constexpr (kCurrentArea) {
      const int mi = (l + 1) % 3, ni = (l + 2) % 3;
      const Eigen::Vector3d zm = z.col(mi), zn = z.col(ni);
      const Eigen::Vector3d u = zm.cross(zn);
      const double alpha = u.norm();
      m[static_cast<std::size_t>(4 * l)] = -c * alpha * proj;
      m[static_cast<std::size_t>(3 * l + mi)] = -c / alpha * zh * zn.cross(u).transpose();
      m[static_cast<std::size_t>(3 * l + ni)] = -c / alpha * zh * u.cross(zm).transpose();
    } else {
      m[static_cast<std::size_t>(4 * l)] = -c * proj;
    }
  }
  add_chord_blocks<K>(d, m, dfdx);
}

template struct ActiveStressKernel<4>;
template struct ActiveStressKernel<8>;
template struct ActiveStressKernel<10>;
template struct ActiveStressKernel<27>;
template struct ActiveAxisKernel<4, true>;
template struct ActiveAxisKernel<8, true>;
template struct ActiveAxisKernel<4, false>;
template struct ActiveAxisKernel<8, false>;

// ---------------------------------------------------------------- factories

template <int K>
ActiveStressKernel<K> make_active_stress_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                const ActiveTensionParams& params,
                                                const std::vector<std::size_t>* element_subset) {
  const Eigen::Vector3d r = fractions(params);
  const std::vector<std::size_t> entries = select_frame_entries("active_tension", mesh, frames, K, element_subset);
  ActiveStressKernel<K> kern;
  kern.fraction = r;
  const auto& grads = frames.template nodal_gradient<K>();
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    kern.elements.push_back(element_stencil<K>(mesh, e));
    kern.element.push_back(e);
    kern.gradient.push_back(grads[k]);
    kern.frame.push_back(frames.frame[k]);
    kern.volume0.push_back(frames.volume0[k]);
  }
  kern.schedule = make_schedule(params, kern.element);
  return kern;
}

template <int K, bool kCurrentArea>
ActiveAxisKernel<K, kCurrentArea> make_active_axis_kernel(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                          const ActiveTensionParams& params,
                                                          const std::vector<std::size_t>* element_subset) {
  const Eigen::Vector3d r = fractions(params);
  const double h = params.thesis_half ? 0.5 : 1.0;
  const std::vector<std::size_t> entries = select_frame_entries("active_tension", mesh, frames, K, element_subset);
  ActiveAxisKernel<K, kCurrentArea> kern;
  const auto& coeffs = frames.template coefficients<K>();
  for (const std::size_t k : entries) {
    const std::size_t e = frames.element[k];
    kern.elements.push_back(element_stencil<K>(mesh, e));
    kern.element.push_back(e);
    kern.chord.push_back(chord_matrix<K>(coeffs[k]));
    Eigen::Vector3d c = h * frames.volume_ratio[k] * r;                             // h r_l R_v
    if constexpr (!kCurrentArea) c = c.cwiseProduct(frames.virtual_face_area0[k]);  // * A_l^0
    kern.coefficient.push_back(c);
  }
  kern.schedule = make_schedule(params, kern.element);
  return kern;
}

#define ADAMSS_ACTIVE_INSTANTIATE(K)                                                                            \
  template ActiveStressKernel<K> make_active_stress_kernel<K>(                                                  \
      const preprocess::Mesh&, const AxisFrames&, const ActiveTensionParams&, const std::vector<std::size_t>*); \
  template ActiveAxisKernel<K, true> make_active_axis_kernel<K, true>(                                          \
      const preprocess::Mesh&, const AxisFrames&, const ActiveTensionParams&, const std::vector<std::size_t>*); \
  template ActiveAxisKernel<K, false> make_active_axis_kernel<K, false>(                                        \
      const preprocess::Mesh&, const AxisFrames&, const ActiveTensionParams&, const std::vector<std::size_t>*);
ADAMSS_ACTIVE_INSTANTIATE(4)
ADAMSS_ACTIVE_INSTANTIATE(8)
#undef ADAMSS_ACTIVE_INSTANTIATE

namespace {
template <int K>
std::unique_ptr<ForceTerm> make_term_k(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                       const ActiveTensionParams& params, const std::vector<std::size_t>* subset) {
  switch (params.form) {
    case ActiveTensionParams::Form::Stress:
      return std::make_unique<StencilTerm<ActiveStressKernel<K>, K>>(
          make_active_stress_kernel<K>(mesh, frames, params, subset));
    case ActiveTensionParams::Form::Tension:
      return std::make_unique<StencilTerm<ActiveAxisKernel<K, true>, K>>(
          make_active_axis_kernel<K, true>(mesh, frames, params, subset));
    case ActiveTensionParams::Form::Force:
      return std::make_unique<StencilTerm<ActiveAxisKernel<K, false>, K>>(
          make_active_axis_kernel<K, false>(mesh, frames, params, subset));
  }
  throw InputError(std::string("active_tension.form: unknown form ") + form_name(params.form));
}
}  // namespace

std::unique_ptr<ForceTerm> make_active_tension_term(const preprocess::Mesh& mesh, const AxisFrames& frames,
                                                    const ActiveTensionParams& params,
                                                    const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) return make_term_k<4>(mesh, frames, params, element_subset);
  return make_term_k<8>(mesh, frames, params, element_subset);
}

}  // namespace adamss::solver
