// The nodal-averaged volume term (solver/terms/fem/nodal_volume.hpp) and the volume penalty
// forms (solver/terms/fem/volume_penalty.hpp): derivative harness for every form on tetrahedra
// and hexahedra, the sparse pattern it announces, exact energy under uniform dilatation, the
// penalty derivatives, and the error paths.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>

#include "common/error.hpp"
#include "force_term_harness.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/terms/fem/volume_penalty.hpp"

using namespace adamss;
using solver::Index;
using solver::VolumePenalty;
using solver::VolumePenaltyForm;

namespace {

constexpr VolumePenaltyForm kForms[] = {VolumePenaltyForm::Quadratic, VolumePenaltyForm::Log,
                                        VolumePenaltyForm::SimoTaylor};

preprocess::Mesh box(const std::string& topo) {
  return preprocess::make_box_mesh({1.5e-3, 1e-3, 1e-3}, {3, 2, 2}, topo);
}

solver::NodalVolumeParams params(VolumePenaltyForm form, double r = 1.0) {
  return {{form, 5e3}, solver::TimeCourse::constant(r), {}};
}

}  // namespace

TEST(VolumePenalty, DerivativesMatchFiniteDifferences) {
  for (const VolumePenaltyForm f : kForms) {
    SCOPED_TRACE(solver::volume_penalty_name(f));
    const VolumePenalty u{f, 3.0};
    for (const double r : {1.0, 0.8}) {
      for (const double J : {0.7, 1.0, 1.3}) {
        const double h = 1e-6;
        EXPECT_NEAR(u.slope(J, r), (u.value(J + h, r) - u.value(J - h, r)) / (2 * h), 1e-7);
        EXPECT_NEAR(u.curvature(J, r), (u.slope(J + h, r) - u.slope(J - h, r)) / (2 * h), 1e-6);
      }
      EXPECT_DOUBLE_EQ(u.value(r, r), 0.0);
      EXPECT_NEAR(u.slope(r, r), 0.0, 1e-15);
    }
    EXPECT_NEAR(u.curvature(1.0, 1.0), 6.0, 1e-12) << "bulk modulus 2 p at J = r = 1";
  }
  EXPECT_TRUE(std::isinf(VolumePenalty{VolumePenaltyForm::Log, 1.0}.value(-0.1, 1.0)));
  EXPECT_TRUE(std::isnan(VolumePenalty{VolumePenaltyForm::SimoTaylor, 1.0}.slope(0.0, 1.0)));
  EXPECT_DOUBLE_EQ((VolumePenalty{VolumePenaltyForm::Quadratic, 1.0}.value(0.0, 1.0)), 1.0);
}

TEST(NodalVolume, PassesHarnessForEveryFormOnTetAndHex) {
  for (const std::string topo : {"tet6m", "tet5", "hex"}) {
    const preprocess::Mesh mesh = box(topo);
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.06);
    for (const VolumePenaltyForm f : kForms) {
      for (const double r : {1.0, 1.1}) {
        SCOPED_TRACE(topo + " / " + solver::volume_penalty_name(f) + " r " + std::to_string(r));
        const auto term = solver::make_nodal_volume_term(mesh, params(f, r));
        EXPECT_EQ(term->name(), "volume_preservation");
        test::HarnessOptions opt;
        opt.tolerance = 2e-6;
        test::check_force_term(*term, x, Eigen::Matrix3Xd::Zero(3, x.cols()), 0.5e-3, opt);
      }
    }
  }
}

