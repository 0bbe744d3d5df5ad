// Material-specific friction (seed 000 eqs. 2.107-2.111) and global friction (eq. 2.118).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <type_traits>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/terms/loads/global_friction.hpp"
#include "solver/core/mass.hpp"
#include "solver/terms/adamss/material_friction.hpp"
#include "support/fibre_fixtures.hpp"
#include "support/lattice_fixtures.hpp"

using namespace adamss;
using solver::MaterialFrictionParams;

namespace {

constexpr double kH = 1e-3;  // voxel size of block_mesh (m)

Eigen::Matrix3Xd random_velocities(Eigen::Index n, double speed, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd v(3, n);
  for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = speed * u(rng);
  return v;
}

MaterialFrictionParams friction(MaterialFrictionParams::Scaling s, Eigen::Vector3d eta = {2.0, 0.7, 0.3}) {
  MaterialFrictionParams p;
  p.scaling = s;
  p.value = eta;  // Pa s
  return p;
}

constexpr std::array<MaterialFrictionParams::Scaling, 2> kScalings{MaterialFrictionParams::Scaling::Virtual,
                                                                   MaterialFrictionParams::Scaling::Face};

}  // namespace

// -------------------------------------------------------------------- material friction

TEST(MaterialFriction, PassesHarnessOnTetAndHexMeshes) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Tet5, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 1, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    for (auto s : kScalings) {
      SCOPED_TRACE(std::string(preprocess::topology_name(t)) +
                   (s == MaterialFrictionParams::Scaling::Face ? " / face" : " / virtual"));
      const auto term = solver::make_material_friction_term(mesh, frames, friction(s));
      EXPECT_EQ(term->name(), "material_friction");
      EXPECT_FALSE(term->has_energy());
      EXPECT_TRUE(term->has_jacobian());
      const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1);
      const Eigen::Matrix3Xd v = random_velocities(x.cols(), 0.01, 5);
      test::HarnessOptions opt;
      opt.tolerance = 1e-6;
      test::check_force_term(*term, x, v, kH, opt);
    }
  }
}

// v = u + omega x x: every chord only rotates (zeta_dot = omega x zeta), so w = 0.
TEST(MaterialFriction, RigidMotionGivesZeroForce) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 1, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1);
    const Eigen::Vector3d omega(3.0, -1.0, 2.0), u(0.01, 0.02, -0.03);  // rad/s, m/s
    Eigen::Matrix3Xd v(3, x.cols());
    for (Eigen::Index i = 0; i < x.cols(); ++i) v.col(i) = u + omega.cross(Eigen::Vector3d(x.col(i)));
    for (auto s : kScalings) {
      const auto term = solver::make_material_friction_term(mesh, frames, friction(s));
      // Reference scale: the forces of a random velocity field of the same size (|v| ~ 0.03 m/s).
      const double ref = test::forces_of(*term, x, random_velocities(x.cols(), 0.03, 9)).cwiseAbs().maxCoeff();
      ASSERT_GT(ref, 0.0);
      EXPECT_LT(test::forces_of(*term, x, v).cwiseAbs().maxCoeff(), 1e-12 * ref);
    }
  }
}

// The power v . f = -sum c_l w_l^2 is never positive, and strictly negative for generic v.
TEST(MaterialFriction, DissipatesForRandomStates) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 2, 1, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    for (auto s : kScalings) {
      const auto term = solver::make_material_friction_term(mesh, frames, friction(s));
      for (unsigned seed = 1; seed <= 20; ++seed) {
        const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.15, seed);
        const Eigen::Matrix3Xd v = random_velocities(x.cols(), 0.01, 100 + seed);
        const double power = (v.array() * test::forces_of(*term, x, v).array()).sum();
        EXPECT_LT(power, 0.0) << "seed " << seed;
      }
    }
  }
}

