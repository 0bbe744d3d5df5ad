// CGAL Mesh_3 on a labelled image. All CGAL includes of the project live in this file (Mesh_3
// is slow to compile); see cgal_mesher.hpp for the method.
#include "preprocess/meshers/cgal_mesher.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/ImageIO.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_3/Sliver_perturber.h>
#include <CGAL/Mesh_3/sliver_criteria.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/lloyd_optimize_mesh_3.h>
#include <CGAL/odt_optimize_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/meshers/locality_order.hpp"

namespace adamss::preprocess {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
using Point = K::Point_3;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Mesh_3's "outside the domain" test: every label that is not solid.
struct NotSolid {
  std::vector<int> solid;  // sorted
  bool operator()(int label) const { return !std::binary_search(solid.begin(), solid.end(), label); }
};

std::string describe_labels(const LabelImage& image) {
  std::ostringstream os;
  bool first = true;
  for (const auto& [label, count] : image.histogram()) {
    os << (first ? "" : ", ") << label << " (" << count << " voxels)";
    first = false;
  }
  return os.str();
}

std::string join_labels(const std::vector<std::int32_t>& labels) {
  std::ostringstream os;
  for (std::size_t i = 0; i < labels.size(); ++i) os << (i ? "," : "") << labels[i];
  return os.str();
}

void require_positive(double v, const char* option) {
  if (!std::isfinite(v) || !(v > 0.0)) {
    std::ostringstream os;
    os << option << ": must be a positive length, got " << v << " m";
    throw InputError(os.str());
  }
}

/// The image padded with one voxel of label 0 on every side, in CGAL's ImageIO layout
/// (int32, x fastest), with voxel sizes s / h.
struct PaddedImage {
  std::array<std::int64_t, 3> dims{};
  std::vector<std::int32_t> labels;
  [[nodiscard]] std::size_t linear(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(i + dims[0] * (j + dims[1] * k));
  }
};

PaddedImage pad(const LabelImage& image) {
  PaddedImage p;
  const auto& d = image.grid.dims;
  p.dims = {d[0] + 2, d[1] + 2, d[2] + 2};
  p.labels.assign(static_cast<std::size_t>(p.dims[0] * p.dims[1] * p.dims[2]), 0);
  for (std::int64_t k = 0; k < d[2]; ++k) {
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i) p.labels[p.linear(i + 1, j + 1, k + 1)] = image.at(i, j, k);
  }
  return p;
}

/// Voxel faces to seed Mesh_3 with: for each 6-connected component of equal labels and each of
/// the six face directions, up to `per_direction` faces to another label with at least one side
/// solid, evenly spaced in voxel order. Each entry is (voxel, axis, +1/-1).
struct SeedFace {
  std::size_t voxel;
  int axis;
  int step;
};

std::vector<SeedFace> seed_faces(const PaddedImage& img, const NotSolid& not_solid, std::size_t per_direction) {
  const auto& d = img.dims;
  const std::size_t n = img.labels.size();
  const std::array<std::int64_t, 3> stride{1, d[0], d[0] * d[1]};
  std::vector<std::uint8_t> seen(n, 0);
  std::vector<SeedFace> out;
  std::vector<std::size_t> stack;
  std::vector<SeedFace> faces;
  for (std::size_t start = 0; start < n; ++start) {
    if (seen[start]) continue;
    const std::int32_t label = img.labels[start];
    const bool solid = !not_solid(label);
    faces.clear();
    // Depth-first flood fill collecting the component's faces; sorted into voxel order below.
    stack.assign(1, start);
    seen[start] = 1;
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      const std::int64_t iv = static_cast<std::int64_t>(v);
      const std::array<std::int64_t, 3> ijk{iv % d[0], (iv / d[0]) % d[1], iv / (d[0] * d[1])};
      for (int a = 0; a < 3; ++a) {
        for (int s : {-1, 1}) {
          const std::int64_t c = ijk[static_cast<std::size_t>(a)] + s;
          if (c < 0 || c >= d[static_cast<std::size_t>(a)]) continue;
          const auto w = static_cast<std::size_t>(iv + s * stride[static_cast<std::size_t>(a)]);
          if (img.labels[w] == label) {
            if (!seen[w]) {
              seen[w] = 1;
              stack.push_back(w);
            }
          } else if (solid || !not_solid(img.labels[w])) {
            faces.push_back({v, a, s});
          }
        }
      }
    }
    if (faces.empty()) continue;
    // Group by face direction, then voxel order; take up to per_direction evenly spaced faces of
    // each of the six directions, so the seeds are never all on one side of a thin structure.
    std::sort(faces.begin(), faces.end(), [](const SeedFace& x, const SeedFace& y) {
      return std::tie(x.axis, x.step, x.voxel) < std::tie(y.axis, y.step, y.voxel);
    });
    for (std::size_t lo = 0; lo < faces.size();) {
      std::size_t hi = lo;
      while (hi < faces.size() && faces[hi].axis == faces[lo].axis && faces[hi].step == faces[lo].step) ++hi;
      const std::size_t n_dir = hi - lo, m = std::min(per_direction, n_dir);
      for (std::size_t q = 0; q < m; ++q) out.push_back(faces[lo + (2 * q + 1) * n_dir / (2 * m)]);
      lo = hi;
    }
  }
  return out;
}

