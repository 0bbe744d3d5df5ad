#include "solver/scene/scene_image_mesh.hpp"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <optional>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "preprocess/pipeline/mesh_request.hpp"
#include "solver/scene/mesh_cache.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;
using common::Dimension;

namespace {

/// `solid:` as labels (default {1}).
std::vector<std::int32_t> solid_labels(SceneNode& node) {
  if (!node.has("solid")) return {1};
  std::vector<std::int32_t> out;
  for (const long long l : node.integers("solid")) {
    if (l < 1 || l > 1000000)
      throw InputError(node.at("solid") + ": labels are integers >= 1, got " + std::to_string(l));
    out.push_back(static_cast<std::int32_t>(l));
  }
  if (out.empty()) throw InputError(node.at("solid") + ": give at least one label");
  return out;
}

/// `cavities: {lv: 2, rv: 3}` in the order written.
std::vector<preprocess::CavitySpec> cavity_specs(SceneNode& node) {
  std::vector<preprocess::CavitySpec> out;
  auto c = node.optional_map("cavities");
  if (!c) return out;
  for (const auto& kv : c->yaml()) {
    const auto name = kv.first.as<std::string>();
    const long long label = c->integer(name);
    if (label < 1 || label > 1000000)
      throw InputError(c->at(name) + ": a cavity label is an integer >= 1, got " + std::to_string(label));
    if (name.empty() || name.find('/') != std::string::npos)
      throw InputError(c->at(name) + ": a cavity name must be non-empty and without '/'");
    out.push_back({name, static_cast<std::int32_t>(label)});
  }
  c->finish();
  return out;
}

/// `fibres: rule` with its angles; values appended to `key`. NoFibres for `none`.
preprocess::FibreSource fibre_source(SceneNode& node, std::ostringstream& key) {
  const std::string kind = node.choice("fibres", {"none", "rule"}, "none");
  key << ";fibres;" << kind;
  if (kind == "none") {
    for (const char* k : {"helix_endo", "helix_epi", "sheet_angle", "sheet_angle_epi", "helix_endo_rv", "helix_epi_rv",
                          "helix_septum_rv"})
      if (node.has(k)) throw InputError(node.at(k) + ": only with fibres: rule");
    return preprocess::NoFibres{};
  }
  preprocess::RuleFibreOptions o;
  auto angle = [&](const char* k, double fallback) {
    const double v = node.quantity(k, Dimension::Angle, fallback);
    if (!(std::abs(v) <= std::numbers::pi / 2 + 1e-12))
      throw InputError(node.at(k) + ": the angle must lie in [-90, 90] degrees");
    key << ';' << v;
    return v;
  };
  o.helix_endo_rad = angle("helix_endo", o.helix_endo_rad);
  o.helix_epi_rad = angle("helix_epi", o.helix_epi_rad);
  o.sheet_angle_rad = angle("sheet_angle", o.sheet_angle_rad);
  // The per-wall angles of biv meshes and the epicardial sheet angle, each named in the key and
  // only when given (so the cache keys of earlier scenes stay).
  const std::pair<const char*, std::optional<double>*> optional_angles[] = {
      {"helix_endo_rv", &o.rv_helix_endo_rad},
      {"helix_epi_rv", &o.rv_helix_epi_rad},
      {"helix_septum_rv", &o.septum_rv_helix_rad},
      {"sheet_angle_epi", &o.sheet_angle_epi_rad}};
  for (const auto& [name, value] : optional_angles) {
    if (!node.has(name)) continue;
    key << ';' << name;
    *value = angle(name, 0.0);
  }
  return preprocess::RuleFibres{o};
}

}  // namespace

