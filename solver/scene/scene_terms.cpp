#include "solver/scene/scene_terms.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

#include "common/error.hpp"
#include "common/suggest.hpp"
#include "materials/factory.hpp"
#include "materials/uncoupled.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "solver/core/penalty_continuation.hpp"
#include "solver/terms/adamss/active_tension.hpp"
#include "solver/terms/adamss/axial_springs.hpp"
#include "solver/terms/adamss/hourglass.hpp"
#include "solver/terms/adamss/material_friction.hpp"
#include "solver/terms/adamss/torsion_springs.hpp"
#include "solver/terms/adamss/virtual_hex.hpp"
#include "solver/terms/adamss/volume_preservation.hpp"
#include "solver/terms/adamss/volume_springs.hpp"
#include "solver/terms/fem/active_stress_gauss.hpp"
#include "solver/terms/fem/fem_element.hpp"
#include "solver/terms/fem/nodal_volume.hpp"
#include "solver/terms/fem/volume_p1disc.hpp"
#include "solver/terms/springs/hybmss.hpp"
#include "solver/terms/springs/lloyd_springs.hpp"
#include "solver/terms/springs/mass_springs.hpp"

namespace adamss::solver {

using common::Dimension;

const AxisFrames& MaterialContext::frames() {
  if (!frames_) {
    frames_ = build_axis_frames(mesh, &elements);
    if (frame_counter != nullptr) *frame_counter += elements.size();
  }
  return *frames_;
}

namespace {

/// Law parameters: stiffness-like names (k.., C, E, lambda, mu, kappa, Holzapfel-Ogden's a, a_f,
/// a_s, a_fs) are pressures, the rest dimensionless. The law factory checks names and ranges.
std::map<std::string, double> law_parameters(SceneNode& node, const std::string& key) {
  std::map<std::string, double> params;
  auto m = node.optional_map(key);
  if (!m) return params;
  for (const auto& kv : m->yaml()) {
    const std::string name = kv.first.as<std::string>();
    const bool pressure = name == "C" || name == "E" || name == "lambda" || name == "mu" || name == "kappa" ||
                          name == "a" || name == "a_f" || name == "a_s" || name == "a_fs" ||
                          (name.size() == 3 && name[0] == 'k' && std::isdigit(static_cast<unsigned char>(name[1])));
    params[name] =
        SceneNode::to_quantity(kv.second, pressure ? Dimension::Pressure : Dimension::Dimensionless, m->at(name));
  }
  return params;
}

/// Modulus of a law for the wave-speed estimate: the largest diagonal entry of the
/// normal block of its tangent at E = 0 (Pa).
double law_modulus(const materials::Law& law) {
  const materials::Matrix6d c = law.tangent(Eigen::Matrix3d::Zero());
  return std::max({c(0, 0), c(1, 1), c(2, 2)});
}

/// law + parameters, wrapped in UncoupledLaw (W(Ebar), no volumetric part) for `uncoupled: true`.
std::shared_ptr<const materials::Law> scene_law(SceneNode& node) {
  const std::string law_name = node.text("law");
  const bool uncoupled = node.flag("uncoupled", false);
  if (uncoupled && law_name.rfind("volumetric_", 0) == 0)
    throw InputError(node.at("uncoupled") + ": a volumetric law has no isochoric part (its uncoupled form is zero)");
  std::shared_ptr<const materials::Law> law;
  try {
    law = materials::make_law(law_name, law_parameters(node, "parameters"));
  } catch (const InputError& e) {
    throw InputError(node.path() + ": " + e.what());
  }
  if (uncoupled) return std::make_shared<materials::UncoupledLaw>(law);
  return law;
}

/// quadrature: axis (the thesis's one F per element from the axis frames) or gauss (the law
/// at the Gauss points of the element's own interpolation; solver/terms/fem/fem_element.hpp).
void build_virtual_hex(SceneNode& node, MaterialContext& ctx) {
  const std::shared_ptr<const materials::Law> law = scene_law(node);
  const bool gauss = node.choice("quadrature", {"axis", "gauss"}, "axis") == "gauss";
  node.finish();
  if (gauss) {
    ctx.model.terms.push_back(make_gauss_point_term(ctx.mesh, law, &ctx.elements, "virtual_hexahedron"));
  } else {
    ctx.model.terms.push_back(make_virtual_hex_term(ctx.mesh, ctx.frames(), law, &ctx.elements));
  }
  ctx.wave_modulus = std::max(ctx.wave_modulus, law_modulus(*law));
}

/// The FEM reference element: the law at the Gauss points (linear tet, trilinear hex).
void build_fem_element(SceneNode& node, MaterialContext& ctx) {
  const std::shared_ptr<const materials::Law> law = scene_law(node);
  node.finish();
  ctx.model.terms.push_back(make_gauss_point_term(ctx.mesh, law, &ctx.elements, "fem_element"));
  ctx.wave_modulus = std::max(ctx.wave_modulus, law_modulus(*law));
}

/// Three per-axis values: a list [fibre, sheet, normal] or one value for all three.
Eigen::Vector3d per_axis(SceneNode& node, const std::string& key, Dimension dim) {
  const YAML::Node& y = node.yaml();
  if (y[key].IsDefined() && y[key].IsSequence()) return node.vector3(key, dim);
  const double v = node.quantity(key, dim);
  return {v, v, v};
}

void build_material_friction(SceneNode& node, MaterialContext& ctx) {
  MaterialFrictionParams p;
  p.scaling = node.choice("scaling", {"virtual", "face"}, "virtual") == "virtual"
                  ? MaterialFrictionParams::Scaling::Virtual
                  : MaterialFrictionParams::Scaling::Face;
  const bool eta = node.has("viscosity"), kd = node.has("k_d");
  if (eta == kd) throw InputError(node.path() + ": give either viscosity: (Pa s) or k_d: (the thesis's N s/m^3)");
  if (eta) {
    p.coefficient = MaterialFrictionParams::Coefficient::Viscosity;
    p.value = per_axis(node, "viscosity", Dimension::Viscosity);
  } else {
    p.coefficient = MaterialFrictionParams::Coefficient::ThesisKd;
    p.value = per_axis(node, "k_d", Dimension::Dimensionless);
  }
  node.finish();
  ctx.model.terms.push_back(make_material_friction_term(ctx.mesh, ctx.frames(), p, &ctx.elements));
}

void build_active_tension(SceneNode& node, MaterialContext& ctx) {
  ActiveTensionParams p;
  const std::string form = node.choice("form", {"stress", "tension", "force"}, "stress");
  p.form = form == "stress"
               ? ActiveTensionParams::Form::Stress
               : (form == "tension" ? ActiveTensionParams::Form::Tension : ActiveTensionParams::Form::Force);
  p.course = node.course("tension", Dimension::Pressure);
  p.sheet_fraction = node.positive("sheet_fraction", Dimension::Dimensionless, 0.0, true);
  p.normal_fraction = node.positive("normal_fraction", Dimension::Dimensionless, 0.0, true);
  p.thesis_half = node.flag("thesis_half", false);
  if (auto d = node.optional_map("delay")) {
    // d_e = distance from `origin` to the element barycentre / speed (activation spreading from a point).
    const Eigen::Vector3d origin = d->vector3("origin", Dimension::Length);
    const double speed = d->positive("speed", Dimension::Velocity);
    const double offset = d->positive("offset", Dimension::Time, 0.0, true);
    d->finish();
    const auto delay_of = [&](std::size_t e) {
      return offset + (preprocess::element_barycentre(ctx.mesh, e) - origin).norm() / speed;
    };
    if (preprocess::is_quadratic(ctx.mesh.type)) {  // per mesh element, at the Gauss points
      p.delay.assign(ctx.mesh.element_count(), 0.0);
      for (const std::size_t e : ctx.elements) p.delay[e] = delay_of(e);
    } else {  // per axis-frame entry
      const AxisFrames& fr = ctx.frames();
      p.delay.resize(fr.size());
      for (std::size_t k = 0; k < fr.size(); ++k) p.delay[k] = delay_of(fr.element[k]);
    }
  }
  node.finish();
  if (preprocess::is_quadratic(ctx.mesh.type)) {
    ctx.model.terms.push_back(make_gauss_active_stress_term(ctx.mesh, p, &ctx.elements));
    return;
  }
  ctx.model.terms.push_back(make_active_tension_term(ctx.mesh, ctx.frames(), p, &ctx.elements));
}

/// distribution: anisotropic / isotropic (element terms, eqs. 2.86-2.106) or nodal (node patches,
/// solver/terms/fem/nodal_volume.hpp); form: the U(J; r) of solver/terms/fem/volume_penalty.hpp.
void build_volume(SceneNode& node, MaterialContext& ctx) {
  VolumeParams p;
  p.p = node.positive("p", Dimension::Pressure);
  p.ratio = node.course("ratio", Dimension::Dimensionless, 1.0);
  const std::string form = node.choice("form", {"quadratic", "log", "simo_taylor"}, "quadratic");
  p.form = form == "quadratic" ? VolumePenaltyForm::Quadratic
                               : (form == "log" ? VolumePenaltyForm::Log : VolumePenaltyForm::SimoTaylor);
  const std::string dist = node.choice("distribution", {"anisotropic", "isotropic", "nodal", "linear"}, "anisotropic");
  // augmented_lagrangian: {tolerance, max_updates} (solver/core/augmented_lagrangian.hpp)
  if (std::optional<SceneNode> al = node.optional_map("augmented_lagrangian")) {
    p.augmented.enabled = true;
    p.augmented.tolerance = al->positive("tolerance", Dimension::Dimensionless, p.augmented.tolerance);
    const long long updates = al->integer("max_updates", p.augmented.max_updates);
    if (updates < 1 || updates > 100000) {
      throw InputError(al->at("max_updates") + ": must be an integer in [1, 100000], got " + std::to_string(updates));
    }
    p.augmented.max_updates = static_cast<int>(updates);
    al->finish();
    check_augmented_lagrangian(p.augmented, node.at("augmented_lagrangian"));
  }
  // continuation: {from, factor} (solver/core/penalty_continuation.hpp): p reached in stages.
  std::optional<ContinuationSettings> continuation;
  if (std::optional<SceneNode> c = node.optional_map("continuation")) {
    ContinuationSettings cs;
    const double from = c->positive("from", Dimension::Pressure);
    cs.start = from / p.p;
    cs.factor = c->positive("factor", Dimension::Dimensionless, cs.factor);
    c->finish();
    if (p.augmented.enabled) {
      throw InputError(node.at("continuation") +
                       ": not together with augmented_lagrangian (the continuation ends on the penalty's answer, the "
                       "multipliers on the incompressible one; choose one)");
    }
    check_continuation(cs, node.at("continuation"));
    continuation = cs;
  }
  // constrain_fixed_nodes (nodal only): false releases the constraints of fully fixed nodes.
  bool constrain_fixed = true;
  if (node.has("constrain_fixed_nodes")) {
    if (dist != "nodal") {
      throw InputError(node.at("constrain_fixed_nodes") +
                       ": only with distribution nodal (the node-patch term); "
                       "distribution is " +
                       dist);
    }
    constrain_fixed = node.flag("constrain_fixed_nodes", true);
  }
  node.finish();
  ctx.bulk_modulus += 2.0 * p.p;  // every form has bulk modulus 2 p
  const auto add = [&](std::unique_ptr<ForceTerm> term) {
    if (continuation) term = std::make_unique<PenaltyContinuation>(std::move(term), *continuation);
    ctx.model.terms.push_back(std::move(term));
  };
  if (dist == "nodal") {
    add(make_nodal_volume_term(ctx.mesh, {{p.form, p.p}, p.ratio, p.augmented, constrain_fixed}, &ctx.elements));
    return;
  }
  if (dist == "linear") {  // Q2-P1disc on hex27 (solver/terms/fem/volume_p1disc.hpp)
    add(make_linear_dilatation_term(ctx.mesh, {p.form, p.p}, p.ratio, &ctx.elements, p.augmented));
    return;
  }
  p.distribution = dist == "anisotropic" ? VolumeDistribution::Anisotropic : VolumeDistribution::Isotropic;
  if (dist == "anisotropic" && preprocess::is_quadratic(ctx.mesh.type)) {  // before the axis frames refuse it
    throw InputError(node.at("distribution") +
                     ": anisotropic (the default) needs the axis frames of linear elements; " +
                     (ctx.mesh.type == preprocess::ElementType::Hex27
                          ? "hex27 takes distribution linear (Q2-P1disc) or isotropic (Q2-P0)"
                          : "tet10 takes distribution nodal (P2-P1) or isotropic (P2-P0)"));
  }
  const AxisFrames* frames = p.distribution == VolumeDistribution::Anisotropic ? &ctx.frames() : nullptr;
  add(make_volume_term(ctx.mesh, frames, p, &ctx.elements));
}

void build_volume_springs(SceneNode& node, MaterialContext& ctx) {
  VolumeSpringParams p;
  const std::string form = node.choice("form", {"auto", "hex", "tet"}, "auto");
  p.form = form == "auto" ? VolumeSpringForm::Auto : (form == "hex" ? VolumeSpringForm::Hex : VolumeSpringForm::Tet);
  p.k_s = node.positive("k_s", Dimension::Stiffness, std::nullopt, true);
  p.k_d = node.positive("k_d", Dimension::Damping, 0.0, true);
  p.adaptive = node.has("mu");
  p.mu = node.positive("mu", Dimension::Dimensionless, 0.0, true);
  node.finish();
  ctx.model.terms.push_back(make_volume_spring_term(ctx.mesh, p, &ctx.elements));
}

/// A polynomial [k1, k2, k3] (1 to 3 entries); Pa for face/virtual scaling, plain SI for none.
SpringPolynomial polynomial(SceneNode& node, const std::string& key, SpringScaling scaling) {
  SpringPolynomial k{0.0, 0.0, 0.0};
  if (!node.has(key)) return k;
  const std::vector<double> v =
      node.quantities(key, scaling == SpringScaling::None ? Dimension::Dimensionless : Dimension::Pressure);
  if (v.empty() || v.size() > 3) throw InputError(node.at(key) + ": give 1 to 3 coefficients [k1, k2, k3]");
  for (std::size_t i = 0; i < v.size(); ++i) k[i] = v[i];
  return k;
}

void build_axial_springs(SceneNode& node, MaterialContext& ctx) {
  AxialSpringParams p;
  if (node.has("set")) {
    node.choice("set", {"table_2_2"});
    p = table_2_2_springs().axial;
  }
  p.scaling = parse_spring_scaling(node.choice("scaling", {"virtual", "face", "none"}, spring_scaling_name(p.scaling)),
                                   node.at("scaling"));
  const char* axes[3] = {"fibre", "sheet", "normal"};
  for (int l = 0; l < 3; ++l)
    if (node.has(axes[l])) p.k[static_cast<std::size_t>(l)] = polynomial(node, axes[l], p.scaling);
  node.finish();
  ctx.model.terms.push_back(make_axial_spring_term(ctx.mesh, ctx.frames(), p, &ctx.elements));
  if (p.scaling != SpringScaling::None)
    ctx.wave_modulus = std::max({ctx.wave_modulus, p.k[0][0], p.k[1][0], p.k[2][0]});
}

void build_torsion_springs(SceneNode& node, MaterialContext& ctx) {
  TorsionSpringParams p;
  if (node.has("set")) {
    node.choice("set", {"table_2_2"});
    p = table_2_2_springs().torsion;
  }
  p.form = parse_torsion_form(node.choice("form", {"cosine", "angle"}, torsion_form_name(p.form)), node.at("form"));
  p.scaling = parse_spring_scaling(node.choice("scaling", {"virtual", "face", "none"}, spring_scaling_name(p.scaling)),
                                   node.at("scaling"));
  const char* pairs[3] = {"fibre_sheet", "fibre_normal", "sheet_normal"};
  for (int q = 0; q < 3; ++q)
    if (node.has(pairs[q])) p.k[static_cast<std::size_t>(q)] = polynomial(node, pairs[q], p.scaling);
  node.finish();
  ctx.model.terms.push_back(make_torsion_spring_term(ctx.mesh, ctx.frames(), p, &ctx.elements));
}

/// Total reference volume of the material's elements (m^3).
double material_volume(const MaterialContext& ctx) {
  double v = 0.0;
  for (const std::size_t e : ctx.elements) v += preprocess::element_volume(ctx.mesh, e);
  return v;
}

/// Adds `springs` as a term of the material and raises its wave modulus to their largest
/// C_iiii (edge_springs.hpp: spring_set_modulus over the material's volume).
void add_edge_springs(EdgeSpringKernel springs, MaterialContext& ctx) {
  auto term = std::make_unique<StencilTerm<EdgeSpringKernel, 2>>(std::move(springs));
  ctx.wave_modulus =
      std::max(ctx.wave_modulus, spring_set_modulus(term->kernel(), ctx.mesh.nodes, material_volume(ctx)));
  ctx.model.terms.push_back(std::move(term));
}

void build_mass_springs(SceneNode& node, MaterialContext& ctx) {
  MassSpringParams p;
  p.stiffness = node.positive("stiffness", Dimension::Stiffness);
  const std::string d = node.choice("diagonals", {"none", "face", "all"}, "none");
  p.diagonals = d == "none" ? SpringDiagonals::None : (d == "face" ? SpringDiagonals::Face : SpringDiagonals::All);
  if (ctx.mesh.type == preprocess::ElementType::Tet4 && p.diagonals != SpringDiagonals::None)
    throw InputError(node.at("diagonals") + ": '" + d + "' needs a hexahedral mesh; tetrahedra have only edges");
  node.finish();
  add_edge_springs(make_mass_spring_kernel(ctx.mesh, p, &ctx.elements), ctx);
}

void build_hybmss(SceneNode& node, MaterialContext& ctx) {
  HybmssParams p;
  p.youngs_modulus = node.positive("youngs_modulus", Dimension::Pressure);
  p.poisson_ratio = node.quantity("poisson_ratio", Dimension::Dimensionless);
  if (!(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5))
    throw InputError(node.at("poisson_ratio") + ": must lie in (-1, 0.5), got " + std::to_string(p.poisson_ratio));
  p.A = node.quantity("A", Dimension::Dimensionless, 1.0);
  if (!(p.A >= 0.0) || !std::isfinite(p.A))
    throw InputError(node.at("A") + ": the ratio k_f/k_c must be >= 0 (0 = HybMSS-FD), got " + std::to_string(p.A));
  node.finish();
  if (ctx.mesh.type != preprocess::ElementType::Hex8)
    throw InputError(node.path() + ": hybmss needs a hexahedral mesh (mesh topology: hex); this mesh has tetrahedra");
  // The terms of make_hybmss_terms, built here so the spring kernel stays typed.
  add_edge_springs(make_hybmss_spring_kernel(ctx.mesh, p, &ctx.elements), ctx);
  HybmssVolumeKernel vol = make_hybmss_volume_kernel(ctx.mesh, p, &ctx.elements);
  if (vol.kappa != 0.0) ctx.model.terms.push_back(std::make_unique<StencilTerm<HybmssVolumeKernel, 8>>(std::move(vol)));
  ctx.bulk_modulus += hybmss_kappa(p.youngs_modulus, p.poisson_ratio);  // P-wave modulus 3G + kappa
}

void build_lloyd_springs(SceneNode& node, MaterialContext& ctx) {
  LloydParams p;
  p.youngs_modulus = node.positive("youngs_modulus", Dimension::Pressure);
  p.volume_force = node.flag("volume_force", false);
  node.finish();
  if (ctx.mesh.type != preprocess::ElementType::Tet4) {
    throw InputError(
        node.path() +
        ": lloyd_springs needs a tetrahedral mesh (a tet topology such as tet6m); this mesh has hexahedra");
  }
  // The terms of make_lloyd_terms, built here so the spring kernel stays typed.
  add_edge_springs(make_lloyd_spring_kernel(ctx.mesh, p, &ctx.elements), ctx);
  if (p.volume_force) {
    VolumeParams vp;
    vp.p = lloyd_volume_penalty(p.youngs_modulus);
    vp.distribution = VolumeDistribution::Isotropic;
    ctx.model.terms.push_back(make_volume_term(ctx.mesh, nullptr, vp, &ctx.elements));
  }
  if (p.volume_force) ctx.bulk_modulus += 2.0 * lloyd_volume_penalty(p.youngs_modulus);
}

/// Hourglass stabilisation of hexahedra (an addition, not in the thesis; solver/terms/adamss/hourglass.hpp).
/// modulus defaults to the modulus the terms listed before it declared (the virtual hexahedron's law).
void build_hourglass(SceneNode& node, MaterialContext& ctx) {
  HourglassParams p;
  p.fraction = node.positive("fraction", Dimension::Dimensionless, 0.05);
  if (node.has("modulus")) {
    p.modulus = node.positive("modulus", Dimension::Pressure);
  } else {
    p.modulus = ctx.wave_modulus;
    if (!(p.modulus > 0.0)) {
      throw InputError(node.path() +
                       ": no material modulus yet: list hourglass after virtual_hexahedron (or axial_springs), or "
                       "give modulus: (Pa)");
    }
  }
  node.finish();
  ctx.model.terms.push_back(make_hourglass_term(ctx.mesh, p, &ctx.elements));
}

using Builder = void (*)(SceneNode&, MaterialContext&);

const std::map<std::string, Builder>& builders() {
  static const std::map<std::string, Builder> kTable{
      {"virtual_hexahedron", build_virtual_hex},
      {"fem_element", build_fem_element},
      {"material_friction", build_material_friction},
      {"active_tension", build_active_tension},
      {"volume", build_volume},
      {"axial_springs", build_axial_springs},
      {"torsion_springs", build_torsion_springs},
      {"volume_springs", build_volume_springs},
      {"mass_springs", build_mass_springs},
      {"hybmss", build_hybmss},
      {"lloyd_springs", build_lloyd_springs},
      {"hourglass", build_hourglass},
  };
  return kTable;
}

}  // namespace

std::vector<std::string> material_term_types() {
  std::vector<std::string> out;
  for (const auto& [name, b] : builders()) out.push_back(name);
  return out;
}

void build_material_term(const std::string& type, SceneNode& node, MaterialContext& ctx) {
  const auto it = builders().find(type);
  if (it == builders().end()) {
    std::string list;
    for (const auto& n : material_term_types()) list += (list.empty() ? "" : ", ") + n;
    throw InputError(node.path() + ": unknown force term '" + type + "'" + did_you_mean(type, material_term_types()) +
                     " (known: " + list + ")");
  }
  // Quadratic elements carry the FEM path only (preprocess/mesh/quadratic.hpp): the spring and
  // axis-frame terms are defined on linear elements.
  if (preprocess::is_quadratic(ctx.mesh.type) && type != "fem_element" && type != "volume" &&
      type != "active_tension") {
    const bool tet = ctx.mesh.type == preprocess::ElementType::Tet10;
    throw InputError(node.path() + ": force term '" + type + "' is not available on quadratic " +
                     (tet ? "tetrahedra (tet10)" : "hexahedra (hex27)") + "; they take fem_element, volume " +
                     (tet ? "(distribution isotropic or nodal)" : "(distribution linear or isotropic)") +
                     " and active_tension (form stress)");
  }
  try {
    it->second(node, ctx);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(node.path(), 0) == 0) throw;  // already names the key path
    throw InputError(node.path() + ": " + msg);
  }
}

}  // namespace adamss::solver