/// Local frame: padded voxel (i, j, k) has its centre at (i v_x, j v_y, k v_z), v = s / h.
struct LocalFrame {
  Eigen::Vector3d v;          // voxel sizes in units of h
  Eigen::Matrix3d world_lin;  // index -> world linear part
  Eigen::Vector3d world_off;
  [[nodiscard]] Eigen::Vector3d to_world(const Point& p) const {
    const Eigen::Vector3d idx(p.x() / v.x() - 1.0, p.y() / v.y() - 1.0, p.z() / v.z() - 1.0);
    return world_lin * idx + world_off;
  }
  [[nodiscard]] Point centre(const PaddedImage& img, std::size_t voxel) const {
    const auto iv = static_cast<std::int64_t>(voxel);
    const auto& d = img.dims;
    const std::int64_t i = iv % d[0], j = (iv / d[0]) % d[1], k = iv / (d[0] * d[1]);  // voxel indices
    return {static_cast<double>(i) * v.x(), static_cast<double>(j) * v.y(), static_cast<double>(k) * v.z()};
  }
};

/// Thrown by PerturbVisitor to stop the sliver perturber after a fixed number of vertex
/// perturbation attempts: a deterministic replacement for its wall-clock time limit. The
/// visitor is called between attempts, when the triangulation is consistent.
struct PerturbCapReached {};

struct PerturbCounters {
  std::size_t attempts = 0;
  std::size_t cap = 0;
  double bound_reached_deg = 0.0;
};

class PerturbVisitor {
 public:
  explicit PerturbVisitor(PerturbCounters* c) : c_(c) {}
  void bound_reached(double bound) { c_->bound_reached_deg = bound; }
  void end_of_perturbation_iteration(std::size_t /*queue_size*/) {
    if (++c_->attempts >= c_->cap) throw PerturbCapReached{};
  }

 private:
  PerturbCounters* c_;
};

/// CGAL::perturb_mesh_3 with the default perturbations and sliver bound (12 deg), no time
/// limit, and at most counters.cap vertex perturbation attempts.
void perturb_capped(C3t3& c3t3, const Domain& domain, PerturbCounters& counters) {
  using Criterion = CGAL::Mesh_3::Min_dihedral_angle_criterion<Tr>;
  using Perturber = CGAL::Mesh_3::Sliver_perturber<C3t3, Domain, Criterion, PerturbVisitor>;
  const Criterion criterion(0.0, c3t3.triangulation());  // 0 = the criterion's default bound
  Perturber perturber(c3t3, domain, criterion);
  for (auto* p : CGAL::default_perturbation_vector(c3t3, domain, criterion)) perturber.add_perturbation(p);
  perturber.set_time_limit(0.0);
  try {
    perturber(PerturbVisitor(&counters));
  } catch (const PerturbCapReached&) {
    // Stopped between two attempts; the cached sliver values may be stale for the exuder.
    for (auto c = c3t3.triangulation().finite_cells_begin(); c != c3t3.triangulation().finite_cells_end(); ++c)
      c->reset_cache_validity();
  }
}

std::string format_length(double m) {
  std::ostringstream os;
  os.precision(6);
  os << m * 1e3 << "mm";
  return os.str();
}

