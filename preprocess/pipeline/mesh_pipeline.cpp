#include "preprocess/pipeline/mesh_pipeline.hpp"

#include <chrono>
#include <string>
#include <utility>

#include "common/error.hpp"
#include "preprocess/image/label_cleanup.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "preprocess/image/resample.hpp"
#include "preprocess/surfaces/anatomical_tags.hpp"
#include "preprocess/surfaces/boundary_labels.hpp"

namespace adamss::preprocess {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
// C++20 deduces this from the aggregate initialiser; clang 14 (clang-tidy) still needs the guide.
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

/// Records a warning in the build and hands it to the request's on_warning at once.
void warn(const MeshRequest& request, MeshBuild& out, const std::string& text) {
  out.warnings.push_back(text);
  if (request.on_warning) request.on_warning(text);
}

/// The header notes of an image just read, as warnings of the build.
void warn_notes(const MeshRequest& request, MeshBuild& out, const NiftiNotes& notes) {
  for (const std::string& w : notes.warnings) warn(request, out, w);
}

/// The label image of the request; a phantom brings its analytic fibre and sheet fields too.
Phantom source_image(const MeshRequest& request, MeshBuild& out) {
  return std::visit(Overloaded{[&](const ImageFile& f) {
                                 NiftiNotes notes;
                                 const LabelScaling scaling =
                                     f.apply_label_scaling ? LabelScaling::kApply : LabelScaling::kRefuse;
                                 Phantom p{read_label_image(f.path, &notes, scaling), {}, {}};
                                 warn_notes(request, out, notes);
                                 return p;
                               },
                               [](const PhantomImage& p) { return make_phantom(p.kind, p.options); }},
                    request.image);
}

/// The volume mesh of the solid labels: CGAL Mesh_3 or the voxel lattice.
void mesh_volume(const MeshRequest& request, const LabelImage& image, MeshBuild& out) {
  if (request.topology == Topology::Cgal) {
    CgalMeshOptions options = request.cgal;
    options.solid_labels.assign(request.solid_labels.begin(), request.solid_labels.end());
    out.cgal = mesh_cgal(image, options);
    out.mesh = std::move(out.cgal->mesh);
    out.cgal->mesh = Mesh{};
  } else {
    LatticeMeshOptions options;
    options.topology = request.topology;
    options.solid_labels = request.solid_labels;
    out.mesh = mesh_lattice(image, options);
  }
  out.mesh.attributes["source"] = request.source;
}

/// Fibre and sheet per element from the request's fibre source; returns the stage's seconds
/// (0 when nothing was assigned).
double add_fibres(const MeshRequest& request, const Phantom& source, MeshBuild& out) {
  const auto t = Clock::now();
  if (const auto* rule = std::get_if<RuleFibres>(&request.fibres)) {
    out.rule_fibres = assign_rule_fibres(out.mesh, source.image, rule->options);
    return out.rule_fibres->total_seconds;
  }
  if (const auto* files = std::get_if<FibreImages>(&request.fibres)) {
    NiftiNotes fiber_notes;
    NiftiNotes sheet_notes;
    const VectorImage f = read_vector_image(files->fiber_file, &fiber_notes);
    warn_notes(request, out, fiber_notes);
    const VectorImage s = read_vector_image(files->sheet_file, &sheet_notes);
    warn_notes(request, out, sheet_notes);
    out.image_fibres =
        assign_fibres(out.mesh, source.image.grid, f, files->fiber_file, s, files->sheet_file, files->strict);
    out.mesh.attributes["fiber_source"] = files->fiber_file;
    out.mesh.attributes["sheet_source"] = files->sheet_file;
    return since(t);
  }
  if (std::holds_alternative<PhantomFibres>(request.fibres) && source.fiber && source.sheet) {
    out.image_fibres = assign_fibres(out.mesh, source.image.grid, *source.fiber, "phantom fibre", *source.sheet,
                                     "phantom sheet", false);
    return since(t);
  }
  return 0.0;
}

/// Boundary faces with the label beyond each: from the CGAL mesher's surface patches (it knows
/// that label exactly), else read from the image next to each lattice face.
std::vector<BoundaryFace> labelled_boundary(const MeshBuild& build, const LabelImage& image) {
  if (!build.cgal) return boundary_faces_with_labels(build.mesh, image);
  std::vector<BoundaryFace> faces;
  for (const SurfacePatchFace& pf : build.cgal->patches) {
    BoundaryFace f;
    f.nodes = {pf.nodes[0], pf.nodes[1], pf.nodes[2], -1};
    f.element = pf.element;
    f.inside_label = pf.label_in;
    f.outside_label = pf.label_out;
    faces.push_back(f);
  }
  return faces;
}

void add_plane_tag(Mesh& mesh, const PlaneTagRequest& request) {
  const TagPlane& p = request.plane;
  if (request.skip_if_empty) {
    std::vector<Index> nodes;
    try {
      nodes = nodes_on_plane(mesh, p, p.name);
    } catch (const InputError&) {
      // The plane holds no node (e.g. not a voxel face at this voxel size): no tag.
    }
    if (!nodes.empty()) mesh.node_tags[p.name] = std::move(nodes);
    return;
  }
  if (mesh.node_tags.count(p.name) != 0)
    throw InputError("--tag-plane " + p.name + ": a node tag of that name already exists");
  mesh.node_tags[p.name] = nodes_on_plane(mesh, p, "--tag-plane");
}

/// Label-pair node tags, plane tags and cavities.
void add_surfaces(const MeshRequest& request, const LabelImage& image, MeshBuild& out) {
  const std::vector<BoundaryFace> faces = labelled_boundary(out, image);
  out.mesh.node_tags = label_pair_tags(faces);
  for (const PlaneTagRequest& p : request.tag_planes) add_plane_tag(out.mesh, p);
  if (!request.cavities.empty()) {
    check_cavity_labels_present(image, request.cavities);
    for (const std::string& w : cavity_border_warnings(image, request.cavities)) warn(request, out, w);
    add_cavities(out.mesh, faces, request.cavities, &out.cavities);
    out.anatomy = add_anatomical_tags(out.mesh, request.cavities, request.solid_labels);
    for (const std::string& name : out.anatomy->skipped)
      warn(request, out, "anatomical tag '" + name + "' not added: the mesh already has a tag of that name");
  }
}

/// The requested cell fields: scalar images from files, then the phantom's scar segment.
void add_fields(const MeshRequest& request, const LabelImage& image, MeshBuild& out) {
  for (const CellFieldSpec& f : request.cell_fields) {
    NiftiNotes notes;
    const ScalarImage field = read_scalar_image(f.file, &notes);
    warn_notes(request, out, notes);
    out.cell_fields.push_back(add_cell_field(out.mesh, f.name, field, f.method));
    out.mesh.attributes["cell_field_" + f.name] = f.file + ":" + interpolation_name(f.method);
  }
  if (request.scar) add_cell_field(out.mesh, "scar", scar_image(image, *request.scar), Interpolation::Nearest);
}

/// Quality and conformity; NumericalError for inverted elements or overshared faces.
void check_mesh(MeshBuild& out) {
  out.quality = summarize_quality(out.mesh);
  out.conformity = check_conformity(out.mesh);
  if (out.quality->inverted > 0)
    throw NumericalError("mesher produced " + std::to_string(out.quality->inverted) + " inverted elements");
  if (out.conformity->overshared_faces > 0) {
    throw NumericalError("mesher produced a non-conforming mesh (" + std::to_string(out.conformity->overshared_faces) +
                         " faces in more than two elements)");
  }
}

}  // namespace

