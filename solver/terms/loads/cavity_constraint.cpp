#include "solver/terms/loads/cavity_constraint.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "solver/core/scaled_sink.hpp"

namespace adamss::solver {

CavityConstraintTerm::CavityConstraintTerm(const Surface& surface, TimeCourse ratio, const Eigen::Matrix3Xd& x_ref)
    : surface_(surface), ratio_(std::move(ratio)) {
  if (open_edge_count(surface_) != 0) {
    throw InputError("cavity_volume:" + surface_.name + ": the surface is open (" +
                     std::to_string(open_edge_count(surface_)) +
                     " boundary edges); a volume constraint needs a closed cavity with its lid (e.g. mesh "
                     "--cavity or a phantom recipe)");
  }
  closure_ = surface_closure(surface_, static_cast<std::size_t>(x_ref.cols()));
  v0_ = volume(x_ref);
  if (!(v0_ > 0.0)) throw InputError("cavity_volume:" + surface_.name + ": reference volume is not positive");
  unit_ = make_cavity_pressure_term(surface_, TimeCourse::constant(1.0), static_cast<std::size_t>(x_ref.cols()));
}

CavityConstraintTerm::CavityConstraintTerm(const Surface& surface, const CirculationSettings& circulation,
                                           const Eigen::Matrix3Xd& x_ref, const std::string& what)
    : CavityConstraintTerm(surface, TimeCourse::constant(1.0), x_ref) {
  circulation_ = std::make_unique<Circulation>(circulation, v0_, what);
}

CavityCondition CavityConstraintTerm::condition(double t1, double h) const {
  if (circulation_) return circulation_->condition(t1, h);
  CavityCondition c;
  c.volume = target_volume(t1);
  return c;
}

void CavityConstraintTerm::end_step(const StateView& s, double dt) {
  if (circulation_) circulation_->end_step(s.t, dt, volume(s.x), p_);
}

void CavityConstraintTerm::save_state(StateArchive& archive) const {
  archive.put("multiplier", p_);
  archive.put("reference_volume", v0_);
  archive.put_int("has_circulation", circulation_ ? 1 : 0);
  if (circulation_) {
    StateArchive ca = archive.child("circulation");
    circulation_->save_state(ca);
  }
}

void CavityConstraintTerm::load_state(const StateArchive& archive) {
  const bool had = archive.integer("has_circulation") != 0;
  if (had != (circulation_ != nullptr)) {
    throw InputError(archive.source() + ": " + name() + (had ? " had" : " had no") +
                     " circulation when the checkpoint was written (a different scene)");
  }
  // The same mesh gives the same reference volume to the last bit; anything else is another
  // geometry with the same node and element counts.
  const double v0 = archive.scalar("reference_volume");
  if (!(std::abs(v0 - v0_) <= 1e-12 * v0_)) {
    std::ostringstream os;
    os << archive.source() << ": " << name() << " has a reference volume of " << v0 * 1e6
       << " ml in the checkpoint and " << v0_ * 1e6 << " ml in the scene (a checkpoint of a different scene)";
    throw InputError(os.str());
  }
  if (circulation_) circulation_->load_state(archive.child("circulation"));
  p_ = archive.scalar("multiplier");
}

double CavityConstraintTerm::energy(const StateView& /*s*/) const {
  throw std::logic_error("force term '" + name() + "' has no energy");
}

void CavityConstraintTerm::add_forces(const StateView& s, Eigen::Matrix3Xd& f) const {
  if (p_ == 0.0) return;
  unit_scratch_.setZero(3, s.x.cols());
  unit_->add_forces(s, unit_scratch_);
  f += p_ * unit_scratch_;
}

void CavityConstraintTerm::add_jacobian(const StateView& s, JacobianSink& sink) const {
  thread_local std::vector<double> buffer;
  ScaledSink scaled(sink, p_, buffer);
  unit_->add_jacobian(s, scaled);
}

void CavityConstraintTerm::add_volume_gradient(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& g) const {
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, x.cols());
  unit_->add_forces({x, v, 0.0}, g);
}

std::string CavityConstraintTerm::describe() const {
  std::ostringstream os;
  if (circulation_) {
    const auto& w = circulation_->windkessel().parameters();
    os << "circulation (filling / isovolumic / Windkessel ejection), V0 = " << v0_ * 1e6 << " ml, Z_c "
       << w.characteristic_impedance << " R_p " << w.peripheral_resistance << " Pa s/m^3, C " << w.compliance
       << " m^3/Pa";
  } else {
    os << "volume held at r(t) V0, V0 = " << v0_ * 1e6 << " ml, r " << ratio_.describe();
  }
  return os.str();
}

}  // namespace adamss::solver