TEST(NodalVolume, AnnouncesEveryBlockItFills) {
  // Every non-zero Jacobian block (a, b) either joins two nodes of one element or is in
  // add_couplings, and the couplings reach beyond the elements (nodes two elements apart):
  // otherwise the preallocated PETSc matrix would refuse the entry.
  const preprocess::Mesh mesh = box("tet6m");
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.06);
  const auto term = solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::SimoTaylor));
  test::DenseSink sink(x.cols());
  term->add_jacobian({x, x * 0.0, 0.0}, sink);
  std::set<std::pair<Index, Index>> allowed;
  for (std::size_t e = 0; e < mesh.element_count(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) allowed.insert({mesh.element(e)[a], mesh.element(e)[b]});
  const std::size_t element_pairs = allowed.size();
  std::vector<std::vector<Index>> adj(static_cast<std::size_t>(x.cols()));
  term->add_couplings(adj);
  for (std::size_t a = 0; a < adj.size(); ++a)
    for (const Index b : adj[a]) allowed.insert({static_cast<Index>(a), b});
  EXPECT_GT(allowed.size(), element_pairs) << "the patches couple nodes beyond the elements";
  int filled = 0;
  for (Index a = 0; a < x.cols(); ++a)
    for (Index b = 0; b < x.cols(); ++b) {
      if (sink.kx.block<3, 3>(3 * a, 3 * b).cwiseAbs().maxCoeff() == 0.0) continue;
      ++filled;
      EXPECT_TRUE(allowed.count({a, b})) << "block (" << a << ", " << b << ") is not in the pattern";
    }
  EXPECT_GT(filled, static_cast<int>(element_pairs)) << "the Jacobian does fill blocks beyond the elements";
}

TEST(NodalVolume, UniformDilatationGivesTheTotalVolumeEnergy) {
  // x = lambda X: every nodal ratio is lambda^3, so the energy is V0 U(lambda^3) with V0 the
  // box volume; and the nodal ratios sum the element volumes exactly (no quadrature error).
  for (const std::string topo : {"tet6m", "hex"}) {
    const preprocess::Mesh mesh = box(topo);
    const double lambda = 1.04, v0 = 1.5e-9;
    const Eigen::Matrix3Xd x = lambda * mesh.nodes;
    for (const VolumePenaltyForm f : kForms) {
      const auto term = solver::make_nodal_volume_term(mesh, params(f));
      const double expect = v0 * VolumePenalty{f, 5e3}.value(lambda * lambda * lambda, 1.0);
      EXPECT_NEAR(term->energy({x, x * 0.0, 0.0}), expect, 1e-12 * expect) << topo;
    }
  }
}

TEST(NodalVolume, OneElementEqualsTheElementTerm) {
  // On a single tetrahedron every node's patch is the element itself: J_n = V / V0 at all four
  // nodes, so the nodal term is exactly the isotropic element term.
  preprocess::Mesh mesh = box("tet6m");
  mesh.connectivity.resize(4);
  mesh.labels.resize(1);
  const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.08);
  solver::VolumeParams vp;
  vp.p = 5e3;
  vp.distribution = solver::VolumeDistribution::Isotropic;
  const auto elem = solver::make_volume_term(mesh, nullptr, vp);
  const auto nodal = solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::Quadratic));
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  const double e = elem->energy({x, v, 0.0});
  EXPECT_GT(e, 0.0);
  EXPECT_NEAR(nodal->energy({x, v, 0.0}), e, 1e-12 * e);
  EXPECT_LT((test::forces_of(*nodal, x, v) - test::forces_of(*elem, x, v)).cwiseAbs().maxCoeff(),
            1e-12 * test::forces_of(*elem, x, v).cwiseAbs().maxCoeff());
}

TEST(NodalVolume, RefusesBadInput) {
  const preprocess::Mesh mesh = box("tet6m");
  EXPECT_THROW((void)solver::make_nodal_volume_term(mesh, {{VolumePenaltyForm::Quadratic, 0.0}, {}, {}}), InputError);
  EXPECT_THROW((void)solver::make_nodal_volume_term(mesh, {{VolumePenaltyForm::Quadratic, NAN}, {}, {}}), InputError);
  EXPECT_THROW((void)solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::Log, -1.0)), InputError);
  const std::vector<std::size_t> none;
  EXPECT_THROW((void)solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::Log), &none), InputError);
  const std::vector<std::size_t> past{mesh.element_count()};
  EXPECT_THROW((void)solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::Log), &past), InputError);
  preprocess::Mesh inverted = mesh;
  std::swap(inverted.connectivity[0], inverted.connectivity[1]);  // two nodes of element 0: inverted
  try {
    (void)solver::make_nodal_volume_term(inverted, params(VolumePenaltyForm::Log));
    FAIL() << "an inverted element was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("element 0"), std::string::npos) << e.what();
  }
}