/// The solid labels of options (sorted, unique) as Mesh_3's "outside" test, after the input
/// checks of mesh_cgal (see the header).
NotSolid solid_labels(const LabelImage& image, const CgalMeshOptions& options) {
  if (options.solid_labels.empty()) throw InputError("--solid: no solid label given");
  NotSolid not_solid;
  not_solid.solid.assign(options.solid_labels.begin(), options.solid_labels.end());
  std::sort(not_solid.solid.begin(), not_solid.solid.end());
  not_solid.solid.erase(std::unique(not_solid.solid.begin(), not_solid.solid.end()), not_solid.solid.end());
  if (std::binary_search(not_solid.solid.begin(), not_solid.solid.end(), 0)) {
    throw InputError("--solid: label 0 cannot be meshed with --topology cgal (it is the background)");
  }
  const auto& d = image.grid.dims;
  if (d[0] < 1 || d[1] < 1 || d[2] < 1 || image.labels.size() != image.grid.voxel_count()) {
    throw InputError("mesh_cgal: the label image is empty or its size does not match its dims");
  }
  if (std::none_of(image.labels.begin(), image.labels.end(), [&](std::int32_t l) { return !not_solid(l); })) {
    throw InputError("--solid: no voxel carries the solid label(s) " + join_labels(options.solid_labels) +
                     "; labels present: " + describe_labels(image));
  }
  return not_solid;
}

/// The local frame of the padded image for the unit length h.
LocalFrame local_frame(const Grid& grid, double h) {
  LocalFrame frame;
  frame.v = grid.spacing() / h;
  frame.world_lin = grid.index_to_world.topLeftCorner<3, 3>();
  frame.world_off = grid.index_to_world.topRightCorner<3, 1>();
  return frame;
}

/// The padded image as a CGAL::Image_3 (which owns its copy of the buffer), voxel sizes frame.v.
CGAL::Image_3 cgal_image(const PaddedImage& padded, const LocalFrame& frame) {
  _image* raw = ::_createImage(static_cast<std::size_t>(padded.dims[0]), static_cast<std::size_t>(padded.dims[1]),
                               static_cast<std::size_t>(padded.dims[2]), 1, frame.v.x(), frame.v.y(), frame.v.z(),
                               sizeof(std::int32_t), WK_FIXED, SGN_SIGNED);
  if (raw == nullptr || raw->data == nullptr) throw NumericalError("mesh_cgal: cannot allocate the CGAL image");
  std::memcpy(raw->data, padded.labels.data(), padded.labels.size() * sizeof(std::int32_t));
  return CGAL::Image_3(raw);
}

/// Initial points on every connected component of the surface: for each seed face, the domain
/// boundary on the segment between the two voxel centres, inserted as a surface (dimension 2)
/// vertex. Returns the number of vertices; NumericalError when they do not span 3D.
std::size_t insert_seed_points(C3t3& c3t3, const Domain& domain, const PaddedImage& padded, const LocalFrame& frame,
                               const NotSolid& not_solid) {
  Tr& tr = c3t3.triangulation();
  const auto construct_intersection = domain.construct_intersection_object();
  const auto cwp = tr.geom_traits().construct_weighted_point_3_object();
  const std::array<std::int64_t, 3> stride{1, padded.dims[0], padded.dims[0] * padded.dims[1]};
  for (const SeedFace& f : seed_faces(padded, not_solid, 3)) {
    const Point a = frame.centre(padded, f.voxel);
    const auto other = static_cast<std::size_t>(static_cast<std::int64_t>(f.voxel) +
                                                f.step * stride[static_cast<std::size_t>(f.axis)]);
    const Point b = frame.centre(padded, other);
    const Domain::Intersection x = construct_intersection(K::Segment_3(a, b));
    if (std::get<2>(x) == 0) continue;
    const Tr::Vertex_handle vh = tr.insert(cwp(std::get<0>(x)));
    if (vh == Tr::Vertex_handle()) continue;
    c3t3.set_dimension(vh, 2);
    c3t3.set_index(vh, std::get<1>(x));
  }
  const std::size_t count = tr.number_of_vertices();
  if (tr.dimension() < 3) {
    throw NumericalError("mesh_cgal: the " + std::to_string(count) +
                         " initial surface points do not span 3D (is the solid region degenerate?)");
  }
  return count;
}

