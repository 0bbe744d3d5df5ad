// adamss mesh IMAGE --solid 1 --topology T -o mesh.h5: voxel lattice or CGAL Mesh_3 -> mesh.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "common/units.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"
#include "preprocess/surfaces/cavities.hpp"
#include "preprocess/mesh/cell_fields.hpp"
#include "preprocess/meshers/cgal_mesher.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/meshers/lattice_mesher.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "preprocess/surfaces/node_tags.hpp"
#include "preprocess/fibres/rule_fibres.hpp"

namespace adamss::app {
namespace {

struct MeshArgs {
  std::string image;
  std::vector<int> solid{1};
  std::string topology = "tet6m";
  std::string fiber;
  std::string sheet;
  bool strict = false;
  std::string output;
  std::string vtu;
  bool no_vtu = false;
  std::vector<std::string> cavities;     ///< NAME=LABEL
  std::vector<std::string> tag_planes;   ///< NAME=AXIS:VALUE[:TOL]
  std::vector<std::string> cell_fields;  ///< NAME=FILE[:nearest|:trilinear]
  // --fiber rule (rule-based fibres, preprocess/fibres/rule_fibres.hpp); empty = not given.
  std::string helix_endo, helix_epi, sheet_angle, long_axis;
  // --topology cgal only (empty = default relative to the voxel size).
  std::string cgal_facet_angle;
  std::string cgal_facet_size;
  std::string cgal_facet_distance;
  std::string cgal_cell_ratio;
  std::string cgal_cell_size;
  bool cgal_no_perturb = false;
  bool cgal_no_exude = false;
  bool cgal_lloyd = false;
  bool cgal_odt = false;
  std::string seed;
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// ---- rule-based fibres (--fiber rule): options and the call, kept together.
bool rule_requested(const MeshArgs& a) {
  const bool rule = a.fiber == "rule";
  const bool rule_options =
      !a.helix_endo.empty() || !a.helix_epi.empty() || !a.sheet_angle.empty() || !a.long_axis.empty();
  if (rule_options && !rule)
    throw InputError("--helix-endo/--helix-epi/--sheet-angle/--long-axis apply only with --fiber rule");
  if (rule && !a.sheet.empty()) throw InputError("--sheet: not used with --fiber rule (the rule makes the sheet)");
  return rule;
}

preprocess::RuleFibreOptions rule_options(const MeshArgs& a) {
  preprocess::RuleFibreOptions o;
  auto angle = [](const std::string& text, const std::string& fallback, const char* name) {
    const double v = parse_angle_deg_default(text.empty() ? fallback : text, name);
    if (!(std::abs(v) <= std::numbers::pi / 2 + 1e-12))
      throw InputError(std::string(name) + ": angle must lie in [-90, 90] degrees, got '" + text + "'");
    return v;
  };
  o.helix_endo_rad = angle(a.helix_endo, "60", "--helix-endo");
  o.helix_epi_rad = angle(a.helix_epi, "-60", "--helix-epi");
  o.sheet_angle_rad = angle(a.sheet_angle, "0", "--sheet-angle");
  if (!a.long_axis.empty()) {
    std::stringstream ss(a.long_axis);
    std::string item;
    std::vector<double> v;
    bool ok = true;
    while (ok && std::getline(ss, item, ',')) {
      try {
        std::size_t used = 0;
        v.push_back(std::stod(item, &used));
        ok = item.find_first_not_of(" \t", used) == std::string::npos;
      } catch (const std::exception&) {
        ok = false;
      }
    }
    const Eigen::Vector3d axis = ok && v.size() == 3 ? Eigen::Vector3d(v[0], v[1], v[2]) : Eigen::Vector3d::Zero();
    if (!axis.allFinite() || !(axis.norm() > 0.0))
      throw InputError("--long-axis: '" + a.long_axis + "' is not X,Y,Z (a non-zero direction from apex to base)");
    o.long_axis = axis;
  }
  return o;
}

/// The --cgal-* options (and --seed) as mesher options; InputError naming the option.
preprocess::CgalMeshOptions cgal_options(const MeshArgs& a) {
  preprocess::CgalMeshOptions o;
  o.solid_labels.assign(a.solid.begin(), a.solid.end());
  auto length = [](const std::string& text, const char* what) -> std::optional<double> {
    if (text.empty()) return std::nullopt;
    return common::parse_quantity(text, common::Dimension::Length, what);
  };
  if (!a.cgal_facet_angle.empty()) {
    o.facet_angle_deg = parse_angle_deg_default(a.cgal_facet_angle, "--cgal-facet-angle") * 180.0 / std::numbers::pi;
  }
  o.facet_size_m = length(a.cgal_facet_size, "--cgal-facet-size");
  o.facet_distance_m = length(a.cgal_facet_distance, "--cgal-facet-distance");
  o.cell_size_m = length(a.cgal_cell_size, "--cgal-cell-size");
  if (!a.cgal_cell_ratio.empty()) {
    o.cell_radius_edge_ratio =
        common::parse_quantity(a.cgal_cell_ratio, common::Dimension::Dimensionless, "--cgal-cell-ratio");
  }
  o.perturb = !a.cgal_no_perturb;
  o.exude = !a.cgal_no_exude;
  o.lloyd = a.cgal_lloyd;
  o.odt = a.cgal_odt;
  if (!a.seed.empty()) {
    try {
      std::size_t used = 0;
      const unsigned long long v = std::stoull(a.seed, &used);
      if (used != a.seed.size() || a.seed.front() == '-' || v > 0xffffffffULL) throw std::invalid_argument("bad");
      o.seed = static_cast<std::uint32_t>(v);
    } catch (const std::exception&) {
      throw InputError("--seed: '" + a.seed + "' is not an integer in [0, 4294967295]");
    }
  }
  return o;
}

double assign_rule(preprocess::Mesh& mesh, const preprocess::LabelImage& image, const MeshArgs& a) {
  const preprocess::RuleFibreReport r = preprocess::assign_rule_fibres(mesh, image, rule_options(a));
  const Eigen::Vector3d& l = r.long_axis;
  std::cout << "fibres: rule, " << (r.biv ? "LV + RV" : "one ventricle") << "; faces: " << r.lv_endo_faces
            << " LV endo, " << r.rv_endo_faces << " RV endo, " << r.epi_faces << " epi, " << r.base_faces << " base, "
            << r.other_faces << " other\n"
            << "  long axis (" << l.x() << ", " << l.y() << ", " << l.z() << ") "
            << (r.long_axis_estimated ? "estimated from the valve openings" : "given")
            << (r.biv ? "; RV free wall " + std::to_string(r.rv_elements) + " elements" : "") << "\n"
            << "  Laplace: " << r.solves << " solves, up to " << r.unknowns << " unknowns, " << r.max_iterations
            << " CG iterations, " << r.solve_seconds << " s\n";
  return r.total_seconds;
}
// ---- end of rule-based fibres
/// The first --cgal-* option given on the command line, or "" (for lattice topologies).
std::string first_cgal_option(const MeshArgs& a) {
  const std::pair<bool, const char*> given[] = {{!a.cgal_facet_angle.empty(), "--cgal-facet-angle"},
                                                {!a.cgal_facet_size.empty(), "--cgal-facet-size"},
                                                {!a.cgal_facet_distance.empty(), "--cgal-facet-distance"},
                                                {!a.cgal_cell_ratio.empty(), "--cgal-cell-ratio"},
                                                {!a.cgal_cell_size.empty(), "--cgal-cell-size"},
                                                {a.cgal_no_perturb, "--cgal-no-perturb"},
                                                {a.cgal_no_exude, "--cgal-no-exude"},
                                                {a.cgal_lloyd, "--cgal-lloyd"},
                                                {a.cgal_odt, "--cgal-odt"},
                                                {!a.seed.empty(), "--seed"}};
  for (const auto& [yes, name] : given)
    if (yes) return name;
  return "";
}

void run_mesh(const MeshArgs& a) {
  using namespace preprocess;
  const auto t_start = Clock::now();
  const Topology topo = parse_topology(a.topology);
  if (topo != Topology::Cgal) {
    const std::string opt = first_cgal_option(a);
    if (!opt.empty()) throw InputError(opt + ": only with --topology cgal (got --topology " + a.topology + ")");
  }
  const bool rule = rule_requested(a);
  const CgalMeshOptions cgal_opt = topo == Topology::Cgal ? cgal_options(a) : CgalMeshOptions{};
  if (!rule && a.fiber.empty() != a.sheet.empty()) throw InputError("--fiber and --sheet must be given together");
  require_parent_dir(a.output, "-o");
  const std::string vtu =
      a.no_vtu ? "" : (a.vtu.empty() ? std::filesystem::path(a.output).replace_extension(".vtu").string() : a.vtu);
  if (!vtu.empty()) require_parent_dir(vtu, "--vtu");
  // Option texts are checked before any file is read.
  std::vector<CavitySpec> cavity_specs;
  for (const std::string& c : a.cavities) cavity_specs.push_back(parse_cavity_spec(c, "--cavity"));
  std::vector<TagPlane> planes;
  for (const std::string& p : a.tag_planes) planes.push_back(parse_tag_plane(p, "--tag-plane"));
  std::vector<CellFieldSpec> field_specs;
  for (const std::string& f : a.cell_fields) {
    field_specs.push_back(parse_cell_field_spec(f, "--cell-field"));
    if (!std::filesystem::exists(field_specs.back().file))
      throw InputError("--cell-field " + field_specs.back().name + ": image '" + field_specs.back().file +
                       "' does not exist");
  }

  auto t = Clock::now();
  const LabelImage image = read_label_image(a.image);
  const double t_read = since(t);

  t = Clock::now();
  Mesh mesh;
  std::ostringstream cgal_report;
  std::vector<SurfacePatchFace> cgal_patches;
  if (topo == Topology::Cgal) {
    CgalMeshResult r = mesh_cgal(image, cgal_opt);
    mesh = std::move(r.mesh);
    cgal_patches = r.patches;
    const CgalCriteria& c = r.criteria;
    std::map<std::pair<int, int>, std::size_t> pairs;
    for (const SurfacePatchFace& f : r.patches) ++pairs[{f.label_in, f.label_out}];
    cgal_report << std::setprecision(4) << "  cgal: facet angle " << c.facet_angle_deg << " deg, facet size "
                << c.facet_size_m * 1e3 << " mm, facet distance " << c.facet_distance_m * 1e3
                << " mm, cell radius-edge ratio " << c.cell_radius_edge_ratio << ", cell size " << c.cell_size_m * 1e3
                << " mm (voxel " << c.voxel_size_m * 1e3 << " mm), seed " << cgal_opt.seed << "\n"
                << "  cgal time: refine " << r.refine_seconds << " s"
                << (cgal_opt.odt || cgal_opt.lloyd ? ", smoothing " + std::to_string(r.smooth_seconds) + " s" : "")
                << ", perturb " << r.perturb_seconds << " s (" << r.perturb_attempts << " attempts"
                << (r.perturb_capped ? ", capped" : "") << "), exude " << r.exude_seconds << " s (" << r.initial_points
                << " initial points)\n"
                << "  surface patches (label inside-outside: faces):";
    for (const auto& [pr, n] : pairs) cgal_report << " " << pr.first << "-" << pr.second << ": " << n;
    cgal_report << "\n";
    if (r.inconsistent_patch_faces > 0) {
      cgal_report << "  warning: " << r.inconsistent_patch_faces
                  << " boundary faces had no matching CGAL surface patch (outside label taken from the neighbour)\n";
    }
  } else {
    LatticeMeshOptions opt;
    opt.topology = topo;
    opt.solid_labels.assign(a.solid.begin(), a.solid.end());
    mesh = mesh_lattice(image, opt);
  }
  mesh.attributes["source"] = a.image;
  const double t_mesh = since(t);

  double t_fibre = 0.0;
  if (rule) {
    t_fibre = assign_rule(mesh, image, a);
  } else if (!a.fiber.empty()) {
    t = Clock::now();
    const VectorImage f = read_vector_image(a.fiber);
    const VectorImage s = read_vector_image(a.sheet);
    const FibreReport rep = assign_fibres(mesh, image.grid, f, a.fiber, s, a.sheet, a.strict);
    mesh.attributes["fiber_source"] = a.fiber;
    mesh.attributes["sheet_source"] = a.sheet;
    t_fibre = since(t);
    if (rep.filled_elements > 0) {
      std::cout << "fibres: " << rep.filled_elements
                << " elements had no valid fibre/sheet sample and were filled from neighbours (e.g. element "
                << rep.filled_examples.front() << ")\n";
    }
  }

  // Boundary surfaces: automatic label-pair tags, plane tags, cavities.
  t = Clock::now();
  // CGAL meshes: the mesher's own surface patches know the label beyond each face exactly; the
  // lattice meshes read it from the image next to the face.
  std::vector<BoundaryFace> faces;
  if (topo == Topology::Cgal) {
    for (const SurfacePatchFace& pf : cgal_patches) {
      BoundaryFace f;
      f.nodes = {pf.nodes[0], pf.nodes[1], pf.nodes[2], -1};
      f.element = pf.element;
      f.inside_label = pf.label_in;
      f.outside_label = pf.label_out;
      faces.push_back(f);
    }
  } else {
    faces = boundary_faces_with_labels(mesh, image);
  }
  mesh.node_tags = label_pair_tags(faces);
  for (const TagPlane& p : planes) {
    if (mesh.node_tags.count(p.name) != 0)
      throw InputError("--tag-plane " + p.name + ": a node tag of that name already exists");
    mesh.node_tags[p.name] = nodes_on_plane(mesh, p, "--tag-plane");
  }
  std::vector<CavityBuildInfo> cavity_info;
  if (!cavity_specs.empty()) {
    check_cavity_labels_present(image, cavity_specs);
    add_cavities(mesh, faces, cavity_specs, &cavity_info);
  }
  const double t_surfaces = since(t);

  t = Clock::now();
  std::vector<CellFieldReport> field_reports;
  for (const CellFieldSpec& f : field_specs) {
    const ScalarImage field = read_scalar_image(f.file);
    field_reports.push_back(add_cell_field(mesh, f.name, field, f.method));
    mesh.attributes["cell_field_" + f.name] = f.file + ":" + interpolation_name(f.method);
  }
  const double t_fields = since(t);

  t = Clock::now();
  const QualitySummary q = summarize_quality(mesh);
  const ConformityReport conf = check_conformity(mesh);
  const double t_check = since(t);
  if (q.inverted > 0) throw NumericalError("mesher produced " + std::to_string(q.inverted) + " inverted elements");
  if (conf.overshared_faces > 0) {
    throw NumericalError("mesher produced a non-conforming mesh (" + std::to_string(conf.overshared_faces) +
                         " faces in more than two elements)");
  }
  mesh.attributes["meshing_seconds"] = std::to_string(t_mesh + t_fibre + t_surfaces + t_fields);

  t = Clock::now();
  write_mesh_h5(a.output, mesh);
  if (!vtu.empty()) write_mesh_vtu(vtu, mesh, q.element_volume, q.element_min_dihedral);
  const double t_write = since(t);

  std::cout << std::setprecision(6) << "mesh " << topology_name(topo) << ": " << mesh.node_count() << " nodes, "
            << mesh.element_count() << " " << element_type_name(mesh.type) << " elements, volume " << q.volume_m3 * 1e9
            << " mm^3\n"
            << "  dihedral angle min " << q.min_dihedral_deg << " deg, mean of element minima " << q.mean_dihedral_deg
            << " deg, " << q.below_10_deg << " elements under 10 deg\n"
            << cgal_report.str() << "  boundary: " << conf.boundary_faces << " faces, "
            << (conf.closed_manifold() ? "closed 2-manifold" : "NOT a closed 2-manifold") << " ("
            << conf.nonmanifold_edges << " non-manifold edges, " << conf.nonmanifold_vertices
            << " non-manifold vertices)\n";
  std::cout << "  node tags:";
  for (const auto& [name, nodes] : mesh.node_tags) std::cout << " " << name << " (" << nodes.size() << ")";
  std::cout << "\n";
  for (std::size_t i = 0; i < cavity_specs.size(); ++i) {
    const Cavity& c = mesh.cavities.at(cavity_specs[i].name);
    const CavityBuildInfo& ci = cavity_info[i];
    std::cout << "  cavity " << cavity_specs[i].name << " (label " << cavity_specs[i].label << "): " << ci.wall_faces
              << (c.quads.empty() ? " wall triangles, " : " wall quads, ") << c.lid.size() << " lid triangles ("
              << ci.loops << (ci.loops == 1 ? " opening" : " openings");
    if (ci.loops > 0) std::cout << ", max distance from its plane " << ci.lid_max_deviation_m * 1e3 << " mm";
    std::cout << "), volume " << c.volume_m3 * 1e9 << " mm^3 = " << c.volume_m3 * 1e6 << " ml, "
              << (ci.check.closed_manifold()
                      ? "closed (every edge in two faces)"
                      : "watertight, " + std::to_string(ci.check.nonmanifold_edges) + " edges in more than two faces")
              << "\n";
  }
  for (std::size_t i = 0; i < field_specs.size(); ++i) {
    const CellFieldReport& r = field_reports[i];
    std::cout << "  cell field " << field_specs[i].name << " (" << interpolation_name(field_specs[i].method) << " from "
              << field_specs[i].file << "): min " << r.min << ", max " << r.max;
    if (r.nan_elements > 0) std::cout << ", " << r.nan_elements << " elements NaN (only NaN voxels around them)";
    std::cout << "\n";
  }
  std::cout << "  time: read " << t_read << " s, mesh " << t_mesh << " s, fibres " << t_fibre << " s, surfaces "
            << t_surfaces << " s, cell fields " << t_fields << " s, checks " << t_check << " s, write " << t_write
            << " s, total " << since(t_start) << " s\n"
            << "wrote " << a.output << (vtu.empty() ? "" : " and " + vtu) << "\n";
}

}  // namespace

void add_mesh_command(CLI::App& app) {
  auto args = std::make_shared<MeshArgs>();
  CLI::App* sub = app.add_subcommand(
      "mesh",
      "Mesh the solid labels of a labelled NIfTI image: hex (one hexahedron per voxel), tet5/tet5m "
      "(5 tetrahedra per voxel, alternating so faces match), tet6 (6 per voxel around the main diagonal), "
      "tet6m (6 per voxel, mirrored 2x2x2 kernel), cgal (unstructured tetrahedra from CGAL Mesh_3 on the labelled "
      "image). Writes mesh.h5 and a .vtu for ParaView.");
  sub->add_option("image", args->image, "Labelled image (.nii or .nii.gz)")->required();
  sub->add_option("--solid", args->solid, "Label(s) to mesh, comma separated")->delimiter(',')->capture_default_str();
  sub->add_option("--topology", args->topology, "hex | tet5 | tet5m | tet6 | tet6m | cgal")->capture_default_str();
  sub->add_option("--fiber", args->fiber,
                  "Fibre vector image on the same lattice (interpolated to elements), or 'rule' for rule-based "
                  "fibres from Laplace transmural coordinates");
  sub->add_option("--sheet", args->sheet, "Sheet vector image on the same lattice");
  sub->add_flag("--strict", args->strict, "Reject elements without a valid fibre sample instead of filling them");
  sub->add_option("-o,--output", args->output, "Output mesh.h5")->required();
  sub->add_option("--vtu", args->vtu, "Where to write the .vtu (default: the output name with .vtu)");
  sub->add_flag("--no-vtu", args->no_vtu, "Do not write the .vtu");
  sub->add_option("--cavity", args->cavities,
                  "NAME=LABEL: the closed surface between the solid and image label LABEL (lid over its openings), "
                  "stored as /cavities/NAME with its volume; repeatable (e.g. --cavity lv=2 --cavity rv=3)")
      ->allow_extra_args(false);
  sub->add_option("--tag-plane", args->tag_planes,
                  "NAME=AXIS:VALUE[:TOL]: node tag NAME = nodes with coordinate AXIS (x|y|z) within TOL (default "
                  "1e-3 voxel) of VALUE, e.g. base=z:5mm for the lv/biv phantoms; repeatable")
      ->allow_extra_args(false);
  sub->add_option("--cell-field", args->cell_fields,
                  "NAME=IMAGE[:nearest|:trilinear]: sample a scalar NIfTI at element barycentres into cell data "
                  "NAME (default nearest); repeatable")
      ->allow_extra_args(false);
  sub->add_option("--helix-endo", args->helix_endo,
                  "--fiber rule: helix angle at the endocardium, degrees (default 60)");
  sub->add_option("--helix-epi", args->helix_epi, "--fiber rule: helix angle at the epicardium, degrees (default -60)");
  sub->add_option("--sheet-angle", args->sheet_angle, "--fiber rule: sheet angle about the fibre, degrees (default 0)");
  sub->add_option("--long-axis", args->long_axis,
                  "--fiber rule: X,Y,Z direction from apex to base (default: normal of the valve openings)");
  sub->add_option("--cgal-facet-angle", args->cgal_facet_angle,
                  "cgal: lower bound on surface triangle angles, degrees, in (0, 30] (default 25)");
  sub->add_option("--cgal-facet-size", args->cgal_facet_size,
                  "cgal: upper bound on the surface Delaunay ball radius, a length (default 2 voxels)");
  sub->add_option("--cgal-facet-distance", args->cgal_facet_distance,
                  "cgal: upper bound on the facet-to-surface distance, a length (default half a voxel)");
  sub->add_option("--cgal-cell-ratio", args->cgal_cell_ratio,
                  "cgal: upper bound on the tetrahedron radius-edge ratio, >= 2 (default 3)");
  sub->add_option("--cgal-cell-size", args->cgal_cell_size,
                  "cgal: upper bound on the tetrahedron circumradius, a length (default 2 voxels)");
  sub->add_flag("--cgal-no-perturb", args->cgal_no_perturb, "cgal: skip the sliver perturbation");
  sub->add_flag("--cgal-no-exude", args->cgal_no_exude, "cgal: skip the sliver exudation");
  sub->add_flag("--cgal-lloyd", args->cgal_lloyd, "cgal: Lloyd smoothing before perturbation");
  sub->add_flag("--cgal-odt", args->cgal_odt, "cgal: ODT smoothing before perturbation");
  sub->add_option("--seed", args->seed, "cgal: random seed (default 0); the same seed gives the same mesh");
  sub->callback([args]() { run_mesh(*args); });
}

}  // namespace adamss::app
