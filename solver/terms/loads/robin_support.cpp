#include "solver/terms/loads/robin_support.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "common/error.hpp"
#include "solver/terms/loads/cavity_pressure.hpp"
#include "solver/terms/loads/support_term.hpp"

namespace adamss::solver {

namespace {

/// Adds a face's vector area (out of the solid) to the nodal sums, 1/n per corner.
template <int N>
void add_face(const std::array<Index, N>& f, const Eigen::Matrix3Xd& x, std::map<Index, Eigen::Vector4d>& acc) {
  Mat3N<N> xf;
  for (int k = 0; k < N; ++k) xf.col(k) = x.col(f[static_cast<std::size_t>(k)]);
  // Surface faces point into the cavity, i.e. out of the solid for an outer boundary (surface.hpp).
  const Eigen::Vector3d a = vector_area<N>(xf);
  for (const Index n : f) {
    Eigen::Vector4d& s = acc.try_emplace(n, Eigen::Vector4d::Zero()).first->second;
    s.head<3>() += a / N;
    s[3] += a.norm() / N;
  }
}

}  // namespace

std::string RobinSupportKernel::describe() const {
  std::ostringstream os;
  os << nodes.size() << " nodes, area " << area.sum() * 1e6 << " mm^2, k " << stiffness << " Pa/m, c " << damping
     << " Pa s/m";
  return os.str();
}

std::unique_ptr<ForceTerm> make_robin_support_term(const Surface& surface, const Eigen::Matrix3Xd& x_ref,
                                                   double stiffness, double damping) {
  const std::string what = "robin_support:" + surface.name;
  if (surface.face_count() == 0) throw InputError(what + ": the surface has no faces");
  validate_surface(surface, static_cast<std::size_t>(x_ref.cols()));
  if (!std::isfinite(stiffness) || !std::isfinite(damping) || stiffness < 0.0 || damping < 0.0)
    throw InputError(what + ": stiffness and damping must be finite and >= 0");
  if (stiffness == 0.0 && damping == 0.0) throw InputError(what + ": give a stiffness or a damping > 0");
  if (surface.quadratic()) {
    throw InputError(what +
                     ": a Robin support on the quadratic faces of tet10 or hex27 elements is not available yet (the "
                     "nodal areas of curved 6-node triangles and 9-node quads); use linear elements or fix the nodes "
                     "instead");
  }
  std::map<Index, Eigen::Vector4d> acc;  // sum of vector areas / n, and of areas / n, per node
  for (const auto& f : surface.triangles) add_face<3>(f, x_ref, acc);
  for (const auto& f : surface.quads) add_face<4>(f, x_ref, acc);
  RobinSupportKernel k;
  k.surface_name = surface.name;
  k.stiffness = stiffness;
  k.damping = damping;
  const auto n = static_cast<Eigen::Index>(acc.size());
  k.normal.resize(3, n);
  k.area.resize(n);
  k.x0.resize(3, n);
  Eigen::Index j = 0;
  for (const auto& [node, s] : acc) {
    const double len = s.head<3>().norm();
    if (!(len > 0.0)) {
      throw InputError(what + ": node " + std::to_string(node) +
                       " has no normal (its faces' vector areas cancel: a fold or a sheet of the surface)");
    }
    k.nodes.push_back(node);
    k.normal.col(j) = s.head<3>() / len;
    k.area[j] = s[3];
    k.x0.col(j) = x_ref.col(node);
    ++j;
  }
  return std::make_unique<SupportTerm<RobinSupportKernel>>(std::move(k));
}

}  // namespace adamss::solver
