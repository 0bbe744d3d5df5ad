// adamss info FILE [--json]: what an image or a mesh holds.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "preprocess/surfaces/cavities.hpp"

namespace adamss::app {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

json bbox_json(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return json{{"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}};
}

/// What every image kind shares: dims, spacing, affine, header notes, world bounding box.
json grid_json(const std::string& path, const preprocess::Grid& g, const preprocess::NiftiNotes& notes) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1) ? static_cast<double>(g.dims[0]) - 0.5 : -0.5,
                                 (c & 2) ? static_cast<double>(g.dims[1]) - 0.5 : -0.5,
                                 (c & 4) ? static_cast<double>(g.dims[2]) - 0.5 : -0.5);
    const Eigen::Vector3d w = g.to_world(corner);
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  }
  json affine = json::array();
  for (int r = 0; r < 4; ++r)
    affine.push_back({g.index_to_world(r, 0), g.index_to_world(r, 1), g.index_to_world(r, 2), g.index_to_world(r, 3)});
  const Eigen::Vector3d sp = g.spacing();
  return json{{"path", path},
              {"dims", {g.dims[0], g.dims[1], g.dims[2]}},
              {"spacing_m", {sp[0], sp[1], sp[2]}},
              {"voxel_volume_m3", g.voxel_volume()},
              {"affine_m", affine},
              {"affine_source", notes.affine_source},
              {"units", notes.units},
              {"datatype", notes.datatype},
              {"nifti_version", notes.nifti_version},
              {"bounding_box_m", bbox_json(lo, hi)},
              {"warnings", notes.warnings}};
}

/// A fibre/sheet field: how many voxels hold a vector, unit length or not, NaN.
json vector_json(const preprocess::VectorImage& img) {
  std::int64_t zero = 0, nan = 0, unit = 0, set = 0;
  double lo = 0.0, hi = 0.0;
  for (Eigen::Index v = 0; v < img.vectors.cols(); ++v) {
    const Eigen::Vector3d x = img.vectors.col(v).cast<double>();
    if (!x.allFinite()) {
      ++nan;
      continue;
    }
    const double n = x.norm();
    if (n == 0.0) {
      ++zero;
      continue;
    }
    lo = set == 0 ? n : std::min(lo, n);
    hi = set == 0 ? n : std::max(hi, n);
    ++set;
    if (std::abs(n - 1.0) <= 1e-3) ++unit;
  }
  return json{{"voxels_with_vector", set},
              {"unit_length_voxels", unit},
              {"zero_voxels", zero},
              {"nan_voxels", nan},
              {"min_norm", lo},
              {"max_norm", hi}};
}

/// A scalar field (scar, fibrosis, probability): range and NaN count.
json scalar_json(const preprocess::ScalarImage& img) {
  std::int64_t nan = 0, nonzero = 0, finite = 0;
  double lo = 0.0, hi = 0.0;
  for (const double v : img.values) {
    if (std::isnan(v)) {
      ++nan;
      continue;
    }
    lo = finite == 0 ? v : std::min(lo, v);
    hi = finite == 0 ? v : std::max(hi, v);
    ++finite;
    if (v != 0.0) ++nonzero;
  }
  return json{{"min", lo}, {"max", hi}, {"nonzero_voxels", nonzero}, {"nan_voxels", nan}};
}

