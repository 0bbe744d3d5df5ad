#include "solver/terms/adamss/volume_springs.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"

namespace adamss::solver {
namespace {

/// xi_i = x_b - x_i, l_i = |xi_i|, n_i = xi_i / l_i, w_i = v_b - v_i.
template <int K>
struct SpringGeometry {
  Mat3N<K> n, w;
  Eigen::Matrix<double, K, 1> l;
  SpringGeometry(const Mat3N<K>& x, const Mat3N<K>& v) {
    const Eigen::Vector3d xb = x.rowwise().mean();
    const Eigen::Vector3d vb = v.rowwise().mean();
    for (int i = 0; i < K; ++i) {
      const Eigen::Vector3d xi = xb - x.col(i);
      l(i) = xi.norm();
      n.col(i) = xi / l(i);
      w.col(i) = vb - v.col(i);
    }
  }
};

/// Adds -sum_i c_ia c_ib M_i to block (a, b) of out, c_ia = 1/K - delta_ia:
/// sum_i c_ia c_ib M_i = (1/K^2) sum_i M_i - (1/K)(M_a + M_b) + delta_ab M_a.
template <int K>
void subtract_barycentric(const std::array<Eigen::Matrix3d, K>& m, MatJ<K>& out) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const auto& mi : m) sum += mi;
  const double inv = 1.0 / K;
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K; ++b) {
      Eigen::Matrix3d blk = (inv * inv) * sum - inv * (m[static_cast<std::size_t>(a)] + m[static_cast<std::size_t>(b)]);
      if (a == b) blk += m[static_cast<std::size_t>(a)];
      out.template block<3, 3>(3 * a, 3 * b) -= blk;
    }
  }
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

const char* volume_spring_form_name(VolumeSpringForm f) {
  switch (f) {
    case VolumeSpringForm::Auto:
      return "auto";
    case VolumeSpringForm::Hex:
      return "hex";
    case VolumeSpringForm::Tet:
      return "tet";
  }
  return "?";
}

template <int K>
double VolumeSpringKernel<K>::energy(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double /*t*/) const {
  const SpringGeometry<K> g(x, v);
  const double k = k_hat[i];
  if (form == VolumeSpringForm::Hex) {
    return 0.5 * k * (g.l - rest[i]).squaredNorm();
  }
  const double d = g.l.sum() - rest[i].sum();
  return 0.5 * k * d * d;
}

template <int K>
void VolumeSpringKernel<K>::forces(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double /*t*/,
                                   Mat3N<K>& f) const {
  const SpringGeometry<K> g(x, v);
  const double k = k_hat[i];
  if (form == VolumeSpringForm::Hex) {
    // f_a = phi_a n_a - (1/K) sum_i phi_i n_i.
    Mat3N<K> gi;
    for (int a = 0; a < K; ++a) {
      const double phi = k * (g.l(a) - rest[i](a)) + k_d * g.n.col(a).dot(g.w.col(a));
      gi.col(a) = phi * g.n.col(a);
    }
    const Eigen::Vector3d mean = gi.rowwise().mean();
    f += gi;
    f.colwise() -= mean;
  } else {
    // f_a = phi (n_a - mean n).
    double ldot = 0.0;
    for (int a = 0; a < K; ++a) ldot += g.n.col(a).dot(g.w.col(a));
    const double phi = k * (g.l.sum() - rest[i].sum()) + k_d * ldot;
    const Eigen::Vector3d mean = g.n.rowwise().mean();
    f += phi * (g.n.colwise() - mean);
  }
}

template <int K>
void VolumeSpringKernel<K>::jacobian(std::size_t i, const Mat3N<K>& x, const Mat3N<K>& v, double /*t*/, MatJ<K>& dfdx,
                                     MatJ<K>& dfdv) const {
  const SpringGeometry<K> g(x, v);
  const double k = k_hat[i];
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  if (form == VolumeSpringForm::Hex) {
    std::array<Eigen::Matrix3d, K> mx, mv;
    for (int a = 0; a < K; ++a) {
      const Eigen::Vector3d n = g.n.col(a), w = g.w.col(a);
      const double l = g.l(a);
      const double phi = k * (l - rest[i](a)) + k_d * n.dot(w);
      const Eigen::Matrix3d nn = n * n.transpose();
      const Eigen::Matrix3d P = I - nn;
      mx[static_cast<std::size_t>(a)] = k * nn + (phi / l) * P + (k_d / l) * n * (P * w).transpose();
      mv[static_cast<std::size_t>(a)] = k_d * nn;
    }
    subtract_barycentric<K>(mx, dfdx);
    if (k_d != 0.0) subtract_barycentric<K>(mv, dfdv);
    return;
  }
  // Tet form: f_a = -phi u_a, u_a = mean(n) - n_a.
  double ldot = 0.0;
  std::array<Eigen::Matrix3d, K> nj;
  Mat3N<K> q;
  for (int a = 0; a < K; ++a) {
    const Eigen::Vector3d n = g.n.col(a), w = g.w.col(a);
    const Eigen::Matrix3d P = I - n * n.transpose();
    ldot += n.dot(w);
    nj[static_cast<std::size_t>(a)] = P / g.l(a);
    q.col(a) = P * w / g.l(a);
  }
  const double phi = k * (g.l.sum() - rest[i].sum()) + k_d * ldot;
  const Mat3N<K> u = (-g.n).colwise() + g.n.rowwise().mean();
  const Mat3N<K> s = (-q).colwise() + q.rowwise().mean();
  const Mat3N<K> dphi = k * u + k_d * s;  // column b = dphi/dx_b
  // -phi sum_j c_ja c_jb N_j:
  for (auto& m : nj) m *= phi;
  subtract_barycentric<K>(nj, dfdx);
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K; ++b) {
      dfdx.template block<3, 3>(3 * a, 3 * b) -= u.col(a) * dphi.col(b).transpose();
      if (k_d != 0.0) dfdv.template block<3, 3>(3 * a, 3 * b) -= k_d * u.col(a) * u.col(b).transpose();
    }
  }
}