/// The optional optimisers after refinement (ODT, Lloyd, perturbation, exudation), without
/// wall-clock limits (time_limit = 0) so the result does not depend on load; their times and
/// the perturbation counters go to result.
void optimise(C3t3& c3t3, const Domain& domain, const CgalMeshOptions& options, CgalMeshResult& result) {
  namespace p = CGAL::parameters;
  auto t = Clock::now();
  if (options.odt) {
    CGAL::odt_optimize_mesh_3(c3t3, domain, p::time_limit = 0,
                              p::max_iteration_number = options.max_smoothing_iterations);
  }
  if (options.lloyd) {
    CGAL::lloyd_optimize_mesh_3(c3t3, domain, p::time_limit = 0,
                                p::max_iteration_number = options.max_smoothing_iterations);
  }
  result.smooth_seconds = since(t);
  t = Clock::now();
  if (options.perturb) {
    PerturbCounters counters;
    counters.cap =
        std::max<std::size_t>(1, options.perturb_attempts_per_vertex) * c3t3.triangulation().number_of_vertices();
    perturb_capped(c3t3, domain, counters);
    result.perturb_attempts = counters.attempts;
    result.perturb_capped = counters.attempts >= counters.cap;
    result.perturb_bound_deg = counters.bound_reached_deg;
  }
  result.perturb_seconds = since(t);
  t = Clock::now();
  if (options.exude) CGAL::exude_mesh_3(c3t3, p::time_limit = 0);
  result.exude_seconds = since(t);
}

using NodeOf = std::unordered_map<Tr::Vertex_handle, Index>;

/// Nodes of mesh: the vertices of the cells in the complex, numbered in order of first use, in
/// world coordinates. Returns the vertex -> node map. NumericalError for an empty complex,
/// InputError when the elements exceed the index range.
NodeOf extract_nodes(C3t3& c3t3, const LocalFrame& frame, Mesh& mesh) {
  const std::size_t n_cells = static_cast<std::size_t>(c3t3.number_of_cells_in_complex());
  if (n_cells == 0) throw NumericalError("mesh_cgal: CGAL Mesh_3 produced no element (solid region too thin?)");
  if (n_cells > static_cast<std::size_t>(std::numeric_limits<Index>::max()) / 4) {
    throw InputError("mesh_cgal: " + std::to_string(n_cells) + " elements exceed the index range");
  }
  NodeOf node_of;
  std::vector<Tr::Vertex_handle> vertices;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    for (int i = 0; i < 4; ++i) {
      const Tr::Vertex_handle vh = c->vertex(i);
      if (node_of.emplace(vh, static_cast<Index>(vertices.size())).second) vertices.push_back(vh);
    }
  }
  Tr& tr = c3t3.triangulation();
  const auto cp = tr.geom_traits().construct_point_3_object();
  mesh.nodes.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh.nodes.col(static_cast<Eigen::Index>(v)) = frame.to_world(cp(tr.point(vertices[v])));
  }
  return node_of;
}

/// label_out of the face of cell c opposite CGAL vertex i, whose far side is not meshed: the
/// non-solid member of the facet's surface patch. Counts the face in
/// result.inconsistent_patch_faces when the facet is not in the complex or its patch does not
/// pair `label` with one non-solid label (label_out is then that member, or 0).
template <class CellIt>
std::int32_t unmeshed_far_label(C3t3& c3t3, const CellIt& c, int i, int label, const NotSolid& not_solid,
                                CgalMeshResult& result) {
  std::int32_t out = 0;
  bool known = false;
  if (c3t3.is_in_complex(c, i)) {
    const auto sp = c3t3.surface_patch_index(c, i);
    const bool first_out = not_solid(sp.first), second_out = not_solid(sp.second);
    if (first_out != second_out) {
      out = first_out ? sp.first : sp.second;
      known = sp.first == label || sp.second == label;
    }
  }
  if (!known) ++result.inconsistent_patch_faces;
  return out;
}