// One cube element, axes along its edges, uniaxial strain rate eps_dot along the
// fibre: the viscous force on the x+ face is eta eps_dot h^2 (stress eta eps_dot times
// area), a quarter per corner node, pointing inward (resisting the extension).
TEST(MaterialFriction, UniaxialStrainRateGivesViscousStress) {
  auto mesh = test::block_mesh(1, 1, 1, preprocess::Topology::Hex);
  test::set_axis_fibres(mesh);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const double eta = 3.0, eps_dot = 2.0;  // Pa s, 1/s
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  v.row(0) = eps_dot * mesh.nodes.row(0);
  const double expected = eta * eps_dot * kH * kH / 4.0;  // N per node
  MaterialFrictionParams kd = friction(MaterialFrictionParams::Scaling::Virtual, {eta, 0.0, 0.0});
  kd.coefficient = MaterialFrictionParams::Coefficient::ThesisKd;
  kd.value = {eta / kH, 0.0, 0.0};  // k_d = eta / l0 (N s/m^3)
  for (const auto& p : {friction(MaterialFrictionParams::Scaling::Virtual, {eta, 0.0, 0.0}),
                        friction(MaterialFrictionParams::Scaling::Face, {eta, 0.0, 0.0}), kd}) {
    const auto term = solver::make_material_friction_term(mesh, frames, p);
    const Eigen::Matrix3Xd f = test::forces_of(*term, mesh.nodes, v);
    const double mid = mesh.nodes.row(0).mean();
    for (Eigen::Index n = 0; n < f.cols(); ++n) {
      const double side = mesh.nodes(0, n) > mid ? -1.0 : 1.0;
      EXPECT_NEAR(f(0, n), side * expected, 1e-12 * expected) << "node " << n;
      EXPECT_NEAR(f(1, n), 0.0, 1e-12 * expected);
      EXPECT_NEAR(f(2, n), 0.0, 1e-12 * expected);
    }
  }
  // A sheet or normal strain rate does not load the fibre viscosity.
  Eigen::Matrix3Xd vy = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
  vy.row(1) = eps_dot * mesh.nodes.row(1);
  const auto term = solver::make_material_friction_term(
      mesh, frames, friction(MaterialFrictionParams::Scaling::Virtual, {eta, 0.0, 0.0}));
  EXPECT_LT(test::forces_of(*term, mesh.nodes, vy).cwiseAbs().maxCoeff(), 1e-15 * expected);
}

// Resolution independence of the viscosity parameter: for an affine velocity field
// v = L x the axial rate of every chord at the reference state is w_l = l0_l (e_l . L e_l),
// so the virtual-scaling power is exactly -sum_elements V0 sum_l eta_l (e_l . L e_l)^2
// = -V_total sum_l eta_l (e_l . L e_l)^2 on any mesh, at any resolution.
TEST(MaterialFriction, ViscosityPowerIsVolumeTimesDensityAtAnyResolution) {
  const Eigen::Vector3d eta(2.0, 0.7, 0.3);
  Eigen::Matrix3d lgrad;
  lgrad << 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.6, 0.3, 0.25;  // 1/s
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Hex}) {
    for (int n : {1, 2, 4}) {  // 2 mm cube as n^3 elements (voxels)
      auto mesh = test::block_mesh(n, n, n, t);
      mesh.nodes *= 2.0 / n;
      test::set_rotated_fibres(mesh, true);
      const solver::AxisFrames frames = solver::build_axis_frames(mesh);
      const Eigen::Matrix3Xd v = lgrad * mesh.nodes;
      const auto term =
          solver::make_material_friction_term(mesh, frames, friction(MaterialFrictionParams::Scaling::Virtual, eta));
      const double power = (v.array() * test::forces_of(*term, mesh.nodes, v).array()).sum();
      Eigen::Matrix3d b;
      b << mesh.fiber.col(0), mesh.sheet.col(0), mesh.normal.col(0);
      double density = 0.0;
      for (int l = 0; l < 3; ++l) density += eta[l] * std::pow(b.col(l).dot(lgrad * b.col(l)), 2);
      const double volume = 8e-9;  // (2 mm)^3
      EXPECT_NEAR(power, -volume * density, 1e-10 * volume * density) << preprocess::topology_name(t) << " n = " << n;
    }
  }
}

// The literal k_d is not resolution independent: with the same k_d the power of the
// same flow halves when the element size halves (c = V0 k_d / l0 ~ l0^2, w ~ l0, and
// there are (1/l0)^3 elements: total ~ l0^-3 l0^2 l0^2 = l0).
TEST(MaterialFriction, LiteralKdDependsOnResolution) {
  MaterialFrictionParams p;
  p.coefficient = MaterialFrictionParams::Coefficient::ThesisKd;
  p.value = {1000.0, 0.0, 0.0};
  double power[2];
  for (int k = 0; k < 2; ++k) {
    const int n = 1 << k;  // 1 or 2 elements per direction over 1 mm
    auto mesh = test::block_mesh(n, n, n, preprocess::Topology::Hex);
    mesh.nodes /= n;
    test::set_axis_fibres(mesh);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, mesh.nodes.cols());
    v.row(0) = mesh.nodes.row(0);
    const auto term = solver::make_material_friction_term(mesh, frames, p);
    power[k] = (v.array() * test::forces_of(*term, mesh.nodes, v).array()).sum();
  }
  EXPECT_NEAR(power[1] / power[0], 0.5, 1e-12);
}

