#include "solver/scene_terms.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include "common/error.hpp"
#include "materials/factory.hpp"
#include "solver/virtual_hex.hpp"

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

/// Law parameters: stiffness-like names (k.., C, E, lambda, mu, kappa) are pressures, the rest
/// dimensionless. The law factory checks names and ranges.
std::map<std::string, double> law_parameters(SceneNode& node, const std::string& key) {
  std::map<std::string, double> params;
  auto m = node.optional_map(key);
  if (!m) return params;
  for (const auto& kv : m->yaml()) {
    const std::string name = kv.first.as<std::string>();
    const bool pressure = name == "C" || name == "E" || name == "lambda" || name == "mu" || name == "kappa" ||
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

void build_virtual_hex(SceneNode& node, MaterialContext& ctx) {
  const std::string law_name = node.text("law");
  std::shared_ptr<const materials::Law> law;
  try {
    law = materials::make_law(law_name, law_parameters(node, "parameters"));
  } catch (const InputError& e) {
    throw InputError(node.path() + ": " + e.what());
  }
  node.finish();
  ctx.model.terms.push_back(make_virtual_hex_term(ctx.mesh, ctx.frames(), law));
  ctx.wave_modulus = std::max(ctx.wave_modulus, law_modulus(*law));
}

using Builder = void (*)(SceneNode&, MaterialContext&);

const std::map<std::string, Builder>& builders() {
  static const std::map<std::string, Builder> table{
      {"virtual_hexahedron", build_virtual_hex},
  };
  return table;
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
    throw InputError(node.path() + ": unknown force term '" + type + "' (known: " + list + ")");
  }
  it->second(node, ctx);
}

}  // namespace adamss::solver
