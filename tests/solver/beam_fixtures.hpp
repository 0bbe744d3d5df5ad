#pragma once
// Land problem 1's beam as a model built in code, for the static solver's tests of the volume
// penalty (its augmented Lagrangian and its continuation): a 10 x 1 x 1 mm cantilever of
// hexahedra, the uncoupled Guccione law at the Gauss points, clamped at x = 0, its free end's z
// moved by `lift` (m) over t in [0, 1], with the volume term the caller builds on its mesh.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "materials/factory.hpp"
#include "materials/uncoupled.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "solver/core/mass.hpp"
#include "solver/core/model.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/fem/fem_element.hpp"

namespace adamss::test {

using VolumeTermMaker = std::function<std::unique_ptr<solver::ForceTerm>(const preprocess::Mesh&)>;

/// One volume constraint per element (the Q1/P0 penalty of the Land scenes): the isotropic
/// volume term in Simo-Taylor form with penalty `p` (Pa) and, if given, augmented-Lagrangian settings.
inline std::unique_ptr<solver::ForceTerm> element_volume(const preprocess::Mesh& mesh, double p,
                                                         const solver::AugmentedLagrangian& al = {}) {
  solver::VolumeParams vp;
  vp.p = p;
  vp.distribution = solver::VolumeDistribution::Isotropic;
  vp.form = solver::VolumePenaltyForm::SimoTaylor;
  vp.augmented = al;
  return solver::make_volume_term(mesh, nullptr, vp);
}

/// The beam's model: terms[0] the law (fem_element), terms[1] what `volume` returns.
inline solver::Model lifted_guccione_beam(const std::array<int, 3>& divisions, double lift,
                                          const VolumeTermMaker& volume) {
  auto mesh = std::make_shared<preprocess::Mesh>(preprocess::make_box_mesh({10e-3, 1e-3, 1e-3}, divisions, "hex"));
  solver::Model model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.mass = solver::voronoi_masses(*mesh, std::vector<double>(mesh->element_count(), 1000.0));
  model.constraints = solver::Constraints(mesh->node_count());
  const auto law = std::make_shared<materials::UncoupledLaw>(materials::make_law("guccione_land_problem1", {}));
  model.terms.push_back(solver::make_gauss_point_term(*mesh, law, nullptr, "fem_element"));
  model.terms.push_back(volume(*mesh));
  for (Eigen::Index i = 0; i < model.x_ref.cols(); ++i) {
    const auto n = static_cast<preprocess::Index>(i);
    if (model.x_ref(0, i) < 1e-9) model.constraints.fix(n, 7, "clamp");
    if (model.x_ref(0, i) > 10e-3 - 1e-9)
      model.constraints.control(n, 2, solver::TimeCourse::ramp(0.0, lift, 0.0, 1.0), false, "lift");
  }
  return model;
}

}  // namespace adamss::test
