#pragma once
// Run-time selection of a constitutive law by name, as a scene asks for it.
//
// Parameters are SI (Pa for stiffnesses and moduli) and are all checked: an unknown law, an
// unknown or missing parameter, a negative stiffness/exponent, a non-positive pole, a
// pole_fraction outside (0, 1), or nu outside (-1, 0.5) throws adamss::InputError whose message
// names the law and the parameter.
//
//   name                       parameters (required unless marked optional)
//   hunter                     k11 k22 k33 k12 k13 k23 [Pa], a.., b.. (same suffixes),
//                              pole_fraction (optional, 0.95)
//   hunter_canine              all of the above optional; defaults = seed 000 Table 2.1
//   guccione                   C [Pa], b_f, b_t, b_fs
//   guccione_land_problem1/2/3 the same names, optional; defaults = Land et al. 2015 sets
//   holzapfel_ogden            a, a_f, a_s, a_fs [Pa], b, b_f, b_s, b_fs (all >= 0)
//   holzapfel_ogden_2009       the same names, optional; defaults = Holzapfel & Ogden 2009 fit
//   svk, st_venant_kirchhoff   {E [Pa], nu} or {lambda, mu [Pa]}
//   linear_elastic             the same (an alias of svk)
//   neo_hookean                {E, nu} or {lambda, mu}
//   volumetric_quadratic       kappa [Pa]   (U = kappa/2 (J - 1)^2)
//   volumetric_log             kappa [Pa]   (U = kappa/2 (ln J)^2)
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "materials/law.hpp"

namespace adamss::materials {

/// Builds the law `name` from `params`; throws InputError on any bad input (see above).
std::unique_ptr<Law> make_law(const std::string& name, const std::map<std::string, double>& params);

/// Names make_law accepts, in table order.
std::vector<std::string_view> known_laws();

}  // namespace adamss::materials