/// A label image, else a vector image (fibres: dims (nx, ny, nz, 1, 3)), else a scalar image
/// (non-integral values); the label reader's error when none of the three reads it.
json image_info(const std::string& path) {
  using namespace preprocess;
  const auto t0 = Clock::now();
  NiftiNotes notes;
  const auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  try {
    const LabelImage img = read_label_image(path, &notes, LabelScaling::kApply);
    json j = grid_json(path, img.grid, notes);
    json labels = json::object();
    for (const auto& [label, count] : img.histogram()) labels[std::to_string(label)] = count;
    j["kind"] = "image";
    j["labels"] = labels;
    j["read_seconds"] = seconds();
    return j;
  } catch (const InputError& as_labels) {
    try {
      notes = NiftiNotes{};
      const VectorImage img = read_vector_image(path, &notes);
      json j = grid_json(path, img.grid, notes);
      j["kind"] = "vector_image";
      j["vectors"] = vector_json(img);
      j["read_seconds"] = seconds();
      return j;
    } catch (const InputError&) {
    }
    try {
      notes = NiftiNotes{};
      const ScalarImage img = read_scalar_image(path, &notes);
      json j = grid_json(path, img.grid, notes);
      j["kind"] = "scalar_image";
      j["values"] = scalar_json(img);
      j["read_seconds"] = seconds();
      return j;
    } catch (const InputError&) {
    }
    throw;
  }
}

json mesh_info(const std::string& path) {
  using namespace preprocess;
  const auto t0 = Clock::now();
  const Mesh mesh = read_mesh_file(path);
  const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
  const QualitySummary q = summarize_quality(mesh);
  std::map<std::int32_t, std::int64_t> hist;
  for (std::int32_t l : mesh.labels) ++hist[l];
  json labels = json::object();
  for (const auto& [label, count] : hist) labels[std::to_string(label)] = count;
  json tags = json::object();
  for (const auto& [name, nodes] : mesh.node_tags) tags[name] = nodes.size();
  json cavities = json::object();
  for (const auto& [name, c] : mesh.cavities) {
    const CavityCheck ck = check_cavity(c);
    cavities[name] = json{{"volume_m3", c.volume_m3},
                          {"volume_ml", c.volume_m3 * 1e6},
                          {"volume_recomputed_m3", cavity_volume(c, mesh.nodes)},
                          {"closed", c.closed},
                          {"faces", c.faces.size() + c.quads.size()},
                          {"quads", c.quads.size()},
                          {"lid_faces", c.lid.size()},
                          {"open_edges", ck.open_edges},
                          {"nonmanifold_edges", ck.nonmanifold_edges}};
  }
  json fields = json::object();
  for (const auto& [name, v] : mesh.cell_scalars) {
    double lo = 0.0, hi = 0.0;
    std::size_t nan = 0;
    bool any = false;
    for (Eigen::Index e = 0; e < v.size(); ++e) {
      if (std::isnan(v[e])) {
        ++nan;
        continue;
      }
      lo = any ? std::min(lo, v[e]) : v[e];
      hi = any ? std::max(hi, v[e]) : v[e];
      any = true;
    }
    fields[name] = json{{"min", lo}, {"max", hi}, {"nan_elements", nan}};
  }
  const ConformityReport conf = check_conformity(mesh);
  double vmin = 0.0, vmax = 0.0;
  if (!q.element_volume.empty()) {
    const auto [a, b] = std::minmax_element(q.element_volume.begin(), q.element_volume.end());
    vmin = *a;
    vmax = *b;
  }
  const json quality{{"min_dihedral_deg", q.min_dihedral_deg},
                     {"mean_dihedral_deg", q.mean_dihedral_deg},
                     {"elements_below_10_deg", q.below_10_deg},
                     {"inverted_elements", q.inverted},
                     {"min_element_volume_m3", vmin},
                     {"max_element_volume_m3", vmax},
                     {"boundary_faces", conf.boundary_faces},
                     {"overshared_faces", conf.overshared_faces},
                     {"nonmanifold_edges", conf.nonmanifold_edges},
                     {"nonmanifold_vertices", conf.nonmanifold_vertices},
                     {"boundary_closed_manifold", conf.closed_manifold()},
                     {"boundary_area_m2", conf.boundary_area_m2}};
  json attrs = json::object();
  for (const auto& [k, v] : mesh.attributes) attrs[k] = v;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  if (mesh.node_count() > 0) {
    lo = mesh.nodes.rowwise().minCoeff();
    hi = mesh.nodes.rowwise().maxCoeff();
  }
  return json{{"kind", "mesh"},
              {"path", path},
              {"nodes", mesh.node_count()},
              {"elements", mesh.element_count()},
              {"element_type", element_type_name(mesh.type)},
              {"volume_m3", q.volume_m3},
              {"inverted_elements", q.inverted},
              {"labels", labels},
              {"min_dihedral_deg", q.min_dihedral_deg},
              {"mean_dihedral_deg", q.mean_dihedral_deg},
              {"elements_below_10_deg", q.below_10_deg},
              {"bounding_box_m", bbox_json(lo, hi)},
              {"has_fibres", mesh.has_fibres()},
              {"node_tags", tags},
              {"cavities", cavities},
              {"cell_fields", fields},
              {"quality", quality},
              {"voxel_size_m", mesh.voxel_size_m},
              {"attributes", attrs},
              {"read_seconds", secs}};
}

