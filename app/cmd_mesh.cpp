// adamss mesh IMAGE --solid 1 --topology T -o mesh.h5: voxel lattice -> mesh.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "preprocess/boundary_labels.hpp"
#include "preprocess/cavities.hpp"
#include "preprocess/cell_fields.hpp"
#include "preprocess/fibre_field.hpp"
#include "preprocess/lattice_mesher.hpp"
#include "preprocess/mesh_io.hpp"
#include "preprocess/mesh_quality.hpp"
#include "preprocess/nifti_io.hpp"
#include "preprocess/node_tags.hpp"
#include "preprocess/rule_fibres.hpp"

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
  // --fiber rule (rule-based fibres, preprocess/rule_fibres.hpp); empty = not given.
  std::string helix_endo, helix_epi, sheet_angle, long_axis;
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

void run_mesh(const MeshArgs& a) {
  using namespace preprocess;
  const auto t_start = Clock::now();
  const Topology topo = parse_topology(a.topology);
  if (topo == Topology::Cgal) {
    throw InputError("--topology cgal: the CGAL Mesh_3 mesher is not built yet (use hex, tet5, tet5m, tet6, tet6m)");
  }
  const bool rule = rule_requested(a);
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
  LatticeMeshOptions opt;
  opt.topology = topo;
  opt.solid_labels.assign(a.solid.begin(), a.solid.end());
  Mesh mesh = mesh_lattice(image, opt);
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
  const std::vector<BoundaryFace> faces = boundary_faces_with_labels(mesh, image);
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
            << " deg\n"
            << "  boundary: " << conf.boundary_faces << " faces, "
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
      "tet6m (6 per voxel, mirrored 2x2x2 kernel). Writes mesh.h5 and a .vtu for ParaView.");
  sub->add_option("image", args->image, "Labelled image (.nii or .nii.gz)")->required();
  sub->add_option("--solid", args->solid, "Label(s) to mesh, comma separated")->delimiter(',')->capture_default_str();
  sub->add_option("--topology", args->topology, "hex | tet5 | tet5m | tet6 | tet6m")->capture_default_str();
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
  sub->callback([args]() { run_mesh(*args); });
}

}  // namespace adamss::app