/// Elements of result.mesh (positive volume in world coordinates; CGAL's labels) and their
/// boundary and interface faces into result.patches, in the order of the complex's cells.
void extract_elements(C3t3& c3t3, const NodeOf& node_of, const NotSolid& not_solid, CgalMeshResult& result) {
  // Local face of a VTK tet opposite to local vertex j (kTetFaces).
  constexpr std::array<std::uint8_t, 4> kFaceOpposite{2, 3, 1, 0};
  Mesh& mesh = result.mesh;
  const std::size_t n_cells = static_cast<std::size_t>(c3t3.number_of_cells_in_complex());
  mesh.connectivity.reserve(4 * n_cells);
  mesh.labels.reserve(n_cells);
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    const auto e = static_cast<std::uint32_t>(mesh.labels.size());
    const int label = c3t3.subdomain_index(c);
    std::array<Index, 4> n{};
    for (int i = 0; i < 4; ++i) n[static_cast<std::size_t>(i)] = node_of.at(c->vertex(i));
    const Eigen::Vector3d x0 = mesh.nodes.col(n[0]);
    const double vol = (mesh.nodes.col(n[1]) - x0).dot((mesh.nodes.col(n[2]) - x0).cross(mesh.nodes.col(n[3]) - x0));
    std::array<int, 4> slot{0, 1, 2, 3};  // CGAL vertex i -> local node slot[i]
    if (vol < 0.0) {
      std::swap(n[0], n[1]);
      std::swap(slot[0], slot[1]);
    }
    mesh.connectivity.insert(mesh.connectivity.end(), n.begin(), n.end());
    mesh.labels.push_back(label);
    for (int i = 0; i < 4; ++i) {
      const Tr::Cell_handle nb = c->neighbor(i);
      if (c3t3.is_in_complex(nb) && c3t3.subdomain_index(nb) == label) continue;
      SurfacePatchFace f;
      const auto& lf = kTetFaces[kFaceOpposite[static_cast<std::size_t>(slot[static_cast<std::size_t>(i)])]];
      for (int q = 0; q < 3; ++q) f.nodes[static_cast<std::size_t>(q)] = n[static_cast<std::size_t>(lf[q])];
      f.element = e;
      f.label_in = label;
      // An interface between two solid labels: the mesh decides; else the surface patch does.
      f.label_out =
          c3t3.is_in_complex(nb) ? c3t3.subdomain_index(nb) : unmeshed_far_label(c3t3, c, i, label, not_solid, result);
      result.patches.push_back(f);
    }
  }
}

/// The "cgal_criteria" mesh attribute: the criteria and options that made the mesh.
std::string criteria_attribute(const CgalCriteria& crit, const CgalMeshOptions& options) {
  std::ostringstream os;
  os << "facet_angle=" << crit.facet_angle_deg << "deg facet_size=" << format_length(crit.facet_size_m)
     << " facet_distance=" << format_length(crit.facet_distance_m)
     << " cell_radius_edge_ratio=" << crit.cell_radius_edge_ratio << " cell_size=" << format_length(crit.cell_size_m)
     << (options.odt ? " odt" : "") << (options.lloyd ? " lloyd" : "") << (options.perturb ? " perturb" : "")
     << (options.exude ? " exude" : "") << " seed=" << options.seed;
  return os.str();
}

}  // namespace

CgalCriteria resolve_cgal_criteria(const Grid& grid, const CgalMeshOptions& options) {
  const Eigen::Matrix3d a = grid.index_to_world.topLeftCorner<3, 3>();
  const Eigen::Vector3d s = grid.spacing();
  if (!a.allFinite() || !(s.minCoeff() > 0.0)) throw InputError("--topology cgal: the image affine is singular");
  double max_cosine = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double c = std::abs(a.col(i).dot(a.col(j))) / (s(i) * s(j));
      max_cosine = std::max(max_cosine, c);
      if (c > 1e-3) {
        std::ostringstream os;
        os << "--topology cgal: the image affine shears the voxel axes (voxel axes " << i << " and " << j
           << " are not orthogonal, cosine " << c
           << " > 1e-3, more than rounding); resample the image to an orthogonal grid";
        throw InputError(os.str());
      }
    }
  }
  CgalCriteria c;
  c.max_axis_cosine = max_cosine;
  c.voxel_size_m = s.minCoeff();
  const double h = c.voxel_size_m;
  c.facet_angle_deg = options.facet_angle_deg;
  if (!std::isfinite(c.facet_angle_deg) || !(c.facet_angle_deg > 0.0) || c.facet_angle_deg > 30.0) {
    std::ostringstream os;
    os << "--cgal-facet-angle: must lie in (0, 30] degrees (Mesh_3 may not terminate above 30), got "
       << c.facet_angle_deg;
    throw InputError(os.str());
  }
  c.facet_size_m = options.facet_size_m.value_or(2.0 * h);
  require_positive(c.facet_size_m, "--cgal-facet-size");
  c.facet_distance_m = options.facet_distance_m.value_or(0.5 * h);
  require_positive(c.facet_distance_m, "--cgal-facet-distance");
  c.cell_size_m = options.cell_size_m.value_or(2.0 * h);
  require_positive(c.cell_size_m, "--cgal-cell-size");
  c.cell_radius_edge_ratio = options.cell_radius_edge_ratio;
  if (!std::isfinite(c.cell_radius_edge_ratio) || c.cell_radius_edge_ratio < 2.0) {
    std::ostringstream os;
    os << "--cgal-cell-ratio: the radius-edge ratio must be a number >= 2 (Mesh_3 may not terminate below), got "
       << c.cell_radius_edge_ratio;
    throw InputError(os.str());
  }
  if (options.max_smoothing_iterations < 1) throw InputError("mesh_cgal: max_smoothing_iterations must be >= 1");
  if (options.min_node_elements != 0 && (options.min_node_elements < 2 || options.min_node_elements > 4)) {
    throw InputError(
        "--cgal-min-node-elements: give 2, 3 or 4 (3 removes the surface nodes in one or two elements), "
        "or 0 for none; got " +
        std::to_string(options.min_node_elements));
  }
  return c;
}

