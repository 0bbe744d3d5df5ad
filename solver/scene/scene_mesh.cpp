#include "solver/scene/scene_mesh.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <numbers>
#include <optional>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/quadratic.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "preprocess/pipeline/mesh_pipeline.hpp"
#include "solver/core/model.hpp"
#include "solver/scene/mesh_cache.hpp"
#include "solver/scene/scene_image_mesh.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;
using common::Dimension;

fs::path default_cache_dir() {
  if (const char* d = std::getenv("ADAMSS_CACHE_DIR"); d != nullptr && *d != '\0') return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d != nullptr && *d != '\0') return fs::path(d) / "adamss";
  if (const char* d = std::getenv("HOME"); d != nullptr && *d != '\0') return fs::path(d) / ".cache" / "adamss";
  return "/tmp/adamss-cache";
}

namespace {

/// The three element counts of `divisions`; `example` is shown in the error.
std::array<int, 3> divisions3(SceneNode& node, const char* example) {
  const auto div = node.integers("divisions");
  if (div.size() != 3)
    throw InputError(node.at("divisions") + ": expected three element counts, e.g. " + std::string(example));
  return {static_cast<int>(div[0]), static_cast<int>(div[1]), static_cast<int>(div[2])};
}

/// mesh: {cylinder: [radius, height], divisions: [...], topology: ...}, built in memory.
preprocess::Mesh cylinder_mesh(SceneNode& node, std::string& source) {
  const auto rh = node.quantities("cylinder", Dimension::Length);
  if (rh.size() != 2 || !(rh[0] > 0.0) || !(rh[1] > 0.0))
    throw InputError(node.at("cylinder") + ": expected [radius, height], both positive, e.g. [1 cm, 2 cm]");
  const std::array<int, 3> div = divisions3(node, "[6, 6, 12]");
  const std::string topo = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m"}, "tet6m");
  preprocess::Mesh mesh = preprocess::make_cylinder_mesh(rh[0], rh[1], div, topo, node.at("cylinder"));
  source = "cylinder " + topo + " (built in memory, " + std::to_string(mesh.element_count()) + " elements)";
  return mesh;
}

/// mesh: {box: [x, y, z], divisions: [...], topology: ...}, built in memory.
preprocess::Mesh box_mesh(SceneNode& node, std::string& source) {
  const Eigen::Vector3d size = node.vector3("box", Dimension::Length);
  const std::array<int, 3> div = divisions3(node, "[40, 4, 4]");
  const std::string topo = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m"}, "hex");
  preprocess::Mesh mesh = preprocess::make_box_mesh({size.x(), size.y(), size.z()}, div, topo, node.at("box"));
  source = "box " + topo + " (built in memory, " + std::to_string(mesh.element_count()) + " elements)";
  return mesh;
}

/// The optional `order: 1 | 2` of a mesh (2: quadratic tetrahedra or hexahedra,
/// preprocess/mesh/quadratic.hpp).
int mesh_order(SceneNode& node) {
  const long long order = node.integer("order", 1);
  if (order != 1 && order != 2) {
    throw InputError(node.at("order") +
                     ": the element order must be 1 (linear) or 2 (quadratic: tet10 from tetrahedra, hex27 from "
                     "hexahedra)");
  }
  return static_cast<int>(order);
}

/// mesh: {ellipsoid: land, divisions: [n_v, n_u, n_t], topology: hex|tet, endo: [r_s, r_l],
/// epi: [r_s, r_l], base_z: z, helix_endo: a, helix_epi: a}: the structured truncated ellipsoid
/// (preprocess/meshers/ellipsoid_mesh.hpp), built in memory (no cache: it takes milliseconds).
preprocess::Mesh ellipsoid_mesh(SceneNode& node, std::string& source) {
  node.choice("ellipsoid", {"land"});
  preprocess::EllipsoidMeshOptions eo;
  if (node.has("divisions")) {
    const auto d = node.integers("divisions");
    if (d.size() != 3 || d[0] < 3 || d[1] < 2 || d[2] < 1 || *std::max_element(d.begin(), d.end()) > 100000) {
      throw InputError(node.at("divisions") +
                       ": expected [n_v, n_u, n_t] element counts (circumferential >= 3, longitudinal >= 2, "
                       "transmural >= 1), e.g. [24, 12, 3]");
    }
    eo.n_v = static_cast<int>(d[0]);
    eo.n_u = static_cast<int>(d[1]);
    eo.n_t = static_cast<int>(d[2]);
  }
  eo.tetrahedra = node.choice("topology", {"hex", "tet"}, "hex") == "tet";
  eo.order = mesh_order(node);
  auto radii = [&](const char* key, double& r_s, double& r_l) {
    if (!node.has(key)) return;
    const std::vector<double> r = node.quantities(key, Dimension::Length);
    if (r.size() != 2 || !(r[0] > 0.0) || !(r[1] > 0.0))
      throw InputError(node.at(key) + ": expected two positive lengths [r_s, r_l], e.g. [7 mm, 17 mm]");
    r_s = r[0];
    r_l = r[1];
  };
  radii("endo", eo.endo_r_s, eo.endo_r_l);
  radii("epi", eo.epi_r_s, eo.epi_r_l);
  eo.base_z = node.quantity("base_z", Dimension::Length, eo.base_z);
  eo.helix_endo_rad = node.quantity("helix_endo", Dimension::Angle, eo.helix_endo_rad);
  eo.helix_epi_rad = node.quantity("helix_epi", Dimension::Angle, eo.helix_epi_rad);
  preprocess::Mesh mesh;
  try {
    mesh = preprocess::make_land_ellipsoid(eo);
  } catch (const InputError& e) {
    throw InputError(node.path() + ": " + e.what());
  }
  source = "ellipsoid land " + mesh.attributes["topology"] + " (built in memory, " +
           std::to_string(mesh.element_count()) + " " + preprocess::element_type_name(mesh.type) + " elements)";
  return mesh;
}

/// mesh: {file: mesh.h5, grid.vtu or gmsh.msh}, relative to the scene's folder.
preprocess::Mesh file_mesh(SceneNode& node, const fs::path& base, std::string& source) {
  fs::path p = node.text("file");
  if (p.is_relative()) p = base / p;
  if (!fs::exists(p)) throw InputError(node.at("file") + ": mesh file '" + p.string() + "' does not exist");
  source = p.string();
  return preprocess::read_mesh_file(p);
}

/// A phantom recipe's keys: what to mesh, and the text that names its cache file.
struct PhantomRecipe {
  preprocess::MeshRequest request;
  std::string kind;
  std::string topology;
  std::string key;  ///< every parameter, for the cache file's hash
};

/// Optional `scar: {direction: [...], angle: A}` (lv/biv): a cone of scar elements.
std::optional<preprocess::ScarCone> scar_cone(SceneNode& node, const std::string& kind) {
  auto sc = node.optional_map("scar");
  if (!sc) return std::nullopt;
  if (kind != "lv" && kind != "biv")
    throw InputError(sc->path() + ": a scar segment exists only for the lv and biv phantoms");
  preprocess::ScarCone cone;
  cone.direction = sc->vector3("direction", Dimension::Dimensionless, cone.direction);
  cone.half_angle_rad = sc->quantity("angle", Dimension::Angle, cone.half_angle_rad);
  if (!(cone.direction.norm() > 0.0)) throw InputError(sc->at("direction") + ": must not be zero");
  if (!(cone.half_angle_rad > 0.0 && cone.half_angle_rad < std::numbers::pi))
    throw InputError(sc->at("angle") + ": the half-angle must lie in (0, 180) degrees");
  sc->finish();
  return cone;
}

/// The pipeline request of a phantom recipe: the phantom's labels meshed with its analytic
/// fibres, label-pair node tags; for lv/biv also the cavities (lv = label 2, rv = label 3) and
/// the base plane z = 5 mm (no tag when that is not a voxel face); the scar cell field.
preprocess::MeshRequest phantom_request(const std::string& kind, const preprocess::PhantomOptions& po,
                                        const std::string& topo, const std::optional<preprocess::ScarCone>& scar) {
  preprocess::MeshRequest req;
  req.image = preprocess::PhantomImage{kind, po};
  req.source = "phantom " + kind + " (scene recipe)";
  req.solid_labels = {preprocess::kMyocardium};
  req.topology = preprocess::parse_topology(topo);
  req.fibres = preprocess::PhantomFibres{};
  if (kind == "lv" || kind == "biv") {
    req.cavities.push_back({"lv", preprocess::kLvCavity});
    if (kind == "biv") req.cavities.push_back({"rv", preprocess::kRvCavity});
    // Only when z = 5 mm is a voxel face: otherwise the phantom's top lies above it and CGAL would
    // find a few wall nodes near the plane (0.75 mm voxels: 11 nodes 0.26 mm below the top). The
    // lattice puts the base nodes on that face exactly; CGAL's surface points lie within about
    // 0.04 voxel of it (0.25 mm voxels, facet distance 0.2 mm: 95 nodes within 10 um, 103 within
    // 25 um, 121 within 100 um), so 0.1 voxel takes the base face and, at most, the first wall
    // nodes just below its rim.
    const double faces = preprocess::kPhantomBaseZ / po.voxel_size_m;
    if (std::abs(faces - std::round(faces)) <= 1e-9 * faces) {
      const double tolerance = (topo == "cgal" ? 0.1 : 1e-3) * po.voxel_size_m;
      req.tag_planes.push_back({{"base", 2, preprocess::kPhantomBaseZ, tolerance}, true});
    }
  }
  req.scar = scar;
  return req;
}

/// mesh: {phantom: lv|biv|beam|slab, voxel_size, helix_endo, helix_epi, slab_size, topology, scar}.
PhantomRecipe phantom_recipe(SceneNode& node) {
  PhantomRecipe r;
  r.kind = node.choice("phantom", {"lv", "biv", "beam", "slab"});
  preprocess::PhantomOptions po;
  po.voxel_size_m = node.positive("voxel_size", Dimension::Length, 1e-3);
  po.helix_endo_rad = node.quantity("helix_endo", Dimension::Angle, po.helix_endo_rad);
  po.helix_epi_rad = node.quantity("helix_epi", Dimension::Angle, po.helix_epi_rad);
  if (node.has("slab_size")) {
    const auto s = node.integers("slab_size");
    if (s.size() != 3 || *std::min_element(s.begin(), s.end()) < 1)
      throw InputError(node.at("slab_size") + ": expected three voxel counts >= 1, e.g. [4, 4, 8]");
    po.slab_size = {s[0], s[1], s[2]};
  }
  r.topology = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m", "cgal"}, "tet6m");
  const std::optional<preprocess::ScarCone> scar = scar_cone(node, r.kind);
  std::ostringstream key;
  key << std::setprecision(17) << "v3;" << r.kind << ';' << po.voxel_size_m << ';' << po.helix_endo_rad << ';'
      << po.helix_epi_rad << ';' << po.slab_size[0] << ',' << po.slab_size[1] << ',' << po.slab_size[2] << ';'
      << r.topology;
  if (scar) {
    key << ";scar;" << scar->direction.x() << ',' << scar->direction.y() << ',' << scar->direction.z() << ';'
        << scar->half_angle_rad;
  }
  preprocess::CgalMeshOptions cgal;
  if (r.topology == "cgal") {
    cgal = cgal_options(node, key);
  } else if (node.has("cgal")) {
    throw InputError(node.at("cgal") + ": only with topology: cgal (got topology: " + r.topology + ")");
  }
  r.key = key.str();
  r.request = phantom_request(r.kind, po, r.topology, scar);
  r.request.cgal = cgal;
  return r;
}

/// A phantom recipe's mesh: read from the cache when it was built before, else built and cached.
preprocess::Mesh phantom_mesh(SceneNode& node, const SceneOptions& opt, std::string& source) {
  const PhantomRecipe r = phantom_recipe(node);
  return cached_mesh(r.request, opt, "mesh-" + r.kind + "-" + r.topology + "-" + hash_hex(r.key) + ".h5", source);
}

/// Optional uniform fibre frame `fibre: [...], sheet: [...]` (slabs and beams have none;
/// verification rotates it): the sheet is made orthogonal to the fibre, both unit.
void uniform_fibre_frame(SceneNode& node, preprocess::Mesh& mesh) {
  if (!node.has("fibre")) {
    if (node.has("sheet")) throw InputError(node.at("sheet") + ": give fibre: together with sheet:");
    return;
  }
  Eigen::Vector3d f = node.vector3("fibre", Dimension::Dimensionless);
  Eigen::Vector3d s = node.vector3("sheet", Dimension::Dimensionless);
  if (!(f.norm() > 0.0)) throw InputError(node.at("fibre") + ": the fibre direction must not be zero");
  f.normalize();
  s -= s.dot(f) * f;
  if (!(s.norm() > 1e-6))
    throw InputError(node.at("sheet") + ": the sheet direction must not be parallel to the fibre");
  s.normalize();
  const Eigen::Vector3d n = f.cross(s);
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  mesh.fiber = f.replicate(1, ne);
  mesh.sheet = s.replicate(1, ne);
  mesh.normal = n.replicate(1, ne);
}

/// mesh: {..., reference: unloaded_mesh.h5}: the file named (relative to the scene's folder), or
/// the options' reference_file (`adamss run --reference`), if either is given.
std::optional<fs::path> reference_file(SceneNode& node, const fs::path& base, const SceneOptions& opt) {
  if (!opt.reference_file.empty()) {
    if (node.has("reference")) {
      throw InputError(node.at("reference") + ": the scene names a reference configuration and --reference gives " +
                       "another ('" + opt.reference_file.string() + "'): give one");
    }
    if (!fs::exists(opt.reference_file)) {
      throw InputError("--reference: mesh file '" + opt.reference_file.string() + "' does not exist");
    }
    return opt.reference_file;
  }
  if (!node.has("reference")) return std::nullopt;
  fs::path p = node.text("reference");
  if (p.is_relative()) p = base / p;
  if (!fs::exists(p)) throw InputError(node.at("reference") + ": mesh file '" + p.string() + "' does not exist");
  return p;
}

/// The node positions of the mesh file `file` (same elements as `mesh`, in the same order) in
/// place of the mesh's own.
void take_reference(preprocess::Mesh& mesh, const fs::path& file, const std::string& what) {
  const preprocess::Mesh ref = preprocess::read_mesh_file(file);
  if (ref.type != mesh.type || ref.connectivity != mesh.connectivity) {
    throw InputError(what + ": '" + file.string() + "' has other elements (" + std::to_string(ref.element_count()) +
                     " " + preprocess::element_type_name(ref.type) + ") than the scene's mesh (" +
                     std::to_string(mesh.element_count()) + " " + preprocess::element_type_name(mesh.type) +
                     "): a reference configuration must come from this mesh (adamss unload)");
  }
  replace_node_positions(mesh, ref.nodes, what);
}

}  // namespace