MeshBuild build_mesh(const MeshRequest& request) {
  MeshBuild out;
  auto t = Clock::now();
  Phantom source = source_image(request, out);
  if (request.resample_m > 0.0) {
    if (std::holds_alternative<FibreImages>(request.fibres) || std::holds_alternative<PhantomFibres>(request.fibres)) {
      throw InputError(
          "--resample: fibre images are on the label image's lattice; use rule-based fibres (--fiber "
          "rule) with a resampled image");
    }
    ResampleReport report;
    source.image = resample_labels(source.image, request.resample_m, &report);
    out.resample = report;
  }
  if (request.smooth_m > 0.0) out.smooth = smooth_labels(source.image, request.smooth_m);
  if (request.clean_labels) out.cleanup = clean_labels(source.image, request.solid_labels);
  out.times.read = since(t);

  t = Clock::now();
  mesh_volume(request, source.image, out);
  out.times.mesh = since(t);

  out.times.fibres = add_fibres(request, source, out);
  if (request.on_fibres) request.on_fibres(out);

  t = Clock::now();
  add_surfaces(request, source.image, out);
  out.times.surfaces = since(t);

  t = Clock::now();
  add_fields(request, source.image, out);
  out.times.cell_fields = since(t);

  if (request.check) {
    t = Clock::now();
    check_mesh(out);
    out.times.checks = since(t);
    const MeshStageTimes& s = out.times;
    out.mesh.attributes["meshing_seconds"] = std::to_string(s.mesh + s.fibres + s.surfaces + s.cell_fields);
  }
  return out;
}

}  // namespace adamss::preprocess
