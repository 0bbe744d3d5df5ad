#pragma once
// Small-strain Young's modulus and Poisson ratio of a block model, measured by a static
// uniaxial test along x (solve_static of static_newton.hpp):
//   nodes on the face x = 0 fixed in x, nodes on x = L prescribed to x = L (1 + eps),
//   lateral faces free (also the end faces slide freely in y and z); rigid modes removed by
//   pinning the node at (0, 0, 0) in y and z and the node at (0, W, 0) in z.
// Measured at eps = +strain and eps = -strain; central differences cancel the quadratic
// (geometric) part of the response:
//   E  = (R(+) - R(-)) / (2 strain A0),  R = reaction on the face x = L, A0 = W D
//   nu = -(e_lat(+) - e_lat(-)) / (2 strain),  e_lat = mean of the y and z strains, each
//        (mean y on face y = W - mean y on face y = 0) / W - 1 (likewise z).
// The one-sided tension values are returned too.
#include <gtest/gtest.h>

#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "static_newton.hpp"

namespace adamss::test {

struct UniaxialModuli {
  double youngs = 0.0;          ///< central-difference E (Pa)
  double poisson = 0.0;         ///< central-difference nu
  double youngs_tension = 0.0;  ///< R(+) / (strain A0) (Pa)
  double poisson_tension = 0.0;
  bool converged = false;
};

/// Translates the mesh so that its bounding box starts at the origin.
inline void move_to_origin(preprocess::Mesh& mesh) {
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff();
  mesh.nodes.colwise() -= lo;
}

inline UniaxialModuli measure_uniaxial(const preprocess::Mesh& mesh, const std::vector<const solver::ForceTerm*>& terms,
                                       double strain = 0.01) {
  const Eigen::Vector3d hi = mesh.nodes.rowwise().maxCoeff();
  const double L = hi.x(), W = hi.y(), D = hi.z(), tol = 1e-9 * L;
  const Eigen::Index n = mesh.nodes.cols();
  std::vector<char> fixed(static_cast<std::size_t>(3 * n), 0);
  std::vector<Eigen::Index> far, y0, y1, z0, z1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = mesh.nodes.col(i);
    const auto u = static_cast<std::size_t>(3 * i);
    if (p.x() < tol) fixed[u] = 1;
    if (p.x() > L - tol) {
      fixed[u] = 1;
      far.push_back(i);
    }
    if (p.x() < tol && p.y() < tol && p.z() < tol) fixed[u + 1] = fixed[u + 2] = 1;
    if (p.x() < tol && p.y() > W - tol && p.z() < tol) fixed[u + 2] = 1;
    if (p.y() < tol) y0.push_back(i);
    if (p.y() > W - tol) y1.push_back(i);
    if (p.z() < tol) z0.push_back(i);
    if (p.z() > D - tol) z1.push_back(i);
  }
  auto mean = [](const Eigen::Matrix3Xd& x, const std::vector<Eigen::Index>& set, int c) {
    double s = 0.0;
    for (const auto i : set) s += x(c, i);
    return s / static_cast<double>(set.size());
  };
  UniaxialModuli out;
  out.converged = true;
  double reaction[2] = {0, 0}, lateral[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    const double eps = side == 0 ? strain : -strain;
    Eigen::Matrix3Xd x = mesh.nodes;
    for (const auto i : far) x(0, i) = L * (1.0 + eps);
    StaticNewtonOptions opt;
    opt.tolerance = 1e-13;
    const StaticNewtonResult r = solve_static(terms, x, fixed, opt);
    EXPECT_TRUE(r.converged) << "eps " << eps << ": residual " << r.residual << " N after " << r.iterations;
    out.converged = out.converged && r.converged;
    for (const auto i : far) reaction[side] -= r.force(0, i);
    const double ey = (mean(r.x, y1, 1) - mean(r.x, y0, 1)) / W - 1.0;
    const double ez = (mean(r.x, z1, 2) - mean(r.x, z0, 2)) / D - 1.0;
    lateral[side] = 0.5 * (ey + ez);
  }
  const double area = W * D;
  out.youngs = (reaction[0] - reaction[1]) / (2.0 * strain * area);
  out.poisson = -(lateral[0] - lateral[1]) / (2.0 * strain);
  out.youngs_tension = reaction[0] / (strain * area);
  out.poisson_tension = -lateral[0] / strain;
  return out;
}

}  // namespace adamss::test