TEST(NodalVolume, FixedNodesGiveTheirVolumeToFreeOnesWhenAsked) {
  // constrain_fixed_nodes: false. The nodes on the face x = 0 are fixed in all three axes (and
  // the nodes of x = 1.5 mm in one axis only, which keep their constraints). The fixed nodes carry
  // no constraint; their shares of each element's volume go to its free nodes, so the nodal
  // volumes still sum to the total volume (a uniform dilatation still costs V0 U(lambda^3)); the
  // forces and the Jacobian stay the exact derivatives of the energy; the tet10 corner projection
  // refuses the option.
  for (const std::string topo : {"tet6m", "hex"}) {
    SCOPED_TRACE(topo);
    const preprocess::Mesh mesh = box(topo);
    std::vector<std::uint8_t> mask(mesh.node_count(), 0);
    int fixed = 0;
    for (std::size_t n = 0; n < mesh.node_count(); ++n) {
      if (mesh.nodes(0, static_cast<Eigen::Index>(n)) < 1e-12) {
        mask[n] = 7;
        ++fixed;
      } else if (mesh.nodes(0, static_cast<Eigen::Index>(n)) > 1.5e-3 - 1e-12) {
        mask[n] = 1;
      }
    }
    ASSERT_GT(fixed, 0);
    solver::NodalVolumeParams released = params(VolumePenaltyForm::Quadratic);
    released.constrain_fixed_nodes = false;
    const auto term = solver::make_nodal_volume_term(mesh, released);
    const auto kept = solver::make_nodal_volume_term(mesh, params(VolumePenaltyForm::Quadratic));
    const Eigen::Matrix3Xd x = test::perturbed(mesh.nodes, 0.5e-3, 0.06);
    const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
    const double before = term->energy({x, v, 0.0});
    EXPECT_NEAR(before, kept->energy({x, v, 0.0}), 1e-12 * before) << "nothing changes before the mask";
    term->set_boundary_mask(mask);
    kept->set_boundary_mask(mask);
    EXPECT_NEAR(kept->energy({x, v, 0.0}), before, 1e-12 * before) << "the default keeps every constraint";
    const double after = term->energy({x, v, 0.0});
    EXPECT_GT(after, 0.0);
    EXPECT_GT(std::abs(after / before - 1.0), 1e-3) << "the patches did change";
    EXPECT_NE(term->describe().find(std::to_string(fixed) + " fixed nodes released"), std::string::npos)
        << term->describe();
    const double lambda = 1.04;
    const Eigen::Matrix3Xd xd = lambda * mesh.nodes;
    const double expect =
        1.5e-9 * VolumePenalty{VolumePenaltyForm::Quadratic, 5e3}.value(lambda * lambda * lambda, 1.0);
    EXPECT_NEAR(term->energy({xd, v, 0.0}), expect, 1e-12 * expect) << "the free nodes hold the whole volume";
    test::HarnessOptions opt;
    opt.tolerance = 2e-6;
    test::check_force_term(*term, x, v, 0.5e-3, opt);
    // Every node fixed: nothing can move and no constraint is left.
    term->set_boundary_mask(std::vector<std::uint8_t>(mesh.node_count(), 7));
    EXPECT_EQ(term->energy({x, v, 0.0}), 0.0);
    EXPECT_EQ(test::forces_of(*term, x, v).cwiseAbs().maxCoeff(), 0.0);
  }
  solver::NodalVolumeParams released = params(VolumePenaltyForm::Quadratic);
  released.constrain_fixed_nodes = false;
  EXPECT_THROW((void)solver::make_nodal_volume_term(preprocess::make_quadratic(box("tet6m")), released), InputError);
}