void replace_node_positions(preprocess::Mesh& mesh, const Eigen::Matrix3Xd& nodes, const std::string& what) {
  if (nodes.cols() != mesh.nodes.cols()) {
    throw InputError(what + ": " + std::to_string(nodes.cols()) + " node positions for a mesh of " +
                     std::to_string(mesh.nodes.cols()) + " nodes");
  }
  if (!nodes.allFinite()) throw InputError(what + ": a node position is not finite");
  if (const auto e = first_inverted_element(mesh, nodes)) {
    throw InputError(what + ": element " + std::to_string(*e) + " is inverted or flat at the given node positions");
  }
  mesh.nodes = nodes;
}

preprocess::Mesh load_scene_mesh(SceneNode node, const fs::path& base, const SceneOptions& opt, std::string& source,
                                 fs::path& reference_used) {
  const bool has_file = node.has("file");
  const bool has_phantom = node.has("phantom");
  const bool has_box = node.has("box");
  const bool has_ellipsoid = node.has("ellipsoid");
  const bool has_cylinder = node.has("cylinder");
  const bool has_image = node.has("image");
  if (int(has_file) + int(has_phantom) + int(has_box) + int(has_ellipsoid) + int(has_cylinder) + int(has_image) != 1) {
    throw InputError(node.path() +
                     ": give exactly one of file:, image: (a label image meshed by the scene), phantom: (a voxel "
                     "recipe), box: (a structured cuboid), cylinder: (a structured cylinder), ellipsoid: (a "
                     "truncated ellipsoid)");
  }
  preprocess::Mesh mesh;
  if (has_image) {
    mesh = image_recipe_mesh(node, base, opt, source);
  } else if (has_cylinder) {
    mesh = cylinder_mesh(node, source);
  } else if (has_box) {
    mesh = box_mesh(node, source);
  } else if (has_ellipsoid) {
    mesh = ellipsoid_mesh(node, source);
  } else if (has_file) {
    mesh = file_mesh(node, base, source);
  } else {
    mesh = phantom_mesh(node, opt, source);
  }
  uniform_fibre_frame(node, mesh);
  const std::optional<fs::path> reference = reference_file(node, base, opt);
  // order 2: the ellipsoid recipe places its added nodes on the curved map itself; every other
  // mesh of linear elements gets straight ones after its fibres and tags are set.
  if (!has_ellipsoid && mesh_order(node) == 2) {
    if (mesh.type == preprocess::ElementType::Tet4) {
      mesh = preprocess::make_quadratic(mesh);
      source += ", raised to quadratic tetrahedra (tet10)";
    } else if (mesh.type == preprocess::ElementType::Hex8) {
      mesh = preprocess::make_quadratic_hex(mesh);
      source += ", raised to triquadratic hexahedra (hex27)";
    } else {
      throw InputError(node.at("order") + ": order 2 needs a mesh of linear elements (tet4 or hex8), this one has " +
                       preprocess::element_type_name(mesh.type) + " elements");
    }
  }
  if (reference) {
    take_reference(mesh, *reference, opt.reference_file.empty() ? node.at("reference") : "--reference");
    reference_used = *reference;
  }
  node.finish();
  return mesh;
}

}  // namespace adamss::solver
