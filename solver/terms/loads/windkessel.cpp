#include "solver/terms/loads/windkessel.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace adamss::solver {

Windkessel::Windkessel(const WindkesselParameters& p, const std::string& what) : p_(p), pc_(p.initial_pressure) {
  auto bad = [&](const char* key, double v, const char* rule) {
    std::ostringstream os;
    os << what << "." << key << " must be " << rule << ", got " << v;
    throw InputError(os.str());
  };
  if (!std::isfinite(p.characteristic_impedance) || p.characteristic_impedance < 0.0)
    bad("characteristic_impedance", p.characteristic_impedance, ">= 0 (Pa s/m^3)");
  if (!std::isfinite(p.peripheral_resistance) || !(p.peripheral_resistance > 0.0))
    bad("peripheral_resistance", p.peripheral_resistance, "> 0 (Pa s/m^3)");
  if (!std::isfinite(p.compliance) || !(p.compliance > 0.0)) bad("compliance", p.compliance, "> 0 (m^3/Pa)");
  if (!std::isfinite(p.venous_pressure)) bad("venous_pressure", p.venous_pressure, "finite (Pa)");
  if (!std::isfinite(p.initial_pressure)) bad("initial_pressure", p.initial_pressure, "finite (Pa)");
}

AffinePressure Windkessel::relation(double h) const {
  const double rc = p_.peripheral_resistance * p_.compliance;
  const double den = 1.0 + h / rc;
  return {(pc_ + h * p_.venous_pressure / rc) / den, p_.characteristic_impedance + (h / p_.compliance) / den};
}

double Windkessel::aortic_pressure(double h, double q) const {
  const AffinePressure r = relation(h);
  return r.a + r.b * q;
}

void Windkessel::advance(double h, double q) {
  const double rc = p_.peripheral_resistance * p_.compliance;
  pc_ = (pc_ + h * q / p_.compliance + h * p_.venous_pressure / rc) / (1.0 + h / rc);
}

}  // namespace adamss::solver