// Face scaling at the reference state: c_l = k_d,l / 2 sum_j S_j |n_j . zh_l| with S_j, n_j
// the reference face areas/normals of the axis frame (planar faces: exact).
TEST(MaterialFriction, FaceScalingMatchesAxisFrameFaceData) {
  for (auto t : {preprocess::Topology::Tet6m, preprocess::Topology::Tet5, preprocess::Topology::Hex}) {
    auto mesh = test::block_mesh(2, 1, 1, t);
    test::set_rotated_fibres(mesh, false);
    const solver::AxisFrames frames = solver::build_axis_frames(mesh);
    const Eigen::Vector3d eta(2.0, 0.7, 0.3);
    const auto check = [&](const auto& kern) {
      for (std::size_t i = 0; i < kern.size(); ++i) {
        constexpr int K = std::decay_t<decltype(kern.chord[0])>::RowsAtCompileTime;
        const auto x = solver::element_positions<K>(mesh.nodes, mesh.element(kern.element[i]));
        const Eigen::Vector3d c = kern.damping(i, x);
        for (int l = 0; l < 3; ++l) {
          const Eigen::Vector3d zh = frames.axes0[i].col(l).normalized();
          const double kd = eta[l] / frames.length0[i][l];
          const double expected =
              0.5 * kd *
              (frames.face_area[i][2 * l] * std::abs(frames.face_normal[i].col(2 * l).dot(zh)) +
               frames.face_area[i][2 * l + 1] * std::abs(frames.face_normal[i].col(2 * l + 1).dot(zh)));
          EXPECT_NEAR(c[l], expected, 1e-12 * expected) << "item " << i << " axis " << l;
        }
      }
    };
    const auto p = friction(MaterialFrictionParams::Scaling::Face, eta);
    if (t == preprocess::Topology::Hex) {
      check(solver::make_material_friction_kernel<8>(mesh, frames, p));
    } else {
      check(solver::make_material_friction_kernel<4>(mesh, frames, p));
    }
  }
}

// Virtual scaling: c_l = R_v A_l^0 k_d,l = V0 eta_l / l0_l^2.
TEST(MaterialFriction, VirtualCoefficientIsVolumeOverLengthSquared) {
  auto mesh = test::block_mesh(2, 1, 1, preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  const Eigen::Vector3d eta(2.0, 0.7, 0.3);
  const auto kern =
      solver::make_material_friction_kernel<4>(mesh, frames, friction(MaterialFrictionParams::Scaling::Virtual, eta));
  ASSERT_EQ(kern.size(), frames.size());
  for (std::size_t i = 0; i < kern.size(); ++i) {
    for (int l = 0; l < 3; ++l) {
      const double expected = frames.volume0[i] * eta[l] / std::pow(frames.length0[i][l], 2);
      EXPECT_NEAR(kern.coefficient[i][l], expected, 1e-12 * expected);
    }
  }
}

TEST(MaterialFriction, ErrorsAndSubsets) {
  auto mesh = test::block_mesh(2, 1, 1, preprocess::Topology::Tet6m);
  test::set_rotated_fibres(mesh, false);
  const solver::AxisFrames frames = solver::build_axis_frames(mesh);
  auto bad = friction(MaterialFrictionParams::Scaling::Virtual, {1.0, -0.1, 0.0});
  try {
    (void)solver::make_material_friction_term(mesh, frames, bad);
    FAIL() << "negative viscosity accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material_friction.viscosity[sheet]"), std::string::npos) << e.what();
  }
  bad.value = {std::nan(""), 0.0, 0.0};
  EXPECT_THROW((void)solver::make_material_friction_term(mesh, frames, bad), InputError);
  bad.coefficient = MaterialFrictionParams::Coefficient::ThesisKd;
  bad.value = {0.0, 0.0, -1.0};
  try {
    (void)solver::make_material_friction_term(mesh, frames, bad);
    FAIL() << "negative k_d accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material_friction.kd[normal]"), std::string::npos) << e.what();
  }
  const auto good = friction(MaterialFrictionParams::Scaling::Face);
  EXPECT_THROW((void)solver::make_material_friction_kernel<8>(mesh, frames, good), InputError);
  const std::vector<std::size_t> out = {mesh.element_count()};
  EXPECT_THROW((void)solver::make_material_friction_term(mesh, frames, good, &out), InputError);
  // Complementary subsets add up to the whole.
  std::vector<std::size_t> a, b;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) (e % 3 == 0 ? a : b).push_back(e);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1);
  const Eigen::Matrix3Xd v = random_velocities(x.cols(), 0.01, 2);
  const Eigen::Matrix3Xd fa = test::forces_of(*solver::make_material_friction_term(mesh, frames, good, &a), x, v);
  const Eigen::Matrix3Xd fb = test::forces_of(*solver::make_material_friction_term(mesh, frames, good, &b), x, v);
  const Eigen::Matrix3Xd fall = test::forces_of(*solver::make_material_friction_term(mesh, frames, good), x, v);
  EXPECT_LT((fa + fb - fall).cwiseAbs().maxCoeff(), 1e-13 * fall.cwiseAbs().maxCoeff());
}

