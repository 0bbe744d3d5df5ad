#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>

#include "../support/lattice_fixtures.hpp"
#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "support/fibre_fixtures.hpp"

using namespace adamss;
using solver::VolumeDistribution;

namespace {

constexpr double kH = 1e-3;  // voxel size of test::block_mesh (m)

preprocess::Mesh fibred_block(int n, preprocess::Topology t) {
  auto mesh = test::block_mesh(n, n, n, t);
  test::set_rotated_fibres(mesh, false);
  return mesh;
}

solver::VolumeParams params(double p, double r, VolumeDistribution d) {
  solver::VolumeParams vp;
  vp.p = p;
  vp.ratio = solver::TimeCourse::constant(r);
  vp.distribution = d;
  return vp;
}

template <int K>
const solver::VolumeKernel<K>& kernel_of(const solver::ForceTerm& t) {
  return dynamic_cast<const solver::StencilTerm<solver::VolumeKernel<K>, K>&>(t).kernel();
}

/// Omega = det(2E + I) written out as eq. (2.99) (E_ij independent entries, 1-based in the thesis).
double omega_299(const Eigen::Matrix3d& E) {
  auto e = [&E](int i, int j) { return E(i - 1, j - 1); };
  return (2 * e(1, 1) + 1) * (2 * e(2, 2) + 1) * (2 * e(3, 3) + 1) + 8 * e(1, 2) * e(2, 3) * e(3, 1) +
         8 * e(2, 1) * e(3, 2) * e(1, 3) - 4 * e(2, 3) * e(3, 2) * (2 * e(1, 1) + 1) -
         4 * e(1, 3) * e(3, 1) * (2 * e(2, 2) + 1) - 4 * e(1, 2) * e(2, 1) * (2 * e(3, 3) + 1);
}

/// dOmega/dE_ij as printed below eq. (2.100), with `kk_sign` the sign in (2 E_kk +- 1)
/// of the off-diagonal case (printed: -1; correct: +1). {i, j, k} = {0, 1, 2}.
Eigen::Matrix3d domega_printed(const Eigen::Matrix3d& E, double kk_sign) {
  Eigen::Matrix3d d;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;  // "j" and "k" of the printed i = j case
        d(i, i) = 2 * (2 * E(a, a) + 1) * (2 * E(b, b) + 1) - 8 * E(b, a) * E(a, b);
      } else {
        const int k = 3 - i - j;
        d(i, j) = 8 * (E(j, k) * E(k, i)) - 4 * E(j, i) * (2 * E(k, k) + kk_sign);
      }
    }
  return d;
}

}  // namespace

TEST(VolumePreservation, PassesHarnessBothDistributions) {
  for (auto t : {preprocess::Topology::Tet5, preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    const auto mesh = fibred_block(2, t);
    const auto frames = solver::build_axis_frames(mesh);
    for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
      for (double r : {1.0, 1.1}) {
        SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + solver::volume_distribution_name(d) + " / r " +
                     std::to_string(r));
        const auto term = solver::make_volume_term(mesh, &frames, params(2e4, r, d));
        EXPECT_EQ(term->name(), "volume_preservation");
        EXPECT_TRUE(term->has_energy());
        EXPECT_TRUE(term->has_jacobian());
        const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.08);
        const Eigen::Matrix3Xd v = test::perturbed(Eigen::Matrix3Xd::Zero(3, x.cols()), 1.0, 1.0, 9);
        test::HarnessOptions opt;
        opt.tolerance = 1e-6;
        test::check_force_term(*term, x, v, kH, opt);
      }
    }
  }
}

TEST(VolumePreservation, IsotropicNeedsNoFibres) {
  for (auto t : {preprocess::Topology::Tet6, preprocess::Topology::Hex}) {
    const auto mesh = test::block_mesh(2, 1, 2, t);
    ASSERT_FALSE(mesh.has_fibres());
    const auto term = solver::make_volume_term(mesh, nullptr, params(1e4, 0.95, VolumeDistribution::Isotropic));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1, 5);
    test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), kH);
    EXPECT_THROW((void)solver::make_volume_term(mesh, nullptr, params(1e4, 1.0, VolumeDistribution::Anisotropic)),
                 InputError);
  }
}