preprocess::CgalMeshOptions cgal_options(SceneNode& node, std::ostringstream& key) {
  preprocess::CgalMeshOptions o;
  key << ";order;rcm";  // CGAL meshes are renumbered for locality (locality_order.hpp): not the earlier files
  auto c = node.optional_map("cgal");
  if (!c) return o;
  if (c->has("facet_angle")) {
    o.facet_angle_deg = c->quantity("facet_angle", Dimension::Angle) * 180.0 / std::numbers::pi;
    if (!(o.facet_angle_deg > 0.0 && o.facet_angle_deg <= 30.0))
      throw InputError(c->at("facet_angle") + ": the facet angle bound must lie in (0, 30] degrees");
  }
  if (c->has("facet_size")) o.facet_size_m = c->positive("facet_size", Dimension::Length);
  if (c->has("facet_distance")) o.facet_distance_m = c->positive("facet_distance", Dimension::Length);
  if (c->has("cell_size")) o.cell_size_m = c->positive("cell_size", Dimension::Length);
  o.cell_radius_edge_ratio = c->quantity("cell_ratio", Dimension::Dimensionless, o.cell_radius_edge_ratio);
  if (!(o.cell_radius_edge_ratio >= 2.0))
    throw InputError(c->at("cell_ratio") + ": the radius-edge ratio bound must be >= 2");
  const long long seed = c->integer("seed", 0);
  if (seed < 0 || seed > 0xffffffffLL) throw InputError(c->at("seed") + ": an integer in [0, 4294967295]");
  o.seed = static_cast<std::uint32_t>(seed);
  const long long min_node = c->integer("min_node_elements", 0);
  if (min_node != 0 && (min_node < 2 || min_node > 4)) {
    throw InputError(c->at("min_node_elements") +
                     ": 2, 3 or 4 (every node in at least that many elements; 3 removes the surface nodes in one or "
                     "two elements), or 0 for none");
  }
  o.min_node_elements = static_cast<int>(min_node);
  c->finish();
  key << ";cgal;" << o.facet_angle_deg << ';' << o.facet_size_m.value_or(-1.0) << ';'
      << o.facet_distance_m.value_or(-1.0) << ';' << o.cell_size_m.value_or(-1.0) << ';' << o.cell_radius_edge_ratio
      << ';' << o.seed;
  if (o.min_node_elements > 0) key << ";min_node_elements;" << o.min_node_elements;  // none: earlier names stay
  return o;
}

preprocess::Mesh image_recipe_mesh(SceneNode& node, const fs::path& base, const SceneOptions& opt,
                                   std::string& source) {
  fs::path image = node.text("image");
  if (image.is_relative()) image = base / image;
  if (!fs::is_regular_file(image))
    throw InputError(node.at("image") + ": label image '" + image.string() + "' does not exist");
  std::ostringstream key;
  key << std::setprecision(17) << "image-v2;" << file_hash_hex(image, node.at("image"));
  preprocess::MeshRequest req;
  req.image = preprocess::ImageFile{image.string(), false};
  req.source = image.string() + " (scene image recipe)";
  req.solid_labels = solid_labels(node);
  for (const auto l : req.solid_labels) key << ";solid;" << l;
  req.cavities = cavity_specs(node);
  for (const auto& c : req.cavities) key << ";cavity;" << c.name << '=' << c.label;
  const std::string topo = node.choice("topology", {"cgal", "hex", "tet5", "tet5m", "tet6", "tet6m"}, "cgal");
  req.topology = preprocess::parse_topology(topo);
  key << ";topology;" << topo;
  if (req.topology == preprocess::Topology::Cgal) {
    req.cgal = cgal_options(node, key);
  } else if (node.has("cgal")) {
    throw InputError(node.at("cgal") + ": only with topology: cgal (got topology: " + topo + ")");
  }
  req.fibres = fibre_source(node, key);
  if (node.has("resample")) {
    req.resample_m = node.positive("resample", Dimension::Length);
    key << ";resample;" << req.resample_m;  // (no key without it: the earlier cache names stay valid)
  }
  if (node.has("smooth")) {
    req.smooth_m = node.positive("smooth", Dimension::Length);
    key << ";smooth;" << req.smooth_m;
  }
  if (node.has("clean")) {
    req.clean_labels = node.flag("clean", false);
    if (req.clean_labels) key << ";clean";
  }
  req.check = true;
  const std::string stem = image.filename().string().substr(0, image.filename().string().find('.'));
  try {
    return cached_mesh(req, opt, "mesh-image-" + stem + "-" + topo + "-" + hash_hex(key.str()) + ".h5", source);
  } catch (const InputError& e) {
    throw InputError(node.at("image") + ": " + e.what());
  }
}

}  // namespace adamss::solver
