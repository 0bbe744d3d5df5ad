#include "solver/scene/scene_materials.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "common/error.hpp"
#include "solver/core/mass.hpp"
#include "solver/scene/scene_terms.hpp"

namespace adamss::solver {

using common::Dimension;

namespace {

/// The elements a material asks for: those whose label is in `labels` and, with a
/// `cell_field: {name: F, min: a, max: b}` entry, whose F_e lies in [a, b] (a scar field
/// splitting the wall into a healthy and a scar material).
struct ElementSelection {
  std::vector<long long> labels;
  const Eigen::VectorXd* field = nullptr;
  double field_min = -INFINITY;
  double field_max = INFINITY;
  std::string where;  ///< key path for messages

  [[nodiscard]] bool contains(const preprocess::Mesh& mesh, std::size_t e) const {
    if (std::find(labels.begin(), labels.end(), mesh.labels[e]) == labels.end()) return false;
    const auto i = static_cast<Eigen::Index>(e);
    return field == nullptr || ((*field)(i) >= field_min && (*field)(i) <= field_max);
  }
};

/// The mesh's cell field `name`; InputError listing the fields it has.
const Eigen::VectorXd& cell_field(const preprocess::Mesh& mesh, const std::string& name, const std::string& where) {
  const auto it = mesh.cell_scalars.find(name);
  if (it != mesh.cell_scalars.end()) return it->second;
  std::string have;
  for (const auto& [k, v] : mesh.cell_scalars) have += (have.empty() ? "" : ", ") + k;
  throw InputError(where + ": the mesh has no cell field '" + name + "' (it has: " +
                   (have.empty() ? std::string("none; add one with adamss mesh --cell-field NAME=IMAGE") : have) + ")");
}

ElementSelection element_selection(SceneNode& m, const preprocess::Mesh& mesh) {
  ElementSelection sel;
  sel.labels = m.integers("labels");
  sel.where = m.at("labels");
  if (auto f = m.optional_map("cell_field")) {
    sel.field = &cell_field(mesh, f->text("name"), f->at("name"));
    sel.field_min = f->quantity("min", Dimension::Dimensionless, -INFINITY);
    sel.field_max = f->quantity("max", Dimension::Dimensionless, INFINITY);
    if (!(sel.field_min <= sel.field_max)) throw InputError(f->path() + ": min must be <= max");
    sel.where = f->path();
    f->finish();
  }
  return sel;
}

/// Which material owns each element, and its density (-1: none yet).
struct ElementOwners {
  std::vector<std::string> name;
  std::vector<double> density;
};

/// The elements of material `m` (sorted), marked as owned in `owners`; InputError when an
/// element already belongs to another material or the material gets none.
std::vector<std::size_t> claim_elements(SceneNode& m, const preprocess::Mesh& mesh, ElementOwners& owners) {
  const std::string name = m.text("name");
  const double rho = m.positive("density", Dimension::Density);
  const ElementSelection sel = element_selection(m, mesh);
  std::vector<std::size_t> elems;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (!sel.contains(mesh, e)) continue;
    if (!owners.name[e].empty()) {
      throw InputError(sel.where + ": element " + std::to_string(e) + " (label " + std::to_string(mesh.labels[e]) +
                       ") already belongs to material '" + owners.name[e] + "'");
    }
    owners.name[e] = name;
    owners.density[e] = rho;
    elems.push_back(e);
  }
  if (elems.empty()) throw InputError(sel.where + ": no element of the mesh carries these labels (and field range)");
  return elems;
}

/// The force terms of material `m` on `elems`; returns its (wave + bulk modulus) / density.
double build_material_terms(SceneNode& m, const std::vector<std::size_t>& elems, LoadedScene& sc) {
  Model& model = sc.model;
  MaterialContext ctx{m.text("name"), *model.mesh, elems, m.positive("density", Dimension::Density), model, 0.0, 0.0,
                      std::nullopt,   nullptr};
  ctx.frame_counter = &sc.axis_frame_elements;
  std::vector<SceneNode> terms = m.list("terms", true);
  if (terms.empty()) throw InputError(m.at("terms") + ": a material needs at least one force term");
  for (SceneNode& t : terms) {
    if (t.yaml().size() != 1)
      throw InputError(t.path() + ": each term is a mapping with one key, the term type (e.g. - volume: {p: 1 kPa})");
    const std::string type = t.yaml().begin()->first.as<std::string>();
    const YAML::Node body = t.yaml().begin()->second;
    SceneNode params(body.IsNull() ? YAML::Node(YAML::NodeType::Map) : body, t.path() + "." + type);
    const std::size_t before = model.terms.size();
    build_material_term(type, params, ctx);
    for (std::size_t k = before; k < model.terms.size(); ++k) {
      sc.term_summary.push_back(model.terms[k]->name() + " [material " + ctx.material +
                                "]: " + model.terms[k]->describe());
    }
  }
  m.finish();
  return (ctx.wave_modulus + ctx.bulk_modulus) / ctx.density;
}

}  // namespace

double load_materials(std::vector<SceneNode> materials, LoadedScene& sc) {
  if (materials.empty()) throw InputError("materials: at least one material is needed");
  const preprocess::Mesh& mesh = *sc.model.mesh;
  ElementOwners owners{std::vector<std::string>(mesh.element_count()), std::vector<double>(mesh.element_count(), -1.0)};
  std::vector<std::pair<SceneNode, std::vector<std::size_t>>> mat_elements;
  std::set<std::string> material_names;
  for (SceneNode& m : materials) {
    const std::string name = m.text("name");
    if (!material_names.insert(name).second)
      throw InputError(m.at("name") + ": a second material named '" + name + "'");
    std::vector<std::size_t> elems = claim_elements(m, mesh, owners);
    mat_elements.emplace_back(m, std::move(elems));
  }
  for (std::size_t e = 0; e < owners.density.size(); ++e) {
    if (owners.density[e] < 0.0) {
      throw InputError("materials: element " + std::to_string(e) + " has label " + std::to_string(mesh.labels[e]) +
                       ", which no material lists (or outside every cell_field range)");
    }
  }
  sc.model.mass = voronoi_masses(mesh, owners.density);
  double max_c2 = 0.0;
  for (auto& [m, elems] : mat_elements) max_c2 = std::max(max_c2, build_material_terms(m, elems, sc));
  return max_c2;
}

}  // namespace adamss::solver