// The exact element volume and its gradient against preprocess::element_volume and
// central differences, on distorted (non-affine) elements.
TEST(VolumePreservation, ElementVolumeAndGradientAreExact) {
  for (auto t : {preprocess::Topology::Tet5, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 1, t);
    mesh.nodes = test::perturbed(mesh.nodes, kH, 0.15, 11);
    for (std::size_t e = 0; e < mesh.element_count(); ++e) {
      const double ref = preprocess::element_volume(mesh, e);
      double v = 0.0;
      double worst = 0.0, gmax = 0.0;
      auto check = [&]<int K>() {
        const solver::Mat3N<K> x = solver::element_positions<K>(mesh.nodes, mesh.element(e));
        v = solver::element_volume_of<K>(x);
        const solver::Mat3N<K> g = solver::element_volume_gradient<K>(x);
        gmax = g.cwiseAbs().maxCoeff();
        const double h = 1e-7 * kH;
        for (int a = 0; a < K; ++a)
          for (int c = 0; c < 3; ++c) {
            solver::Mat3N<K> xp = x, xm = x;
            xp(c, a) += h;
            xm(c, a) -= h;
            const double fd = (solver::element_volume_of<K>(xp) - solver::element_volume_of<K>(xm)) / (2 * h);
            worst = std::max(worst, std::abs(fd - g(c, a)));
          }
      };
      if (t == preprocess::Topology::Hex) {
        check.template operator()<8>();
      } else {
        check.template operator()<4>();
      }
      EXPECT_NEAR(v, ref, 1e-14 * std::abs(ref)) << "element " << e;
      EXPECT_LT(worst, 1e-7 * gmax) << "element " << e;
    }
  }
}

// For tetrahedra the virtual-hexahedron J = det(X G) is V/V0 exactly, so the two
// distributions give the same J, energy, forces and Jacobian.
TEST(VolumePreservation, TetrahedraBothDistributionsAgree) {
  for (auto t : {preprocess::Topology::Tet5, preprocess::Topology::Tet6m}) {
    const auto mesh = fibred_block(2, t);
    const auto frames = solver::build_axis_frames(mesh);
    const auto aniso = solver::make_volume_term(mesh, &frames, params(3e3, 1.07, VolumeDistribution::Anisotropic));
    const auto iso = solver::make_volume_term(mesh, &frames, params(3e3, 1.07, VolumeDistribution::Isotropic));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.12, 17);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    const auto& ka = kernel_of<4>(*aniso);
    const auto& ki = kernel_of<4>(*iso);
    ASSERT_EQ(ka.size(), ki.size());
    for (std::size_t i = 0; i < ka.size(); ++i) {
      ASSERT_EQ(ka.mesh_element[i], ki.mesh_element[i]);  // frames in element order
      const auto xe = solver::element_positions<4>(x, mesh.element(ka.mesh_element[i]));
      EXPECT_NEAR(ka.volume_ratio(i, xe), ki.volume_ratio(i, xe), 1e-12);
    }
    const double e = aniso->energy({x, v, 0.0});
    EXPECT_NEAR(e, iso->energy({x, v, 0.0}), 1e-12 * e);
    const Eigen::Matrix3Xd fa = test::forces_of(*aniso, x, v), fi = test::forces_of(*iso, x, v);
    EXPECT_LT((fa - fi).cwiseAbs().maxCoeff(), 1e-10 * fa.cwiseAbs().maxCoeff());
    test::DenseSink sa(x.cols()), si(x.cols());
    aniso->add_jacobian({x, v, 0.0}, sa);
    iso->add_jacobian({x, v, 0.0}, si);
    EXPECT_LT((sa.kx - si.kx).cwiseAbs().maxCoeff(), 1e-10 * sa.kx.cwiseAbs().maxCoeff());
  }
}