template <int K>
void VolumeSpringKernel<K>::end_step(const StateView& s, double dt) {
  if (!adaptive || !(dt > 0.0)) return;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Mat3N<K> x = element_positions<K>(s.x, elements[i].data());
    const Eigen::Vector3d xb = x.rowwise().mean();
    const double sum_l = (x.colwise() - xb).colwise().norm().sum();
    const double dv = element_volume_of<K>(x) - volume0[i];
    k_hat[i] += mu * dt * (std::abs(dv) / volume0[i]) * (sum_l / rest[i].sum());
  }
}

template <int K>
void VolumeSpringKernel<K>::load_state(const StateArchive& archive) {
  const std::vector<double>& k = archive.doubles("k_hat");
  if (k.size() != k_hat.size()) {
    throw InputError(archive.source() + ": volume_springs k_hat has " + std::to_string(k.size()) +
                     " values, the scene's term has " + std::to_string(k_hat.size()) +
                     " elements (the checkpoint belongs to a different scene)");
  }
  k_hat = k;
}

template struct VolumeSpringKernel<4>;
template struct VolumeSpringKernel<8>;

template <int K>
VolumeSpringKernel<K> make_volume_spring_kernel(const preprocess::Mesh& mesh, const VolumeSpringParams& params,
                                                const std::vector<std::size_t>* element_subset) {
  auto check = [](double v, const char* key, const char* unit) {
    if (!std::isfinite(v) || v < 0.0) {
      throw InputError(std::string("volume_springs: ") + key + " (" + unit + ") must be finite and >= 0, got " +
                       fmt(v));
    }
  };
  check(params.k_s, "k_s", "N/m");
  check(params.k_d, "k_d", "N s/m");
  check(params.mu, "mu", "N/(m s)");
  const preprocess::ElementType want = K == 4 ? preprocess::ElementType::Tet4 : preprocess::ElementType::Hex8;
  if (mesh.type != want) {
    throw InputError("volume_springs: mesh element type " + std::string(preprocess::element_type_name(mesh.type)) +
                     " does not match a " + std::to_string(K) + "-node kernel");
  }
  VolumeSpringForm form = params.form;
  if (form == VolumeSpringForm::Auto) form = K == 8 ? VolumeSpringForm::Hex : VolumeSpringForm::Tet;
  if ((form == VolumeSpringForm::Hex) != (K == 8)) {
    throw InputError(std::string("volume_springs: form ") + volume_spring_form_name(form) +
                     " does not match the mesh's " + preprocess::element_type_name(mesh.type) +
                     " elements (hex form for hexahedra, eq. 2.75; tet form for tetrahedra, eq. 2.76; or auto)");
  }
  const std::size_t ne = mesh.element_count();
  std::vector<char> selected(ne, element_subset ? 0 : 1);
  if (element_subset) {
    for (std::size_t e : *element_subset) {
      if (e >= ne) {
        throw InputError("volume_springs: element " + std::to_string(e) + " out of range (mesh has " +
                         std::to_string(ne) + ")");
      }
      selected[e] = 1;
    }
  }
  VolumeSpringKernel<K> kern;
  kern.form = form;
  kern.k_d = params.k_d;
  kern.adaptive = params.adaptive;
  kern.mu = params.mu;
  for (std::size_t e = 0; e < ne; ++e) {
    if (!selected[e]) continue;
    const Index* n = mesh.element(e);
    const Mat3N<K> x = element_positions<K>(mesh.nodes, n);
    const Eigen::Vector3d xb = x.rowwise().mean();
    const Eigen::Matrix<double, K, 1> rest = (x.colwise() - xb).colwise().norm().transpose();
    const double v0 = element_volume_of<K>(x);
    if (!(rest.minCoeff() > 0.0)) {
      throw InputError("volume_springs: element " + std::to_string(e) +
                       " has a vertex at its barycentre (zero rest length)");
    }
    if (!std::isfinite(v0) || !(v0 > 0.0)) {
      throw InputError("volume_springs: element " + std::to_string(e) + " has reference volume " + fmt(v0) +
                       " m^3 (must be > 0)");
    }
    std::array<Index, K> st{};
    for (int a = 0; a < K; ++a) st[static_cast<std::size_t>(a)] = n[a];
    kern.elements.push_back(st);
    kern.mesh_element.push_back(e);
    kern.rest.push_back(rest);
    kern.volume0.push_back(v0);
    kern.k_hat.push_back(params.k_s);
  }
  return kern;
}

template VolumeSpringKernel<4> make_volume_spring_kernel<4>(const preprocess::Mesh&, const VolumeSpringParams&,
                                                            const std::vector<std::size_t>*);
template VolumeSpringKernel<8> make_volume_spring_kernel<8>(const preprocess::Mesh&, const VolumeSpringParams&,
                                                            const std::vector<std::size_t>*);

std::unique_ptr<ForceTerm> make_volume_spring_term(const preprocess::Mesh& mesh, const VolumeSpringParams& params,
                                                   const std::vector<std::size_t>* element_subset) {
  if (mesh.type == preprocess::ElementType::Tet4) {
    return std::make_unique<StencilTerm<VolumeSpringKernel<4>, 4>>(
        make_volume_spring_kernel<4>(mesh, params, element_subset));
  }
  return std::make_unique<StencilTerm<VolumeSpringKernel<8>, 8>>(
      make_volume_spring_kernel<8>(mesh, params, element_subset));
}

}  // namespace adamss::solver
