#include "materials/elastic_constants.hpp"

namespace adamss::materials {

Lame read_lame(ParamReader& reader) {
  const bool young_pair = reader.has("E") || reader.has("nu");
  const bool lame_pair = reader.has("lambda") || reader.has("mu");
  if (young_pair && lame_pair) {
    fail_parameter(reader.law(), reader.has("E") ? "E" : "nu",
                   "cannot be combined with 'lambda'/'mu': give {E, nu} or {lambda, mu}");
  }
  if (lame_pair) {
    const double lambda = reader.required("lambda");
    const double mu = reader.required("mu");
    reader.optional("E", 0.0);  // accepted names, for the error listing
    reader.optional("nu", 0.0);
    return checked_lame(reader.law(), lambda, mu);
  }
  const double young = reader.required("E");
  const double nu = reader.required("nu");
  reader.optional("lambda", 0.0);
  reader.optional("mu", 0.0);
  return lame_from_young_poisson(reader.law(), young, nu);
}

}  // namespace adamss::materials