// Hexahedra: the two agree in J for affine motions (J = det A) and differ otherwise (the
// virtual hexahedron sees the chord-averaged F, the isotropic J the true volume). The
// forces agree only when the axis-frame gradient G equals the mean FEM gradient, i.e.
// for cuboids with the axes along the edges; with oblique fibres the anisotropic term
// distributes the same pressure differently (through the intersection points).
TEST(VolumePreservation, HexahedraAgreeForAffineMotion) {
  Eigen::Matrix3d A;
  A << 1.1, 0.2, -0.05, 0.03, 0.9, 0.1, -0.1, 0.07, 1.05;
  for (bool aligned : {false, true}) {
    SCOPED_TRACE(aligned ? "axis-aligned fibres" : "oblique fibres");
    auto mesh = fibred_block(2, preprocess::Topology::Hex);
    if (aligned) {
      mesh.fiber.colwise() = Eigen::Vector3d::UnitX();
      mesh.sheet.colwise() = Eigen::Vector3d::UnitY();
      mesh.normal.colwise() = Eigen::Vector3d::UnitZ();
    }
    const auto frames = solver::build_axis_frames(mesh);
    const auto aniso = solver::make_volume_term(mesh, &frames, params(1e3, 1.0, VolumeDistribution::Anisotropic));
    const auto iso = solver::make_volume_term(mesh, &frames, params(1e3, 1.0, VolumeDistribution::Isotropic));
    const Eigen::Matrix3Xd x = (A * mesh.nodes).colwise() + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
    const auto& ka = kernel_of<8>(*aniso);
    const auto& ki = kernel_of<8>(*iso);
    for (std::size_t i = 0; i < ka.size(); ++i) {
      const auto xe = solver::element_positions<8>(x, mesh.element(ka.mesh_element[i]));
      EXPECT_NEAR(ka.volume_ratio(i, xe), A.determinant(), 1e-12);
      EXPECT_NEAR(ki.volume_ratio(i, xe), A.determinant(), 1e-12);
    }
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    const Eigen::Matrix3Xd fa = test::forces_of(*aniso, x, v), fi = test::forces_of(*iso, x, v);
    if (aligned) {
      EXPECT_LT((fa - fi).cwiseAbs().maxCoeff(), 1e-10 * fi.cwiseAbs().maxCoeff());
    } else {
      EXPECT_GT((fa - fi).cwiseAbs().maxCoeff(), 1e-3 * fi.cwiseAbs().maxCoeff());
    }
    // A non-affine motion: the isotropic J is the true volume ratio V/V0, the anisotropic one is not.
    const Eigen::Matrix3Xd xn = test::perturbed(mesh.nodes, kH, 0.1, 23);
    preprocess::Mesh moved = mesh;
    moved.nodes = xn;
    double max_gap = 0.0;
    for (std::size_t i = 0; i < ki.size(); ++i) {
      const auto xe = solver::element_positions<8>(xn, mesh.element(ki.mesh_element[i]));
      const double vr = preprocess::element_volume(moved, ki.mesh_element[i]) / ki.volume0[i];
      EXPECT_NEAR(ki.volume_ratio(i, xe), vr, 1e-12);
      max_gap = std::max(max_gap, std::abs(ka.volume_ratio(i, xe) - vr));
    }
    EXPECT_GT(max_gap, 1e-3);
  }
}

