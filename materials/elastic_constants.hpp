#pragma once
// Isotropic elastic constants: Young's modulus E and Poisson's ratio nu <-> Lame lambda, mu.
//   lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = E / (2 (1 + nu)),   [Pa]
// Valid (positive-definite small-strain energy) when E > 0 and -1 < nu < 1/2, i.e. mu > 0 and
// bulk modulus K = lambda + 2 mu / 3 > 0. nu = 1/2 (incompressible) has no finite lambda.
#include <string_view>

#include "materials/params.hpp"

namespace adamss::materials {

/// Lame parameters [Pa].
struct Lame {
  double lambda = 0.0;
  double mu = 0.0;
};

/// Checks mu > 0 and K = lambda + 2 mu / 3 > 0; throws InputError naming `law`.
inline Lame checked_lame(std::string_view law, double lambda, double mu) {
  check_positive(law, "mu", mu);
  if (!(lambda + 2.0 * mu / 3.0 > 0.0))
    fail_parameter(law, "lambda", "must give a positive bulk modulus lambda + 2 mu/3");
  return {lambda, mu};
}

/// Lame parameters from E [Pa] and nu; throws InputError naming `law` and the parameter.
inline Lame lame_from_young_poisson(std::string_view law, double young, double nu) {
  check_positive(law, "E", young);
  check_open_interval(law, "nu", nu, -1.0, 0.5);
  return {young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), young / (2.0 * (1.0 + nu))};
}

/// Reads either {E, nu} or {lambda, mu} (not a mix) from `reader` and checks them.
Lame read_lame(ParamReader& reader);

}  // namespace adamss::materials
