#pragma once
// The runtime interface of a constitutive law, and the adapter that turns any concrete
// (templated, non-virtual) law into one.
//
// Conventions shared by every law in adamss::materials
// ----------------------------------------------------
// * Frame: all tensors have components in the element's fibre frame (f, s, n) = (1, 2, 3).
// * Strain: Green-Lagrange E = 1/2 (F^T F - I), symmetric, dimensionless.
// * Energy: W(E) in Pa = J/m^3 per unit reference volume. Every law's W is written as a
//   function of all nine entries of E and is symmetric under E_ij <-> E_ji; a law whose
//   textbook form names an off-diagonal pair once (Hunter's k12 E12^2 term) is evaluated on
//   the symmetric part e_ij = (E_ij + E_ji)/2.
// * Stress: second Piola-Kirchhoff S_ij = dW/dE_ij, the derivative taken with E_ij and E_ji
//   as independent entries. Because W is symmetric in them, S is symmetric, and
//   dW = S : dE = sum_ij S_ij dE_ij for every symmetric increment dE. (Equivalently
//   S_ij = 1/2 (dW/dE_ij + dW/dE_ji) of any form of W.) For a single shear pair that means
//   S_12 = 1/2 dW/d(E_12), where W is read as a function of the one value E_12 = E_21.
// * Tangent: tangent(E) is the 6x6 Voigt matrix of voigt.hpp (order 11,22,33,23,13,12,
//   engineering shear strain): dS_voigt = D dE_voigt with dE_voigt = (dE11,dE22,dE33,
//   2dE23,2dE13,2dE12). apply_tangent(E, dE) = dS for a symmetric 3x3 dE, without Voigt.
// * stress_and_tangent(E, S, D) gives both at once (a Jacobian assembly needs both at every
//   point): a law that shares work between them (Guccione's exp(Q), the uncoupled split's
//   C^-1, J^-2/3 and base stress) overrides it; the default calls stress and tangent.
// * No heap allocation in energy / stress / tangent / apply_tangent (fixed-size Eigen only).
#include <Eigen/Core>
#include <string_view>
#include <utility>

#include "materials/voigt.hpp"

namespace adamss::materials {

/// A hyperelastic law chosen at run time (the solver builds one per material from a scene).
class Law {
 public:
  virtual ~Law() = default;
  /// Kind of law ("hunter", "guccione", "svk", "neo_hookean", ...).
  virtual std::string_view name() const = 0;
  /// Strain-energy density W(E) [Pa].
  virtual double energy(const Eigen::Matrix3d& E) const = 0;
  /// Second Piola-Kirchhoff stress S = dW/dE [Pa], symmetric.
  virtual Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const = 0;
  /// Voigt tangent D = dS/dE [Pa] (see the conventions above).
  virtual Matrix6d tangent(const Eigen::Matrix3d& E) const = 0;
  /// dS = C(E) : dE for a symmetric increment dE [Pa].
  virtual Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const = 0;
  /// S = stress(E) and D = tangent(E) in one call (equal to them to rounding).
  virtual void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const {
    S = stress(E);
    D = tangent(E);
  }
};

/// Wraps a concrete law `Model` as a Law. `Model` provides
///   std::string_view name() const;
///   template <typename T> T energy(const Eigen::Matrix<T,3,3>&) const;
///   Eigen::Matrix3d stress(const Eigen::Matrix3d&) const;
///   Matrix6d tangent(const Eigen::Matrix3d&) const;
///   Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d&, const Eigen::Matrix3d&) const;
/// and optionally void stress_and_tangent(const Eigen::Matrix3d&, Eigen::Matrix3d&, Matrix6d&) const.
template <typename Model>
class LawOf final : public Law {
 public:
  explicit LawOf(Model model) : model_(std::move(model)) {}
  std::string_view name() const override { return model_.name(); }
  double energy(const Eigen::Matrix3d& E) const override { return model_.template energy<double>(E); }
  Eigen::Matrix3d stress(const Eigen::Matrix3d& E) const override { return model_.stress(E); }
  Matrix6d tangent(const Eigen::Matrix3d& E) const override { return model_.tangent(E); }
  Eigen::Matrix3d apply_tangent(const Eigen::Matrix3d& E, const Eigen::Matrix3d& dE) const override {
    return model_.apply_tangent(E, dE);
  }
  void stress_and_tangent(const Eigen::Matrix3d& E, Eigen::Matrix3d& S, Matrix6d& D) const override {
    if constexpr (requires { model_.stress_and_tangent(E, S, D); }) {
      model_.stress_and_tangent(E, S, D);
    } else {
      S = model_.stress(E);
      D = model_.tangent(E);
    }
  }
  /// The concrete law, for callers that need its parameters.
  const Model& model() const { return model_; }

 private:
  Model model_;
};

}  // namespace adamss::materials
