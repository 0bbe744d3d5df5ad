#include "solver/scene/scene.hpp"

#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iomanip>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "preprocess/surfaces/cavities.hpp"
#include "preprocess/mesh/cell_fields.hpp"
#include "preprocess/meshers/ellipsoid_mesh.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/surfaces/node_tags.hpp"
#include "preprocess/image/phantom.hpp"
#include "solver/terms/loads/gravity.hpp"
#include "solver/core/mass.hpp"
#include "solver/scene/scene_loads.hpp"
#include "solver/scene/scene_terms.hpp"

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

/// FNV-1a, for cache file names.
std::string hash_hex(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (const unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  std::ostringstream os;
  os << std::hex << std::setw(16) << std::setfill('0') << h;
  return os.str();
}

/// mesh: {ellipsoid: land, divisions: [n_v, n_u, n_t], topology: hex|tet, endo: [r_s, r_l],
/// epi: [r_s, r_l], base_z: z}: the structured truncated ellipsoid (preprocess/meshers/ellipsoid_mesh.hpp),
/// built in memory (no cache: it takes milliseconds).
preprocess::Mesh ellipsoid_mesh(SceneNode& node) {
  node.choice("ellipsoid", {"land"});
  preprocess::EllipsoidMeshOptions eo;
  if (node.has("divisions")) {
    const auto d = node.integers("divisions");
    if (d.size() != 3 || d[0] < 3 || d[1] < 2 || d[2] < 1 || *std::max_element(d.begin(), d.end()) > 100000)
      throw InputError(node.at("divisions") +
                       ": expected [n_v, n_u, n_t] element counts (circumferential >= 3, longitudinal >= 2, "
                       "transmural >= 1), e.g. [24, 12, 3]");
    eo.n_v = static_cast<int>(d[0]);
    eo.n_u = static_cast<int>(d[1]);
    eo.n_t = static_cast<int>(d[2]);
  }
  eo.tetrahedra = node.choice("topology", {"hex", "tet"}, "hex") == "tet";
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
  try {
    return preprocess::make_land_ellipsoid(eo);
  } catch (const InputError& e) {
    throw InputError(node.path() + ": " + e.what());
  }
}

/// mesh: {file: ...}, a phantom recipe or an ellipsoid recipe; returns the mesh and the file it
/// came from (for an ellipsoid, a description of the recipe).
preprocess::Mesh load_mesh(SceneNode node, const fs::path& base, const SceneOptions& opt, std::string& source) {
  preprocess::Mesh mesh;
  const bool has_file = node.has("file");
  const bool has_phantom = node.has("phantom");
  const bool has_box = node.has("box");
  const bool has_ellipsoid = node.has("ellipsoid");
  const bool has_cylinder = node.has("cylinder");
  if (static_cast<int>(has_file) + static_cast<int>(has_phantom) + static_cast<int>(has_box) +
          static_cast<int>(has_ellipsoid) + static_cast<int>(has_cylinder) !=
      1)
    throw InputError(node.path() +
                     ": give exactly one of file:, phantom: (a voxel recipe), box: (a structured cuboid), "
                     "cylinder: (a structured cylinder), ellipsoid: (a truncated ellipsoid)");
  if (has_cylinder) {
    const auto rh = node.quantities("cylinder", Dimension::Length);
    if (rh.size() != 2 || !(rh[0] > 0.0) || !(rh[1] > 0.0))
      throw InputError(node.at("cylinder") + ": expected [radius, height], both positive, e.g. [1 cm, 2 cm]");
    const auto div = node.integers("divisions");
    if (div.size() != 3) throw InputError(node.at("divisions") + ": expected three element counts, e.g. [6, 6, 12]");
    const std::string topo = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m"}, "tet6m");
    mesh = preprocess::make_cylinder_mesh(
        rh[0], rh[1], {static_cast<int>(div[0]), static_cast<int>(div[1]), static_cast<int>(div[2])}, topo,
        node.at("cylinder"));
    source = "cylinder " + topo + " (built in memory, " + std::to_string(mesh.element_count()) + " elements)";
  } else if (has_box) {
    const Eigen::Vector3d size = node.vector3("box", Dimension::Length);
    const auto div = node.integers("divisions");
    if (div.size() != 3) throw InputError(node.at("divisions") + ": expected three element counts, e.g. [40, 4, 4]");
    const std::string topo = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m"}, "hex");
    mesh = preprocess::make_box_mesh({size.x(), size.y(), size.z()},
                                     {static_cast<int>(div[0]), static_cast<int>(div[1]), static_cast<int>(div[2])},
                                     topo, node.at("box"));
    source = "box " + topo + " (built in memory, " + std::to_string(mesh.element_count()) + " elements)";
  } else if (has_ellipsoid) {
    mesh = ellipsoid_mesh(node);
    source = "ellipsoid land " + mesh.attributes["topology"] + " (built in memory, " +
             std::to_string(mesh.element_count()) + " elements)";
  } else if (has_file) {
    fs::path p = node.text("file");
    if (p.is_relative()) p = base / p;
    if (!fs::exists(p)) throw InputError(node.at("file") + ": mesh file '" + p.string() + "' does not exist");
    source = p.string();
    mesh = preprocess::read_mesh_h5(p);
  } else {
    const std::string kind = node.choice("phantom", {"lv", "biv", "beam", "slab"});
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
    const std::string topo = node.choice("topology", {"hex", "tet5", "tet5m", "tet6", "tet6m"}, "tet6m");
    // Optional scar segment (lv/biv): the 0/1 cell field `scar` of preprocess::scar_image.
    std::optional<preprocess::ScarCone> scar;
    if (auto sc = node.optional_map("scar")) {
      if (kind != "lv" && kind != "biv")
        throw InputError(sc->path() + ": a scar segment exists only for the lv and biv phantoms");
      preprocess::ScarCone cone;
      cone.direction = sc->vector3("direction", Dimension::Dimensionless, cone.direction);
      cone.half_angle_rad = sc->quantity("angle", Dimension::Angle, cone.half_angle_rad);
      if (!(cone.direction.norm() > 0.0)) throw InputError(sc->at("direction") + ": must not be zero");
      if (!(cone.half_angle_rad > 0.0 && cone.half_angle_rad < std::numbers::pi))
        throw InputError(sc->at("angle") + ": the half-angle must lie in (0, 180) degrees");
      sc->finish();
      scar = cone;
    }
    std::ostringstream key;
    key << std::setprecision(17) << "v2;" << kind << ';' << po.voxel_size_m << ';' << po.helix_endo_rad << ';'
        << po.helix_epi_rad << ';' << po.slab_size[0] << ',' << po.slab_size[1] << ',' << po.slab_size[2] << ';'
        << topo;
    if (scar)
      key << ";scar;" << scar->direction.x() << ',' << scar->direction.y() << ',' << scar->direction.z() << ';'
          << scar->half_angle_rad;
    const fs::path dir = opt.cache_dir.empty() ? default_cache_dir() : opt.cache_dir;
    const fs::path file = dir / ("mesh-" + kind + "-" + topo + "-" + hash_hex(key.str()) + ".h5");
    source = file.string();
    if (fs::exists(file)) {
      mesh = preprocess::read_mesh_h5(file);
    } else {
      std::error_code ec;
      fs::create_directories(dir, ec);
      if (ec) throw InputError("mesh cache folder " + dir.string() + ": " + ec.message() + " (set ADAMSS_CACHE_DIR)");
      const preprocess::Phantom ph = preprocess::make_phantom(kind, po);
      preprocess::LatticeMeshOptions lo;
      lo.topology = preprocess::parse_topology(topo);
      lo.solid_labels = {preprocess::kMyocardium};
      mesh = preprocess::mesh_lattice(ph.image, lo);
      if (ph.fiber && ph.sheet) {
        preprocess::assign_fibres(mesh, ph.image.grid, *ph.fiber, "phantom fibre", *ph.sheet, "phantom sheet", false);
      }
      // Surfaces for scenes: label-pair node tags (surface:1-0, surface:1-2, ...), the cavities
      // of the lv/biv phantoms (lv = label 2, rv = label 3) and the base plane z = 5 mm.
      const std::vector<preprocess::BoundaryFace> faces = preprocess::boundary_faces_with_labels(mesh, ph.image);
      mesh.node_tags = preprocess::label_pair_tags(faces);
      if (kind == "lv" || kind == "biv") {
        std::vector<preprocess::CavitySpec> specs{{"lv", preprocess::kLvCavity}};
        if (kind == "biv") specs.push_back({"rv", preprocess::kRvCavity});
        preprocess::add_cavities(mesh, faces, specs);
        preprocess::TagPlane base_plane{"base", 2, preprocess::kPhantomBaseZ_m, 1e-3 * po.voxel_size_m};
        std::vector<Index> b;
        try {
          b = preprocess::nodes_on_plane(mesh, base_plane, "base");
        } catch (const InputError&) {
          // z = 5 mm is not a voxel face at this voxel size: no base tag.
        }
        if (!b.empty()) mesh.node_tags["base"] = std::move(b);
      }
      if (scar)
        preprocess::add_cell_field(mesh, "scar", preprocess::scar_image(ph.image, *scar),
                                   preprocess::Interpolation::Nearest);
      mesh.attributes["source"] = "phantom " + kind + " (scene recipe)";
      // Several runs (parallel tests) may build the same recipe at once: each writes its own
      // file and renames it into place, so readers only ever see a complete mesh.
      const fs::path part = file.string() + ".part" + std::to_string(::getpid());
      preprocess::write_mesh_h5(part, mesh);
      fs::rename(part, file, ec);
      if (ec)
        throw InputError("mesh cache: cannot rename " + part.string() + " to " + file.string() + ": " + ec.message());
    }
  }
  // Optional uniform fibre frame (slabs and beams have none; verification rotates it).
  if (node.has("fibre")) {
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
  } else if (node.has("sheet")) {
    throw InputError(node.at("sheet") + ": give fibre: together with sheet:");
  }
  node.finish();
  return mesh;
}

/// Shortest element edge (m), for the critical step; collapsed edges (repeated node indices of a
/// degenerate hexahedron) are not edges.
double shortest_edge(const preprocess::Mesh& mesh) {
  static constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  static constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                           {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  double l = std::numeric_limits<double>::infinity();
  const bool tet = mesh.type == preprocess::ElementType::Tet4;
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const preprocess::Index* n = mesh.element(e);
    const int ne = tet ? 6 : 12;
    for (int k = 0; k < ne; ++k) {
      const int a = tet ? kTetEdges[k][0] : kHexEdges[k][0];
      const int b = tet ? kTetEdges[k][1] : kHexEdges[k][1];
      if (n[a] == n[b]) continue;  // a collapsed edge of a degenerate hexahedron
      l = std::min(l, (mesh.nodes.col(n[a]) - mesh.nodes.col(n[b])).norm());
    }
  }
  return l;
}

std::vector<Index> select(SceneNode sel, const Model& model, const fs::path& base) {
  std::vector<Index> nodes;
  int kinds = 0;
  if (sel.has("region")) {
    ++kinds;
    nodes = select_nodes(model.x_ref, sel.region("region"), sel.at("region"));
  }
  if (sel.has("tag")) {
    ++kinds;
    nodes = select_nodes_by_tag(*model.mesh, sel.text("tag"), sel.at("tag"));
  }
  if (sel.has("file")) {
    ++kinds;
    fs::path p = sel.text("file");
    if (p.is_relative()) p = base / p;
    nodes = read_node_file(p.string(), model.node_count(), sel.at("file"));
  }
  if (sel.has("nodes")) {
    ++kinds;
    for (const long long i : sel.integers("nodes")) {
      if (i < 0 || static_cast<std::size_t>(i) >= model.node_count())
        throw InputError(sel.at("nodes") + ": node " + std::to_string(i) + " is outside the mesh");
      nodes.push_back(static_cast<Index>(i));
    }
  }
  if (kinds != 1) throw InputError(sel.path() + ": give exactly one of region, tag, file, nodes");
  sel.finish();
  return nodes;
}

void load_boundary(std::vector<SceneNode> entries, Model& model, const fs::path& base) {
  for (SceneNode& b : entries) {
    const std::vector<Index> nodes = select(b.map("select"), model, base);
    const bool fix = b.has("fix"), ctl = b.has("control");
    if (fix == ctl) throw InputError(b.path() + ": give either fix: (axes) or control: {...}");
    if (fix) {
      const std::uint8_t axes = parse_axes(b.text("fix"), b.at("fix"));
      for (const Index n : nodes) model.constraints.fix(n, axes, b.path());
    } else {
      SceneNode c = b.map("control");
      const std::uint8_t axes = parse_axes(c.text("axis"), c.at("axis"));
      const bool disp = c.has("displacement"), vel = c.has("velocity");
      if (disp == vel) throw InputError(c.path() + ": give either displacement: or velocity: (a time course)");
      const TimeCourse course =
          disp ? c.course("displacement", Dimension::Length) : c.course("velocity", Dimension::Velocity);
      c.finish();
      for (int axis = 0; axis < 3; ++axis) {
        if (((axes >> axis) & 1U) == 0) continue;
        for (const Index n : nodes) model.constraints.control(n, axis, course, vel, b.path());
      }
    }
    model.boundary_groups.push_back({b.path(), nodes});
    b.finish();
  }
}

LoadedScene assemble(const YAML::Node& root_yaml, const fs::path& origin, const SceneOptions& opt) {
  LoadedScene sc;
  sc.file = origin;
  const fs::path base = origin.has_parent_path() ? origin.parent_path() : fs::path(".");
  SceneNode root(root_yaml, "");
  sc.name = root.text("name", origin.stem().string());
  sc.description = root.text("description", "");

  auto mesh = std::make_shared<preprocess::Mesh>(load_mesh(root.map("mesh"), base, opt, sc.mesh_source));
  Model& model = sc.model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.constraints = Constraints(mesh->node_count());

  // ---- materials
  std::vector<SceneNode> mats = root.list("materials", true);
  if (mats.empty()) throw InputError("materials: at least one material is needed");
  std::vector<double> density(mesh->element_count(), -1.0);
  std::vector<std::string> owner(mesh->element_count());
  std::vector<std::pair<SceneNode, std::vector<std::size_t>>> mat_elements;
  double max_c2 = 0.0;
  std::set<std::string> material_names;
  for (SceneNode& m : mats) {
    const std::string name = m.text("name");
    if (!material_names.insert(name).second)
      throw InputError(m.at("name") + ": a second material named '" + name + "'");
    const double rho = m.positive("density", Dimension::Density);
    std::vector<std::size_t> elems;
    std::vector<long long> labels = m.integers("labels");
    // Optional `cell_field: {name: F, min: a, max: b}`: only the elements (of these labels)
    // with a <= F_e <= b (a scar field splitting the wall into a healthy and a scar material).
    const Eigen::VectorXd* field = nullptr;
    double f_min = -INFINITY, f_max = INFINITY;
    std::string where = m.at("labels");
    if (auto f = m.optional_map("cell_field")) {
      const std::string fname = f->text("name");
      const auto it = mesh->cell_scalars.find(fname);
      if (it == mesh->cell_scalars.end()) {
        std::string have;
        for (const auto& [k, v] : mesh->cell_scalars) have += (have.empty() ? "" : ", ") + k;
        throw InputError(f->at("name") + ": the mesh has no cell field '" + fname + "' (it has: " +
                         (have.empty() ? std::string("none; add one with adamss mesh --cell-field NAME=IMAGE") : have) +
                         ")");
      }
      field = &it->second;
      f_min = f->quantity("min", Dimension::Dimensionless, -INFINITY);
      f_max = f->quantity("max", Dimension::Dimensionless, INFINITY);
      if (!(f_min <= f_max)) throw InputError(f->path() + ": min must be <= max");
      where = f->path();
      f->finish();
    }
    for (std::size_t e = 0; e < mesh->element_count(); ++e) {
      if (std::find(labels.begin(), labels.end(), mesh->labels[e]) == labels.end()) continue;
      if (field != nullptr &&
          !((*field)(static_cast<Eigen::Index>(e)) >= f_min && (*field)(static_cast<Eigen::Index>(e)) <= f_max))
        continue;
      if (!owner[e].empty())
        throw InputError(where + ": element " + std::to_string(e) + " (label " + std::to_string(mesh->labels[e]) +
                         ") already belongs to material '" + owner[e] + "'");
      owner[e] = name;
      density[e] = rho;
      elems.push_back(e);
    }
    if (elems.empty()) throw InputError(where + ": no element of the mesh carries these labels (and field range)");
    mat_elements.emplace_back(m, std::move(elems));
  }
  for (std::size_t e = 0; e < density.size(); ++e) {
    if (density[e] < 0.0)
      throw InputError("materials: element " + std::to_string(e) + " has label " + std::to_string(mesh->labels[e]) +
                       ", which no material lists (or outside every cell_field range)");
  }
  model.mass = voronoi_masses(*mesh, density);

  for (auto& [m, elems] : mat_elements) {
    MaterialContext ctx{m.text("name"), *mesh,  elems, m.positive("density", Dimension::Density), model, 0.0, 0.0,
                        std::nullopt,   nullptr};
    ctx.frame_counter = &sc.axis_frame_elements;
    std::vector<SceneNode> terms = m.list("terms", true);
    if (terms.empty()) throw InputError(m.at("terms") + ": a material needs at least one force term");
    for (std::size_t i = 0; i < terms.size(); ++i) {
      SceneNode& t = terms[i];
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
    max_c2 = std::max(max_c2, (ctx.wave_modulus + ctx.bulk_modulus) / ctx.density);
  }

  // ---- loads and initial state
  sc.initial.x = model.x_ref;
  sc.initial.v = Eigen::Matrix3Xd::Zero(3, model.x_ref.cols());
  if (auto loads = root.optional_map("loads")) {
    if (loads->has("gravity")) {
      GravityKernel g{model.mass, loads->vector3("gravity", Dimension::Acceleration)};
      model.terms.push_back(std::make_unique<StencilTerm<GravityKernel, 1>>(std::move(g)));
      sc.term_summary.push_back("gravity: " + std::to_string(model.node_count()) + " particles");
    }
    const std::size_t before = model.terms.size();
    build_loads(*loads, model, base);
    for (std::size_t k = before; k < model.terms.size(); ++k)
      sc.term_summary.push_back(model.terms[k]->name() + ": " + model.terms[k]->describe());
    loads->finish();
  }
  if (root.has("initial_velocity")) {
    const Eigen::Vector3d v0 = root.vector3("initial_velocity", Dimension::Velocity);
    sc.initial.v.colwise() = v0;
  }
  load_boundary(root.list("boundary"), model, base);

  // ---- integrator and run
  SceneNode integ = root.map("integrator");
  RunSettings& run = sc.run;
  run.integrator = integ.choice("type", integrator_names());
  run.dt = integ.positive("dt", Dimension::Time);
  run.abm3.error_min = integ.positive("error_min", Dimension::Length, run.abm3.error_min);
  run.abm3.error_max = integ.positive("error_max", Dimension::Length, run.abm3.error_max);
  run.abm3.dt_min = integ.positive("dt_min", Dimension::Time, std::min(run.abm3.dt_min, run.dt));
  run.abm3.dt_max = integ.positive("dt_max", Dimension::Time, std::max(run.abm3.dt_max, run.dt));
  const bool check_dt = integ.flag("check_dt", true);
  ImplicitSettings& imp = run.implicit;
  imp.dt_min = run.abm3.dt_min;
  imp.dt_max = integ.has("dt_max") ? run.abm3.dt_max : 1e30;  // no upper bound unless given
  imp.max_newton = static_cast<int>(integ.integer("max_newton", imp.max_newton));
  imp.newton_rtol = integ.positive("newton_rtol", Dimension::Dimensionless, imp.newton_rtol);
  imp.newton_atol = integ.positive("newton_atol", Dimension::Force, imp.newton_atol);
  imp.newton_xtol = integ.positive("newton_xtol", Dimension::Length, imp.newton_xtol);
  imp.ksp_rtol = integ.positive("ksp_rtol", Dimension::Dimensionless, imp.ksp_rtol);
  imp.ksp_max_it = static_cast<int>(integ.integer("ksp_max_it", imp.ksp_max_it));
  imp.adapt = integ.flag("adapt", imp.adapt);
  imp.petsc_options = integ.text("petsc_options", "");
  if (imp.max_newton < 1) throw InputError(integ.at("max_newton") + ": must be >= 1");
  if (!(run.abm3.error_min < run.abm3.error_max))
    throw InputError(integ.at("error_min") + ": must be smaller than error_max");
  if (!(run.abm3.dt_min <= run.abm3.dt_max)) throw InputError(integ.at("dt_min") + ": must not exceed dt_max");
  integ.finish();

  SceneNode r = root.map("run");
  run.t_end = r.positive("t_end", Dimension::Time);
  run.ke_threshold = r.has("ke_threshold") ? r.positive("ke_threshold", Dimension::Energy, std::nullopt, true) : -1.0;
  run.ke_after = r.positive("ke_after", Dimension::Time, 0.0, true);
  run.max_steps = static_cast<std::size_t>(std::max(0LL, r.integer("max_steps", 0)));
  const long long ce = r.integer("check_every", 1);
  if (ce < 1) throw InputError(r.at("check_every") + ": must be >= 1");
  run.check_every = static_cast<std::size_t>(ce);
  run.flat_fraction = r.positive("flat_fraction", Dimension::Dimensionless, run.flat_fraction, true);
  r.finish();

  if (auto out = root.optional_map("output")) {
    run.export_interval = out->positive("frame_interval", Dimension::Time, 0.0, true);
    run.globals_interval = out->positive("globals_interval", Dimension::Time, 0.0, true);
    run.checkpoint_interval = out->positive("checkpoint_interval", Dimension::Time, 0.0, true);
    std::set<std::string> probe_names;
    for (SceneNode& p : out->list("probes")) {
      const std::string pname = p.text("name");
      if (!probe_names.insert(pname).second) throw InputError(p.at("name") + ": a second probe named '" + pname + "'");
      const Eigen::Vector3d pt = p.vector3("point", Dimension::Length);
      Eigen::Index best = 0;
      (model.x_ref.colwise() - pt).colwise().squaredNorm().minCoeff(&best);
      model.probes.push_back({pname, static_cast<Index>(best)});
      p.finish();
    }
    out->finish();
  } else {
    run.export_interval = run.t_end / 10.0;
    run.globals_interval = 0.0;
  }
  root.finish();

  // ---- critical step (eq. 2.150): h_c = L / c, c = sqrt(M / rho)
  sc.min_edge_length = shortest_edge(*mesh);
  if (max_c2 > 0.0) {
    sc.wave_speed = std::sqrt(max_c2);
    sc.critical_dt = sc.min_edge_length / sc.wave_speed;
    if (integrator_info(run.integrator).stable_step_limited && run.dt > sc.critical_dt) {
      std::ostringstream os;
      os << "integrator.dt = " << run.dt << " s exceeds the critical step h_c = L/c = " << sc.critical_dt
         << " s (eq. 2.150; shortest edge L = " << sc.min_edge_length << " m, wave speed c = " << sc.wave_speed
         << " m/s estimated from the stiffest material)";
      if (check_dt && run.dt > 10.0 * sc.critical_dt) {
        throw InputError(os.str() +
                         "; more than 10 h_c is certainly unstable for an explicit integrator. Lower dt, "
                         "use abm3, or set integrator.check_dt: false to run anyway");
      }
      sc.warnings.push_back(os.str());
    }
  }
  return sc;
}

}  // namespace

LoadedScene load_scene_text(const std::string& yaml, const fs::path& origin, const SceneOptions& options) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw InputError(origin.string() + ": not valid YAML: " + e.what());
  }
  try {
    return assemble(root, origin, options);
  } catch (const InputError& e) {
    throw InputError(origin.string() + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw InputError(origin.string() + ": " + e.what());
  }
}

LoadedScene load_scene(const fs::path& file, const SceneOptions& options) {
  std::ifstream in(file);
  if (!in) throw InputError("cannot open scene file '" + file.string() + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return load_scene_text(ss.str(), file, options);
}

}  // namespace adamss::solver