// S = dW_v/dE = 2 p (J - r) J C^{-1} equals eq. (2.106) with Omega of eq. (2.99) and the
// printed dOmega/dE_ij (with its (2 E_kk - 1) corrected to (2 E_kk + 1)), and both
// equal central differences of W_v(E) = p (Omega - 2 r sqrt(Omega) + r^2) (eq. 2.105).
TEST(VolumePreservation, StressMatchesEq2106) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  const double p = 7e3, r = 1.08;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::Matrix3d E;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) E(i, j) = E(j, i) = u(rng);
    const Eigen::Matrix3d C = 2.0 * E + Eigen::Matrix3d::Identity();
    const double omega = omega_299(E);
    ASSERT_NEAR(omega, C.determinant(), 1e-14);
    const double J = std::sqrt(omega);
    const Eigen::Matrix3d S_ours = 2.0 * p * (J - r) * J * C.inverse();
    const Eigen::Matrix3d S_thesis = p * domega_printed(E, +1.0) * (1.0 - r / std::sqrt(omega));
    EXPECT_LT((S_ours - S_thesis).cwiseAbs().maxCoeff(), 1e-12 * p);
    // As printed, (2 E_kk - 1): wrong off the diagonal.
    const Eigen::Matrix3d S_printed = p * domega_printed(E, -1.0) * (1.0 - r / std::sqrt(omega));
    EXPECT_GT((S_ours - S_printed).cwiseAbs().maxCoeff(), 1e-3 * S_ours.cwiseAbs().maxCoeff());
    // Central differences over the nine independent entries.
    auto W = [&](const Eigen::Matrix3d& e) {
      const double o = omega_299(e);
      return p * (o - 2.0 * r * std::sqrt(o) + r * r);
    };
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Eigen::Matrix3d ep = E, em = E;
        ep(i, j) += h;
        em(i, j) -= h;
        EXPECT_NEAR((W(ep) - W(em)) / (2 * h), S_ours(i, j), 1e-6 * p);
      }
  }
}

// The kernel's nodal forces are those of the virtual hexahedron with the eq. 2.106
// stress: f_a = -V0 F S g_a, for a non-affine configuration of a hex and a tet mesh.
TEST(VolumePreservation, AnisotropicForcesAreVirtualHexWithEq2106Stress) {
  const double p = 5e3, r = 0.93;
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    const auto mesh = fibred_block(1, t);
    const auto frames = solver::build_axis_frames(mesh);
    const auto term = solver::make_volume_term(mesh, &frames, params(p, r, VolumeDistribution::Anisotropic));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1, 31);
    const Eigen::Matrix3Xd f = test::forces_of(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()));
    Eigen::Matrix3Xd expect = Eigen::Matrix3Xd::Zero(3, x.cols());
    auto add = [&]<int K>() {
      const auto& grads = frames.nodal_gradient<K>();
      for (std::size_t k = 0; k < frames.size(); ++k) {
        const preprocess::Index* n = mesh.element(frames.element[k]);
        const Eigen::Matrix3d F = solver::element_positions<K>(x, n) * grads[k];
        const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
        const double omega = omega_299(E);
        const Eigen::Matrix3d S = p * domega_printed(E, +1.0) * (1.0 - r / std::sqrt(omega));
        const Eigen::Matrix<double, 3, K> fe = -frames.volume0[k] * F * S * grads[k].transpose();
        for (int a = 0; a < K; ++a) expect.col(n[a]) += fe.col(a);
      }
    };
    if (t == preprocess::Topology::Hex) {
      add.template operator()<8>();
    } else {
      add.template operator()<4>();
    }
    EXPECT_LT((f - expect).cwiseAbs().maxCoeff(), 1e-10 * expect.cwiseAbs().maxCoeff());
  }
}