void print_human(const json& j) {
  std::cout << std::setprecision(6);
  if (j["kind"] == "image") {
    const auto& d = j["dims"];
    const auto& s = j["spacing_m"];
    std::cout << "image " << j["path"].get<std::string>() << " (NIfTI-" << j["nifti_version"].get<int>() << ", "
              << j["datatype"].get<std::string>() << ")\n"
              << "  dims " << d[0] << " x " << d[1] << " x " << d[2] << ", spacing " << s[0].get<double>() * 1e3
              << " x " << s[1].get<double>() * 1e3 << " x " << s[2].get<double>() * 1e3 << " mm ("
              << j["units"].get<std::string>() << ", affine from " << j["affine_source"].get<std::string>() << ")\n";
    for (const auto& [label, count] : j["labels"].items()) {
      std::cout << "  label " << label << ": " << count << " voxels, "
                << count.get<double>() * j["voxel_volume_m3"].get<double>() * 1e9 << " mm^3\n";
    }
    for (const auto& w : j["warnings"]) std::cout << "  warning: " << w.get<std::string>() << "\n";
  } else if (j["kind"] == "vector_image" || j["kind"] == "scalar_image") {
    const auto& d = j["dims"];
    const auto& s = j["spacing_m"];
    const bool vec = j["kind"] == "vector_image";
    std::cout << (vec ? "vector image " : "scalar image ") << j["path"].get<std::string>() << " (NIfTI-"
              << j["nifti_version"].get<int>() << ", " << j["datatype"].get<std::string>() << ")\n"
              << "  dims " << d[0] << " x " << d[1] << " x " << d[2] << ", spacing " << s[0].get<double>() * 1e3
              << " x " << s[1].get<double>() * 1e3 << " x " << s[2].get<double>() * 1e3 << " mm ("
              << j["units"].get<std::string>() << ", affine from " << j["affine_source"].get<std::string>() << ")\n";
    if (vec) {
      const auto& v = j["vectors"];
      std::cout << "  " << v["voxels_with_vector"] << " voxels with a vector (" << v["unit_length_voxels"]
                << " of unit length, norms " << v["min_norm"].get<double>() << " to " << v["max_norm"].get<double>()
                << "), " << v["zero_voxels"] << " zero, " << v["nan_voxels"] << " NaN\n";
    } else {
      const auto& v = j["values"];
      std::cout << "  values " << v["min"].get<double>() << " to " << v["max"].get<double>() << ", "
                << v["nonzero_voxels"] << " voxels nonzero, " << v["nan_voxels"] << " NaN\n";
    }
    for (const auto& w : j["warnings"]) std::cout << "  warning: " << w.get<std::string>() << "\n";
  } else {
    std::cout << "mesh " << j["path"].get<std::string>() << "\n"
              << "  " << j["nodes"] << " nodes, " << j["elements"] << " " << j["element_type"].get<std::string>()
              << " elements, volume " << j["volume_m3"].get<double>() * 1e9 << " mm^3, " << j["inverted_elements"]
              << " inverted\n"
              << "  dihedral angle: min " << j["min_dihedral_deg"].get<double>() << " deg, mean of element minima "
              << j["mean_dihedral_deg"].get<double>() << " deg, " << j["elements_below_10_deg"]
              << " elements under 10 deg\n";
    const json& qj = j["quality"];
    std::cout << "  element volume: min " << qj["min_element_volume_m3"].get<double>() * 1e9 << " mm^3, max "
              << qj["max_element_volume_m3"].get<double>() * 1e9 << " mm^3\n"
              << "  boundary: " << qj["boundary_faces"] << " faces, area " << qj["boundary_area_m2"].get<double>() * 1e6
              << " mm^2, "
              << (qj["boundary_closed_manifold"].get<bool>() ? "closed 2-manifold" : "NOT a closed 2-manifold") << " ("
              << qj["nonmanifold_edges"] << " non-manifold edges, " << qj["nonmanifold_vertices"]
              << " non-manifold vertices)\n"
              << "  fibres: " << (j["has_fibres"].get<bool>() ? "yes" : "no") << "\n";
    for (const auto& [label, count] : j["labels"].items())
      std::cout << "  label " << label << ": " << count << " elements\n";
    for (const auto& [name, n] : j["node_tags"].items()) std::cout << "  node tag " << name << ": " << n << " nodes\n";
    for (const auto& [name, c] : j["cavities"].items()) {
      std::cout << "  cavity " << name << ": " << c["faces"] << " wall faces"
                << (c["quads"].get<std::size_t>() > 0 ? " (quads)" : "") << ", " << c["lid_faces"]
                << " lid faces, volume " << c["volume_ml"].get<double>() << " ml ("
                << c["volume_m3"].get<double>() * 1e9 << " mm^3), " << (c["closed"].get<bool>() ? "closed" : "OPEN");
      if (c["nonmanifold_edges"].get<std::size_t>() > 0)
        std::cout << ", " << c["nonmanifold_edges"] << " edges in more than two faces";
      std::cout << "\n";
    }
    for (const auto& [name, f] : j["cell_fields"].items()) {
      std::cout << "  cell field " << name << ": min " << f["min"].get<double>() << ", max " << f["max"].get<double>();
      if (f["nan_elements"].get<std::size_t>() > 0) std::cout << ", " << f["nan_elements"] << " NaN";
      std::cout << "\n";
    }
    if (j["attributes"].contains("meshing_seconds")) {
      std::cout << "  meshing time: " << j["attributes"]["meshing_seconds"].get<std::string>() << " s\n";
    }
  }
}