CgalMeshResult mesh_cgal(const LabelImage& image, const CgalMeshOptions& options) {
  const NotSolid not_solid = solid_labels(image, options);
  CgalMeshResult result;
  result.criteria = resolve_cgal_criteria(image.grid, options);
  const CgalCriteria& crit = result.criteria;
  const double h = crit.voxel_size_m;

  const PaddedImage padded = pad(image);
  const LocalFrame frame = local_frame(image.grid, h);
  const CGAL::Image_3 image_3 = cgal_image(padded, frame);

  // Determinism: CGAL's global generator (used by Mesh_3's random points on spheres) and the
  // domain's own generator both start from the seed.
  CGAL::get_default_random() = CGAL::Random(options.seed);
  CGAL::Random domain_rng(options.seed);
  namespace p = CGAL::parameters;
  const Domain domain = Domain::create_labeled_image_mesh_domain(image_3, p::value_outside = 0, p::p_rng = &domain_rng,
                                                                 p::null_subdomain_index = not_solid);

  const Criteria criteria(p::facet_angle = crit.facet_angle_deg, p::facet_size = crit.facet_size_m / h,
                          p::facet_distance = crit.facet_distance_m / h,
                          p::cell_radius_edge_ratio = crit.cell_radius_edge_ratio, p::cell_size = crit.cell_size_m / h);

  const auto t = Clock::now();
  C3t3 c3t3;
  result.initial_points = insert_seed_points(c3t3, domain, padded, frame, not_solid);
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_perturb(), p::no_exude(), p::no_odt(), p::no_lloyd(),
                      p::no_reset_c3t3());
  result.refine_seconds = since(t);
  optimise(c3t3, domain, options, result);

  Mesh& mesh = result.mesh;
  mesh.type = ElementType::Tet4;
  const NodeOf node_of = extract_nodes(c3t3, frame, mesh);
  extract_elements(c3t3, node_of, not_solid, result);
  if (options.min_node_elements > 0) {
    result.weak_nodes = remove_weak_nodes(mesh, result.patches, options.min_node_elements);
    const WeakNodeReport& w = *result.weak_nodes;
    mesh.attributes["cgal_weak_node_repair"] =
        "min_node_elements=" + std::to_string(w.min_elements) + " rounds=" + std::to_string(w.rounds) +
        " elements_removed=" + std::to_string(w.elements_removed) +
        " nodes_removed=" + std::to_string(w.nodes_removed) + " volume_fraction=" + std::to_string(w.volume_fraction);
  }
  // Mesh_3's vertex order is close to random in space; renumbered for the solver's memory locality
  // (locality_order.hpp: Jacobian assemblies on the coarse biv-me heart 47 % shorter).
  renumber_for_locality(mesh, &result.patches);
  mesh.voxel_size_m = h;
  mesh.attributes["topology"] = "cgal";
  mesh.attributes["cgal_criteria"] = criteria_attribute(crit, options);
  return result;
}

}  // namespace adamss::preprocess