// A homogeneous dilation x = lambda X of a cube: the Cauchy stress is the pressure
// sigma = 2 p (J - r) I (P = F S = 2 p (J - r) J F^{-T}, sigma = P F^T / J), and the
// energy is p V0 (lambda^3 - r)^2 summed. For every distribution the virial gives it:
// sum_a f_a . x_a = -2 p V0 (J - r) tr(cof(F)^T F) = -3 sigma V (V the current volume).
// Where G is a consistent FEM gradient (tetrahedra, and hexahedra with axis-aligned
// fibres or the isotropic distribution) the nodes of the face x = max carry the total
// force -sigma * (current face area) along x and interior nodes carry none.
TEST(VolumePreservation, HomogeneousDilationGivesAnalyticPressure) {
  const double p = 4e3, r = 1.05;
  for (auto t : {preprocess::Topology::Tet5, preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    for (bool aligned : {false, true}) {
      auto mesh = fibred_block(2, t);
      if (aligned) {
        mesh.fiber.colwise() = Eigen::Vector3d::UnitX();
        mesh.sheet.colwise() = Eigen::Vector3d::UnitY();
        mesh.normal.colwise() = Eigen::Vector3d::UnitZ();
      }
      const auto frames = solver::build_axis_frames(mesh);
      const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
      const double side = hi.x() - lo.x();
      ASSERT_NEAR(side, 2 * kH, 1e-15);
      for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
        const auto term = solver::make_volume_term(mesh, &frames, params(p, r, d));
        const bool consistent = t != preprocess::Topology::Hex || aligned || d == VolumeDistribution::Isotropic;
        for (double lambda : {0.9, 1.0, 1.1}) {
          SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + solver::volume_distribution_name(d) +
                       (aligned ? " / aligned" : " / oblique") + " / lambda " + std::to_string(lambda));
          const Eigen::Matrix3Xd x = lambda * mesh.nodes;
          const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
          const double J = lambda * lambda * lambda;
          const double sigma = 2.0 * p * (J - r);
          const double vol = J * side * side * side;
          const Eigen::Matrix3Xd f = test::forces_of(*term, x, v);
          EXPECT_NEAR((f.array() * x.array()).sum(), -3.0 * sigma * vol, 1e-10 * p * vol);
          EXPECT_NEAR(term->energy({x, v, 0.0}), p * side * side * side * (J - r) * (J - r),
                      1e-12 * p * side * side * side);
          if (!consistent) continue;
          double fx_face = 0.0;
          for (Eigen::Index i = 0; i < x.cols(); ++i) {
            const Eigen::Vector3d X = mesh.nodes.col(i);
            const bool boundary = (X - lo).minCoeff() < 1e-9 * kH || (hi - X).minCoeff() < 1e-9 * kH;
            if (X.x() > hi.x() - 1e-9 * kH) fx_face += f(0, i);
            if (!boundary) {
              EXPECT_LT(f.col(i).norm(), 1e-12 * p * kH * kH) << "interior node " << i;
            }
          }
          EXPECT_NEAR(fx_face, -sigma * lambda * lambda * side * side, 1e-10 * p * side * side);
        }
      }
    }
  }
}

// Volume control: forces vanish exactly at J = r (lambda = r^{1/3}), the energy has its
// minimum there, and at J < r they push the boundary outwards.
TEST(VolumePreservation, VolumeControlEquilibriumAtTargetRatio) {
  const double p = 1e4, r = 1.1;
  const auto mesh = fibred_block(2, preprocess::Topology::Hex);
  const auto frames = solver::build_axis_frames(mesh);
  for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
    const auto term = solver::make_volume_term(mesh, &frames, params(p, r, d));
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    const Eigen::Vector3d c = mesh.nodes.rowwise().mean();
    auto at = [&](double lambda) -> Eigen::Matrix3Xd { return ((mesh.nodes.colwise() - c) * lambda).colwise() + c; };
    const double ls = std::cbrt(r);
    const double f_ref = 2 * p * 0.1 * kH * kH;  // force scale at J - r = -0.1
    EXPECT_LT(test::forces_of(*term, at(ls), v).cwiseAbs().maxCoeff(), 1e-12 * f_ref);
    EXPECT_NEAR(term->energy({at(ls), v, 0.0}), 0.0, 1e-25);
    EXPECT_GT(term->energy({at(ls * 1.001), v, 0.0}), 0.0);
    EXPECT_GT(term->energy({at(ls * 0.999), v, 0.0}), 0.0);
    const Eigen::Matrix3Xd x1 = at(1.0);
    const Eigen::Matrix3Xd f1 = test::forces_of(*term, x1, v);
    for (Eigen::Index i = 0; i < x1.cols(); ++i) {
      EXPECT_GE(f1.col(i).dot(x1.col(i) - c), -1e-12 * f_ref * kH) << "node " << i << " pulled inwards";
    }
  }
}

