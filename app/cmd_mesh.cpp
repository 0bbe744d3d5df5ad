// adamss mesh IMAGE --solid 1 --topology T -o mesh.h5: voxel lattice or CGAL Mesh_3 -> mesh.
#include <chrono>
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
#include "preprocess/cgal_mesher.hpp"
#include "preprocess/fibre_field.hpp"
#include "preprocess/lattice_mesher.hpp"
#include "preprocess/mesh_io.hpp"
#include "preprocess/mesh_quality.hpp"
#include "preprocess/nifti_io.hpp"

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
  const CgalMeshOptions cgal_opt = topo == Topology::Cgal ? cgal_options(a) : CgalMeshOptions{};
  if (a.fiber.empty() != a.sheet.empty()) throw InputError("--fiber and --sheet must be given together");
  require_parent_dir(a.output, "-o");
  const std::string vtu =
      a.no_vtu ? "" : (a.vtu.empty() ? std::filesystem::path(a.output).replace_extension(".vtu").string() : a.vtu);
  if (!vtu.empty()) require_parent_dir(vtu, "--vtu");

  auto t = Clock::now();
  const LabelImage image = read_label_image(a.image);
  const double t_read = since(t);

  t = Clock::now();
  Mesh mesh;
  std::ostringstream cgal_report;
  if (topo == Topology::Cgal) {
    CgalMeshResult r = mesh_cgal(image, cgal_opt);
    mesh = std::move(r.mesh);
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
  if (!a.fiber.empty()) {
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

  t = Clock::now();
  const QualitySummary q = summarize_quality(mesh);
  const ConformityReport conf = check_conformity(mesh);
  const double t_check = since(t);
  if (q.inverted > 0) throw NumericalError("mesher produced " + std::to_string(q.inverted) + " inverted elements");
  if (conf.overshared_faces > 0) {
    throw NumericalError("mesher produced a non-conforming mesh (" + std::to_string(conf.overshared_faces) +
                         " faces in more than two elements)");
  }
  mesh.attributes["meshing_seconds"] = std::to_string(t_mesh + t_fibre);

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
            << " non-manifold vertices)\n"
            << "  time: read " << t_read << " s, mesh " << t_mesh << " s, fibres " << t_fibre << " s, checks "
            << t_check << " s, write " << t_write << " s, total " << since(t_start) << " s\n"
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
  sub->add_option("--fiber", args->fiber, "Fibre vector image on the same lattice (interpolated to elements)");
  sub->add_option("--sheet", args->sheet, "Sheet vector image on the same lattice");
  sub->add_flag("--strict", args->strict, "Reject elements without a valid fibre sample instead of filling them");
  sub->add_option("-o,--output", args->output, "Output mesh.h5")->required();
  sub->add_option("--vtu", args->vtu, "Where to write the .vtu (default: the output name with .vtu)");
  sub->add_flag("--no-vtu", args->no_vtu, "Do not write the .vtu");
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
