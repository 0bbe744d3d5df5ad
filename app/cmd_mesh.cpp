// adamss mesh IMAGE --solid 1 --topology T -o mesh.h5: voxel lattice or CGAL Mesh_3 -> mesh.
// Parses the options into a preprocess::MeshRequest, runs the meshing pipeline
// (preprocess/pipeline/mesh_pipeline.hpp), writes mesh.h5 and the .vtu, and prints the report.
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
#include <variant>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "common/units.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_io_xdmf.hpp"
#include "preprocess/pipeline/mesh_pipeline.hpp"

namespace adamss::app {
namespace {

struct MeshArgs {
  std::string image;
  std::vector<int> solid{1};
  std::string topology = "tet6m";
  std::string fiber;
  std::string sheet;
  bool strict = false;
  bool allow_scaled_labels = false;
  std::string output;
  std::string vtu;
  bool no_vtu = false;
  std::vector<std::string> cavities;     ///< NAME=LABEL
  std::vector<std::string> tag_planes;   ///< NAME=AXIS:VALUE[:TOL]
  std::vector<std::string> cell_fields;  ///< NAME=FILE[:nearest|:trilinear]
  // --fiber rule (rule-based fibres, preprocess/fibres/rule_fibres.hpp); empty = not given.
  std::string helix_endo, helix_epi, sheet_angle, sheet_angle_epi, long_axis;
  std::string helix_endo_rv, helix_epi_rv, helix_septum_rv;  ///< biv angles per wall (empty: the LV ones)
  // --topology cgal only (empty = default relative to the voxel size).
  std::string cgal_facet_angle;
  std::string cgal_facet_size;
  std::string cgal_facet_distance;
  std::string cgal_cell_ratio;
  std::string cgal_cell_size;
  std::string resample;
  std::string smooth;
  bool clean_labels = false;
  bool cgal_no_perturb = false;
  bool cgal_no_exude = false;
  bool cgal_lloyd = false;
  bool cgal_odt = false;
  std::string cgal_min_node_elements;
  std::string seed;
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// ---- rule-based fibres (--fiber rule): options and the call, kept together.
bool rule_requested(const MeshArgs& a) {
  const bool rule = a.fiber == "rule";
  const bool rule_options = !a.helix_endo.empty() || !a.helix_epi.empty() || !a.sheet_angle.empty() ||
                            !a.sheet_angle_epi.empty() || !a.long_axis.empty() || !a.helix_endo_rv.empty() ||
                            !a.helix_epi_rv.empty() || !a.helix_septum_rv.empty();
  if (rule_options && !rule) {
    throw InputError(
        "--helix-endo/--helix-epi/--helix-endo-rv/--helix-epi-rv/--helix-septum-rv/--sheet-angle/--sheet-angle-epi/"
        "--long-axis apply only with --fiber rule");
  }
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
  if (!a.sheet_angle_epi.empty()) o.sheet_angle_epi_rad = angle(a.sheet_angle_epi, "", "--sheet-angle-epi");
  if (!a.helix_endo_rv.empty()) o.rv_helix_endo_rad = angle(a.helix_endo_rv, "", "--helix-endo-rv");
  if (!a.helix_epi_rv.empty()) o.rv_helix_epi_rad = angle(a.helix_epi_rv, "", "--helix-epi-rv");
  if (!a.helix_septum_rv.empty()) o.septum_rv_helix_rad = angle(a.helix_septum_rv, "", "--helix-septum-rv");
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
    return parse_length(text, what);
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
  if (!a.cgal_min_node_elements.empty()) {
    const std::string& v = a.cgal_min_node_elements;
    if (v.size() != 1 || v[0] < '0' || v[0] > '4' || v[0] == '1')
      throw InputError("--cgal-min-node-elements: '" + v + "': give 2, 3 or 4, or 0 for none");
    o.min_node_elements = v[0] - '0';
  }
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

void print_rule_fibres(const preprocess::RuleFibreReport& r) {
  const Eigen::Vector3d& l = r.long_axis;
  std::cout << "fibres: rule, " << (r.biv ? "LV + RV" : "one ventricle") << "; faces: " << r.lv_endo_faces
            << " LV endo, " << r.rv_endo_faces << " RV endo, " << r.epi_faces << " epi, " << r.base_faces << " base, "
            << r.other_faces << " other\n"
            << "  long axis (" << l.x() << ", " << l.y() << ", " << l.z() << ") "
            << (r.long_axis_estimated ? "estimated from the valve openings" : "given")
            << (r.biv ? "; RV free wall " + std::to_string(r.rv_elements) + " elements" : "") << "\n"
            << "  Laplace: " << r.solves << " solves, up to " << r.unknowns << " unknowns, " << r.max_iterations
            << " CG iterations, " << r.solve_seconds << " s\n";
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
                                                {!a.cgal_min_node_elements.empty(), "--cgal-min-node-elements"},
                                                {!a.seed.empty(), "--seed"}};
  for (const auto& [yes, name] : given)
    if (yes) return name;
  return "";
}

/// The files `adamss mesh` writes: mesh.h5 and the .vtu ("" for --no-vtu).
struct MeshOutputs {
  std::string h5;
  std::string vtu;
};

/// Topology, mesher and fibre options; InputError for options that do not go together.
preprocess::MeshRequest request_from_options(const MeshArgs& a) {
  using namespace preprocess;
  MeshRequest req;
  req.topology = parse_topology(a.topology);
  if (req.topology != Topology::Cgal) {
    const std::string opt = first_cgal_option(a);
    if (!opt.empty()) throw InputError(opt + ": only with --topology cgal (got --topology " + a.topology + ")");
  }
  const bool rule = rule_requested(a);
  if (req.topology == Topology::Cgal) req.cgal = cgal_options(a);
  if (!rule && a.fiber.empty() != a.sheet.empty()) throw InputError("--fiber and --sheet must be given together");
  req.image = ImageFile{a.image, a.allow_scaled_labels};
  req.source = a.image;
  req.solid_labels.assign(a.solid.begin(), a.solid.end());
  if (!a.resample.empty()) req.resample_m = parse_length(a.resample, "--resample");
  if (!a.smooth.empty()) req.smooth_m = parse_length(a.smooth, "--smooth");
  req.clean_labels = a.clean_labels;
  if (rule) {
    req.fibres = RuleFibres{};  // options read after the surface options, as before
  } else if (!a.fiber.empty()) {
    req.fibres = FibreImages{a.fiber, a.sheet, a.strict};
  }
  req.check = true;
  return req;
}

MeshOutputs output_paths(const MeshArgs& a) {
  require_parent_dir(a.output, "-o");
  const std::string vtu =
      a.no_vtu ? "" : (a.vtu.empty() ? std::filesystem::path(a.output).replace_extension(".vtu").string() : a.vtu);
  if (!vtu.empty()) require_parent_dir(vtu, "--vtu");
  return {a.output, vtu};
}

/// Refuses an output that would overwrite an input image or the other output (cli_util).
void check_outputs_against_inputs(const MeshArgs& a, const preprocess::MeshRequest& req, const MeshOutputs& out) {
  std::vector<NamedFile> inputs{{"IMAGE", a.image}};
  if (a.fiber != "rule") inputs.push_back({"--fiber", a.fiber});
  inputs.push_back({"--sheet", a.sheet});
  for (const preprocess::CellFieldSpec& f : req.cell_fields) inputs.push_back({"--cell-field " + f.name, f.file});
  const std::string vtu_option = a.vtu.empty() ? "--vtu (default: the -o name with .vtu)" : "--vtu";
  require_distinct_files(inputs, {{"-o", out.h5}, {vtu_option, out.vtu}});
}

/// --cavity, --tag-plane and --cell-field texts into the request (checked before any file is read).
void add_surface_options(const MeshArgs& a, preprocess::MeshRequest& req) {
  using namespace preprocess;
  for (const std::string& c : a.cavities) req.cavities.push_back(parse_cavity_spec(c, "--cavity"));
  for (const std::string& p : a.tag_planes) req.tag_planes.push_back({parse_tag_plane(p, "--tag-plane"), false});
  for (const std::string& f : a.cell_fields) {
    req.cell_fields.push_back(parse_cell_field_spec(f, "--cell-field"));
    if (!std::filesystem::exists(req.cell_fields.back().file)) {
      throw InputError("--cell-field " + req.cell_fields.back().name + ": image '" + req.cell_fields.back().file +
                       "' does not exist");
    }
  }
}

/// Fibre lines printed as soon as the fibres are on the mesh.
void print_fibres(const preprocess::MeshBuild& b) {
  if (b.rule_fibres) print_rule_fibres(*b.rule_fibres);
  if (b.image_fibres && b.image_fibres->filled_elements > 0) {
    std::cout << "fibres: " << b.image_fibres->filled_elements
              << " elements had no valid fibre/sheet sample and were filled from neighbours (e.g. element "
              << b.image_fibres->filled_examples.front() << ")\n";
  }
}

/// The CGAL lines of the report: criteria, times, surface patches per label pair.
std::string cgal_report(const preprocess::CgalMeshResult& r, const preprocess::CgalMeshOptions& opt) {
  const preprocess::CgalCriteria& c = r.criteria;
  std::map<std::pair<int, int>, std::size_t> pairs;
  for (const preprocess::SurfacePatchFace& f : r.patches) ++pairs[{f.label_in, f.label_out}];
  std::ostringstream os;
  os << std::setprecision(4) << "  cgal: facet angle " << c.facet_angle_deg << " deg, facet size "
     << c.facet_size_m * 1e3 << " mm, facet distance " << c.facet_distance_m * 1e3 << " mm, cell radius-edge ratio "
     << c.cell_radius_edge_ratio << ", cell size " << c.cell_size_m * 1e3 << " mm (voxel " << c.voxel_size_m * 1e3
     << " mm), seed " << opt.seed << ", voxel axes orthogonal to cosine " << c.max_axis_cosine << "\n"
     << "  cgal time: refine " << r.refine_seconds << " s"
     << (opt.odt || opt.lloyd ? ", smoothing " + std::to_string(r.smooth_seconds) + " s" : "") << ", perturb "
     << r.perturb_seconds << " s (" << r.perturb_attempts << " attempts" << (r.perturb_capped ? ", capped" : "")
     << "), exude " << r.exude_seconds << " s (" << r.initial_points << " initial points)\n"
     << "  surface patches (label inside-outside: faces):";
  for (const auto& [pr, n] : pairs) os << " " << pr.first << "-" << pr.second << ": " << n;
  os << "\n";
  if (r.weak_nodes) {
    const preprocess::WeakNodeReport& w = *r.weak_nodes;
    os << "  weak nodes (in fewer than " << w.min_elements << " elements): " << w.weak_nodes << " in " << w.rounds
       << " rounds; removed " << w.elements_removed << " elements (" << 100.0 * w.volume_fraction
       << " % of the volume) and " << w.nodes_removed << " nodes";
    if (w.weak_nodes_left > 0) os << "; " << w.weak_nodes_left << " weak nodes left after the last round";
    os << "\n";
  }
  if (r.inconsistent_patch_faces > 0) {
    os << "  warning: " << r.inconsistent_patch_faces
       << " boundary faces had no matching CGAL surface patch (outside label taken from the neighbour)\n";
  }
  return os.str();
}

/// Size, quality, CGAL lines, boundary and node tags.
void print_mesh_summary(const preprocess::MeshRequest& req, const preprocess::MeshBuild& b) {
  const preprocess::Mesh& mesh = b.mesh;
  const preprocess::QualitySummary& q = *b.quality;
  const preprocess::ConformityReport& conf = *b.conformity;
  if (b.resample) {
    const preprocess::ResampleReport& r = *b.resample;
    std::cout << std::setprecision(4) << "resampled (shape-based, per-label signed distance) " << r.dims_before[0]
              << "x" << r.dims_before[1] << "x" << r.dims_before[2] << " voxels of " << r.spacing_before.x() * 1e3
              << " x " << r.spacing_before.y() * 1e3 << " x " << r.spacing_before.z() * 1e3 << " mm to "
              << r.dims_after[0] << "x" << r.dims_after[1] << "x" << r.dims_after[2] << " of " << r.spacing_after * 1e3
              << " mm in " << r.seconds << " s; label volumes (ml):";
    for (const auto& [label, v] : r.volume_before_m3) {
      if (label == 0) continue;
      const auto after = r.volume_after_m3.find(label);
      std::cout << " " << label << ": " << v * 1e6 << " -> "
                << (after != r.volume_after_m3.end() ? after->second * 1e6 : 0.0);
    }
    std::cout << "\n";
  }
  if (b.smooth) {
    const preprocess::SmoothReport& s = *b.smooth;
    std::cout << std::setprecision(4) << "smoothed labels (Gaussian sigma " << s.sigma_m * 1e3
              << " mm on per-label signed distances) in " << s.seconds << " s: " << s.changed_voxels
              << " voxels changed; voxels per label:";
    for (const auto& [label, n] : s.voxels_before) {
      const auto after = s.voxels_after.find(label);
      std::cout << " " << label << ": " << n << " -> " << (after != s.voxels_after.end() ? after->second : 0);
    }
    std::cout << "\n";
  }
  if (b.cleanup) {
    const preprocess::LabelCleanupReport& c = *b.cleanup;
    std::cout << "clean labels: " << c.solid_components << " solid component(s), kept the largest (" << c.largest_voxels
              << " voxels), relabelled " << c.relabelled_voxels << " voxels of the others; filled " << c.holes
              << " enclosed background hole(s) (" << c.filled_voxels << " voxels)\n";
  }
  std::cout << std::setprecision(6) << "mesh " << preprocess::topology_name(req.topology) << ": " << mesh.node_count()
            << " nodes, " << mesh.element_count() << " " << element_type_name(mesh.type) << " elements, volume "
            << q.volume_m3 * 1e9 << " mm^3\n"
            << "  dihedral angle min " << q.min_dihedral_deg << " deg, mean of element minima " << q.mean_dihedral_deg
            << " deg, " << q.below_10_deg << " elements under 10 deg\n"
            << (b.cgal ? cgal_report(*b.cgal, req.cgal) : "") << "  boundary: " << conf.boundary_faces << " faces, "
            << (conf.closed_manifold() ? "closed 2-manifold" : "NOT a closed 2-manifold") << " ("
            << conf.nonmanifold_edges << " non-manifold edges, " << conf.nonmanifold_vertices
            << " non-manifold vertices)\n";
  std::cout << "  node tags:";
  for (const auto& [name, nodes] : mesh.node_tags) std::cout << " " << name << " (" << nodes.size() << ")";
  std::cout << "\n";
}

void print_cavities(const preprocess::MeshRequest& req, const preprocess::MeshBuild& b) {
  for (std::size_t i = 0; i < req.cavities.size(); ++i) {
    const preprocess::Cavity& c = b.mesh.cavities.at(req.cavities[i].name);
    const preprocess::CavityBuildInfo& ci = b.cavities[i];
    std::cout << "  cavity " << req.cavities[i].name << " (label " << req.cavities[i].label << "): " << ci.wall_faces
              << (c.quads.empty() ? " wall triangles, " : " wall quads, ") << c.lid.size() << " lid triangles ("
              << ci.loops << (ci.loops == 1 ? " opening" : " openings");
    if (ci.loops > 0) std::cout << ", max distance from its plane " << ci.lid_max_deviation_m * 1e3 << " mm";
    std::cout << "), volume " << c.volume_m3 * 1e9 << " mm^3 = " << c.volume_m3 * 1e6 << " ml, "
              << (ci.check.closed_manifold()
                      ? "closed (every edge in two faces)"
                      : "watertight, " + std::to_string(ci.check.nonmanifold_edges) + " edges in more than two faces")
              << "\n";
  }
}

void print_cell_fields(const preprocess::MeshRequest& req, const preprocess::MeshBuild& b) {
  for (std::size_t i = 0; i < req.cell_fields.size(); ++i) {
    const preprocess::CellFieldSpec& f = req.cell_fields[i];
    const preprocess::CellFieldReport& r = b.cell_fields[i];
    std::cout << "  cell field " << f.name << " (" << interpolation_name(f.method) << " from " << f.file << "): min "
              << r.min << ", max " << r.max;
    if (r.nan_elements > 0) std::cout << ", " << r.nan_elements << " elements NaN (only NaN voxels around them)";
    std::cout << "\n";
  }
}

void run_mesh(const MeshArgs& a) {
  const auto t_start = Clock::now();
  preprocess::MeshRequest req = request_from_options(a);
  const MeshOutputs out = output_paths(a);
  add_surface_options(a, req);
  check_outputs_against_inputs(a, req, out);
  if (std::filesystem::path(out.h5).extension() == ".xdmf") {
    throw InputError("-o: '" + out.h5 +
                     "' ends in .xdmf, the name of the XDMF sidecar written beside the mesh; "
                     "give the mesh file, e.g. mesh.h5");
  }
  if (auto* rule = std::get_if<preprocess::RuleFibres>(&req.fibres)) rule->options = rule_options(a);
  req.on_fibres = print_fibres;
  // Header notes (unit assumed, scaling applied) and open cavities, on stderr as soon as found.
  req.on_warning = [](const std::string& w) { std::cerr << "adamss mesh: warning: " << w << "\n"; };

  const preprocess::MeshBuild b = preprocess::build_mesh(req);

  const auto t = Clock::now();
  write_mesh_h5(out.h5, b.mesh);
  const std::string xdmf = std::filesystem::path(out.h5).replace_extension(".xdmf").string();
  write_mesh_xdmf(xdmf, out.h5, b.mesh);
  if (!out.vtu.empty()) write_mesh_vtu(out.vtu, b.mesh, b.quality->element_volume, b.quality->element_min_dihedral);
  const double t_write = since(t);

  print_mesh_summary(req, b);
  print_cavities(req, b);
  print_cell_fields(req, b);
  const preprocess::MeshStageTimes& s = b.times;
  std::cout << "  time: read " << s.read << " s, mesh " << s.mesh << " s, fibres " << s.fibres << " s, surfaces "
            << s.surfaces << " s, cell fields " << s.cell_fields << " s, checks " << s.checks << " s, write " << t_write
            << " s, total " << since(t_start) << " s\n"
            << "wrote " << out.h5 << ", " << xdmf << (out.vtu.empty() ? "" : " and " + out.vtu) << "\n";
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
  sub->add_flag("--allow-scaled-labels", args->allow_scaled_labels,
                "Apply the image header's scl_slope/scl_inter to the labels (without it a scaled label image is "
                "refused: an intercept of 1 would turn the background label 0 into 1)");
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
  sub->add_option("--helix-endo-rv", args->helix_endo_rv,
                  "--fiber rule, biv: helix angle at the RV free wall's endocardium, degrees (default --helix-endo)");
  sub->add_option("--helix-epi-rv", args->helix_epi_rv,
                  "--fiber rule, biv: helix angle at the RV free wall's epicardium, degrees (default --helix-epi)");
  sub->add_option("--helix-septum-rv", args->helix_septum_rv,
                  "--fiber rule, biv: helix angle at the septum's RV surface, degrees (default --helix-epi)");
  sub->add_option("--sheet-angle", args->sheet_angle,
                  "--fiber rule: sheet angle about the fibre, degrees (default 0); with --sheet-angle-epi its "
                  "value at the endocardium");
  sub->add_option("--sheet-angle-epi", args->sheet_angle_epi,
                  "--fiber rule: sheet angle at the epicardium, degrees, linear through the wall from --sheet-angle "
                  "(LDRB: --sheet-angle -65 --sheet-angle-epi 25; default: --sheet-angle throughout)");
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
  sub->add_option("--resample", args->resample,
                  "resample the label image to isotropic voxels of this edge before meshing (shape-based "
                  "interpolation of per-label signed distances; e.g. 1.37mm for a 10 mm slice stack)");
  sub->add_option("--smooth", args->smooth,
                  "smooth the labels before meshing: a Gaussian of this standard deviation on each label's signed "
                  "distance (after --resample); 0.7 voxel removes strands joined only by voxel edges or corners and "
                  "keeps walls one voxel thick (e.g. 0.7mm at 1 mm voxels)");
  sub->add_flag("--clean-labels", args->clean_labels,
                "keep the largest connected solid component (islands take their surroundings' label) and fill "
                "background holes enclosed by the image's labels");
  sub->add_option("--cgal-cell-size", args->cgal_cell_size,
                  "cgal: upper bound on the tetrahedron circumradius, a length (default 2 voxels)");
  sub->add_flag("--cgal-no-perturb", args->cgal_no_perturb, "cgal: skip the sliver perturbation");
  sub->add_flag("--cgal-no-exude", args->cgal_no_exude, "cgal: skip the sliver exudation");
  sub->add_flag("--cgal-lloyd", args->cgal_lloyd, "cgal: Lloyd smoothing before perturbation");
  sub->add_flag("--cgal-odt", args->cgal_odt, "cgal: ODT smoothing before perturbation");
  sub->add_option("--cgal-min-node-elements", args->cgal_min_node_elements,
                  "cgal: remove, in rounds, the elements holding a node in fewer than N elements (3: no surface node "
                  "left in one or two elements, which soft laws leave almost unsupported); 0 (default) keeps the mesh")
      ->type_name("N");
  sub->add_option("--seed", args->seed, "cgal: random seed (default 0); the same seed gives the same mesh");
  sub->callback([args]() { run_mesh(*args); });
}

}  // namespace adamss::app