// Relax a distorted block under volume control r = 1.1 with a damped Newton solve
// (dense, using the term's own Jacobian): every element reaches J = r.
TEST(VolumePreservation, NewtonRelaxationReachesTargetVolume) {
  const double p = 1e4, r = 1.1;
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    const auto mesh = fibred_block(2, t);
    const auto frames = solver::build_axis_frames(mesh);
    for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
      SCOPED_TRACE(std::string(preprocess::topology_name(t)) + " / " + solver::volume_distribution_name(d));
      const auto term = solver::make_volume_term(mesh, &frames, params(p, r, d));
      Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.05, 3);
      const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
      const Eigen::Index n = 3 * x.cols();
      const double kscale = p * kH;  // N/m
      // Levenberg-Marquardt with the exact Jacobian (the volume energy alone has many
      // zero modes, the isochoric motions): accept a step when the energy drops.
      double mu = 1e-3 * kscale;
      double e = term->energy({x, v, 0.0});
      int it = 0;
      for (; it < 200; ++it) {
        const Eigen::Matrix3Xd f = test::forces_of(*term, x, v);
        if (f.cwiseAbs().maxCoeff() < 1e-13 * p * kH * kH) break;
        test::DenseSink sink(x.cols());
        term->add_jacobian({x, v, 0.0}, sink);
        for (int tries = 0; tries < 40; ++tries) {
          const Eigen::MatrixXd Kt = -sink.kx + mu * Eigen::MatrixXd::Identity(n, n);
          const Eigen::VectorXd dx = Kt.ldlt().solve(Eigen::Map<const Eigen::VectorXd>(f.data(), n));
          const Eigen::Matrix3Xd xt = x + Eigen::Map<const Eigen::Matrix3Xd>(dx.data(), 3, x.cols());
          const double et = term->energy({xt, v, 0.0});
          if (et < e) {
            x = xt;
            e = et;
            mu = std::max(mu / 3.0, 1e-9 * kscale);
            break;
          }
          mu *= 4.0;
        }
      }
      EXPECT_LT(it, 200) << "no convergence";
      const auto& check = [&]<int K>() {
        const auto& kern = kernel_of<K>(*term);
        for (std::size_t i = 0; i < kern.size(); ++i) {
          EXPECT_NEAR(kern.volume_ratio(i, solver::element_positions<K>(x, mesh.element(kern.mesh_element[i]))), r,
                      1e-9);
        }
      };
      if (t == preprocess::Topology::Hex) {
        check.template operator()<8>();
      } else {
        check.template operator()<4>();
      }
      EXPECT_LT(term->energy({x, v, 0.0}), 1e-20);
    }
  }
}

// Time enters only through r(t): with a ramp r: 1 -> 1.2 over [0, 1] s, the energy and
// forces at t = 0.5 are those of a constant r = 1.1.
TEST(VolumePreservation, RatioFollowsTimeCourse) {
  const auto mesh = fibred_block(1, preprocess::Topology::Hex);
  const auto frames = solver::build_axis_frames(mesh);
  for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
    solver::VolumeParams vp = params(2e3, 1.0, d);
    vp.ratio = solver::TimeCourse::ramp(1.0, 1.2, 0.0, 1.0);
    const auto ramp = solver::make_volume_term(mesh, &frames, vp);
    const auto fixed = solver::make_volume_term(mesh, &frames, params(2e3, 1.1, d));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.05, 2);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    EXPECT_DOUBLE_EQ(ramp->energy({x, v, 0.5}), fixed->energy({x, v, 0.0}));
    EXPECT_LT((test::forces_of(*ramp, x, v, 0.5) - test::forces_of(*fixed, x, v, 0.0)).cwiseAbs().maxCoeff(), 1e-15);
    test::DenseSink a(x.cols()), b(x.cols());
    ramp->add_jacobian({x, v, 0.5}, a);
    fixed->add_jacobian({x, v, 0.0}, b);
    EXPECT_LT((a.kx - b.kx).cwiseAbs().maxCoeff(), 1e-12 * b.kx.cwiseAbs().maxCoeff());
    EXPECT_NE(ramp->energy({x, v, 0.0}), fixed->energy({x, v, 0.0}));
  }
}