struct InfoArgs {
  std::string file;
  bool as_json = false;
};

void run_info(const InfoArgs& a) {
  if (!std::filesystem::exists(a.file)) throw InputError("cannot open '" + a.file + "': no such file");
  json j;
  if (ends_with(a.file, ".nii") || ends_with(a.file, ".nii.gz")) {
    j = image_info(a.file);
  } else if (ends_with(a.file, ".h5") || ends_with(a.file, ".vtu") || ends_with(a.file, ".msh") ||
             ends_with(a.file, ".xdmf") || ends_with(a.file, ".xmf")) {
    j = mesh_info(a.file);
  } else {
    throw InputError(
        "'" + a.file +
        "': unknown kind of file (expected .nii, .nii.gz, mesh .h5, a .vtu grid, a gmsh .msh or an .xdmf mesh)");
  }
  if (a.as_json) {
    std::cout << j.dump(2) << "\n";
  } else {
    print_human(j);
  }
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* sub = app.add_subcommand("info",
                                     "Summarise an image (.nii/.nii.gz) or a mesh (.h5): counts, bounding box, "
                                     "volume, labels, element quality.");
  sub->add_option("file", args->file, "Image or mesh file")->required();
  sub->add_flag("--json", args->as_json, "Print machine-readable JSON (keys documented in docs/file-formats.md)");
  sub->callback([args]() { run_info(*args); });
}

}  // namespace adamss::app