// -------------------------------------------------------------------- global friction

TEST(GlobalFriction, LiteralPassesHarnessAndOpposesVelocity) {
  const auto mesh = test::block_mesh(2, 2, 1, preprocess::Topology::Tet6m);
  const auto term = solver::make_global_friction_term(mesh.node_count(), 0.25);
  EXPECT_EQ(term->name(), "global_friction");
  EXPECT_FALSE(term->has_energy());
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, kH, 0.1);
  const Eigen::Matrix3Xd v = random_velocities(x.cols(), 0.01, 4);
  test::HarnessOptions opt;
  opt.internal = false;  // drag against the lab frame: not momentum-conserving
  test::check_force_term(*term, x, v, kH, opt);
  EXPECT_LT((test::forces_of(*term, x, v) + 0.25 * v).cwiseAbs().maxCoeff(), 1e-18);
  test::DenseSink sink(x.cols());
  term->add_jacobian({x, v, 0.0}, sink);
  EXPECT_EQ((sink.kv + 0.25 * Eigen::MatrixXd::Identity(3 * x.cols(), 3 * x.cols())).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(sink.kx.cwiseAbs().maxCoeff(), 0.0);
  // mu = 0: no friction.
  EXPECT_EQ(test::forces_of(*solver::make_global_friction_term(mesh.node_count(), 0.0), x, v).cwiseAbs().maxCoeff(),
            0.0);
}

// Total drag on a uniformly moving 2 mm cube at two resolutions: the mass-proportional
// variant gives -c M v at both, the literal one -N mu v (N = particle count).
TEST(GlobalFriction, MassProportionalIsResolutionIndependent) {
  const double rho = 1000.0, rate = 5.0, mu = 1e-3;
  const Eigen::Vector3d u(0.1, -0.2, 0.05);
  double literal[2], proportional[2];
  int k = 0;
  for (int n : {2, 4}) {
    auto mesh = test::block_mesh(n, n, n, preprocess::Topology::Tet6m);
    mesh.nodes *= 2.0 / n;
    const Eigen::VectorXd m = solver::voronoi_masses(mesh, std::vector<double>(mesh.element_count(), rho));
    const Eigen::Matrix3Xd v = u.replicate(1, mesh.nodes.cols());
    const auto prop = solver::make_mass_proportional_friction_term(m, rate);
    test::HarnessOptions opt;
    opt.internal = false;
    test::check_force_term(*prop, mesh.nodes, random_velocities(mesh.nodes.cols(), 0.01, 8), kH, opt);
    const Eigen::Vector3d fp = test::forces_of(*prop, mesh.nodes, v).rowwise().sum();
    const Eigen::Vector3d fl =
        test::forces_of(*solver::make_global_friction_term(mesh.node_count(), mu), mesh.nodes, v).rowwise().sum();
    const double total_mass = rho * 8e-9;
    EXPECT_LT((fp + rate * total_mass * u).norm(), 1e-12 * rate * total_mass * u.norm());
    EXPECT_LT((fl + static_cast<double>(mesh.node_count()) * mu * u).norm(), 1e-12 * fl.norm());
    proportional[k] = fp.norm();
    literal[k] = fl.norm();
    ++k;
  }
  EXPECT_NEAR(proportional[1] / proportional[0], 1.0, 1e-12);
  EXPECT_NEAR(literal[1] / literal[0], 125.0 / 27.0, 1e-12);  // 5^3 vs 3^3 nodes
}

TEST(GlobalFriction, RejectsBadInput) {
  try {
    (void)solver::make_global_friction_term(4, -1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("global_friction.mu"), std::string::npos);
  }
  EXPECT_THROW((void)solver::make_global_friction_term(4, std::nan("")), InputError);
  const Eigen::VectorXd m = Eigen::VectorXd::Constant(3, 1e-6);
  try {
    (void)solver::make_mass_proportional_friction_term(m, -2.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("global_friction.rate"), std::string::npos);
  }
  Eigen::VectorXd bad = m;
  bad[1] = -1.0;
  try {
    (void)solver::make_mass_proportional_friction_term(bad, 1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("node 1"), std::string::npos);
  }
}
