#pragma once
// The builders that turn one entry of a material's `terms:` list (or of `loads:`) into
// force terms. One function per term type; each reads its keys through SceneNode (which
// is the schema) and adds to the model. See docs/scene-reference.md.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/model.hpp"
#include "solver/geometry/axis_frame.hpp"
#include "solver/scene/scene_node.hpp"

namespace adamss::solver {

/// What a material-term builder sees.
struct MaterialContext {
  std::string material;  ///< material name
  const preprocess::Mesh& mesh;
  const std::vector<std::size_t>& elements;  ///< the material's elements (mesh indices, sorted)
  double density = 0.0;                      ///< kg/m^3
  Model& model;
  /// The material's axis frames (entries in `elements` order), built on first use.
  const AxisFrames& frames();
  /// Largest stiffness modulus (Pa) the material's deviatoric/spring terms declare, and the sum of the
  /// bulk moduli of its volume terms; their sum estimates the P-wave modulus for the critical step
  /// (eq. 2.150).
  double wave_modulus = 0.0;
  double bulk_modulus = 0.0;
  std::optional<AxisFrames> frames_;
  std::size_t* frame_counter = nullptr;
};

/// Names of the material term types (for messages and the reference).
std::vector<std::string> material_term_types();

/// Builds the material term `type` from `node` (its mapping) into ctx.model.terms.
/// InputError for an unknown type (listing the known ones).
void build_material_term(const std::string& type, SceneNode& node, MaterialContext& ctx);

}  // namespace adamss::solver