TEST(VolumePreservation, SubsetActsOnlyOnItsElements) {
  const auto mesh = fibred_block(2, preprocess::Topology::Hex);
  const auto frames = solver::build_axis_frames(mesh);
  const std::vector<std::size_t> subset{0};
  for (auto d : {VolumeDistribution::Anisotropic, VolumeDistribution::Isotropic}) {
    const auto term = solver::make_volume_term(mesh, &frames, params(1e3, 1.2, d), &subset);
    const Eigen::Matrix3Xd f = test::forces_of(*term, mesh.nodes, Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols()));
    const preprocess::Index* n = mesh.element(0);
    for (Eigen::Index i = 0; i < f.cols(); ++i) {
      const bool in = std::find(n, n + 8, static_cast<preprocess::Index>(i)) != n + 8;
      if (in) {
        EXPECT_GT(f.col(i).norm(), 0.0);
      } else {
        EXPECT_EQ(f.col(i).norm(), 0.0);
      }
    }
    EXPECT_NEAR(term->energy({mesh.nodes, mesh.nodes, 0.0}), 1e3 * kH * kH * kH * 0.04, 1e-18);
  }
}

namespace {
void expect_input_error(const std::function<void()>& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no InputError (expected one mentioning '" << needle << "')";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(VolumePreservation, RejectsBadInput) {
  const auto mesh = fibred_block(1, preprocess::Topology::Hex);
  const auto frames = solver::build_axis_frames(mesh);
  const auto iso = VolumeDistribution::Isotropic;
  auto make = [&](const solver::VolumeParams& vp) { (void)solver::make_volume_term(mesh, &frames, vp); };
  for (double p : {0.0, -1.0, std::nan("")}) expect_input_error([&] { make(params(p, 1.0, iso)); }, "p (volume");
  for (double r : {0.0, -0.5, std::nan("")}) expect_input_error([&] { make(params(1e3, r, iso)); }, "r (target");
  solver::VolumeParams vp = params(1e3, 1.0, iso);
  vp.ratio = solver::TimeCourse::ramp(1.0, -0.1, 0.0, 1.0);
  expect_input_error([&] { make(vp); }, "r (target");
  vp.ratio = solver::TimeCourse::twitch(0.1, 0.0, 0.1, 0.2);
  expect_input_error([&] { make(vp); }, "r (target");
  vp.ratio = solver::TimeCourse::table({0.0, 1.0}, {1.0, 0.0});
  expect_input_error([&] { make(vp); }, "r (target");
  expect_input_error(
      [&] { (void)solver::make_volume_term(mesh, nullptr, params(1e3, 1.0, VolumeDistribution::Anisotropic)); },
      "axis frames");
  const std::vector<std::size_t> bad{5};
  expect_input_error([&] { (void)solver::make_volume_term(mesh, &frames, params(1e3, 1.0, iso), &bad); },
                     "element 5 out of range");
  // A subset element that has no axis frame.
  const auto big = fibred_block(2, preprocess::Topology::Hex);
  const std::vector<std::size_t> only{0, 1};
  const auto part = solver::build_axis_frames(big, &only);
  const std::vector<std::size_t> want{2};
  expect_input_error(
      [&] { (void)solver::make_volume_term(big, &part, params(1e3, 1.0, VolumeDistribution::Anisotropic), &want); },
      "element 2 has no axis frame");
  // Frames of a tet mesh with a hex mesh.
  const auto tets = fibred_block(1, preprocess::Topology::Tet5);
  const auto tet_frames = solver::build_axis_frames(tets);
  expect_input_error(
      [&] { (void)solver::make_volume_term(mesh, &tet_frames, params(1e3, 1.0, VolumeDistribution::Anisotropic)); },
      "element type");
  // An inverted reference element (isotropic V0 from the mesh).
  auto inverted = mesh;
  inverted.nodes.row(2) *= -1.0;
  expect_input_error([&] { (void)solver::make_volume_term(inverted, nullptr, params(1e3, 1.0, iso)); },
                     "element 0 has reference volume");
}
