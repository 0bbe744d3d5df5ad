#include "preprocess/mesh/cell_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/fibres/fibre_field.hpp"

namespace adamss::preprocess {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::int64_t clamp_index(std::int64_t i, std::int64_t n) {
  return std::clamp<std::int64_t>(i, 0, n - 1);
}

}  // namespace

const char* interpolation_name(Interpolation m) {
  return m == Interpolation::Nearest ? "nearest" : "trilinear";
}

CellFieldSpec parse_cell_field_spec(const std::string& text, const std::string& option) {
  const std::string usage = option + " '" + text + "': expected NAME=IMAGE[:nearest|:trilinear]";
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw InputError(usage);
  CellFieldSpec spec;
  spec.name = text.substr(0, eq);
  spec.file = text.substr(eq + 1);
  if (spec.name.empty() || spec.name == "." || spec.name.find('/') != std::string::npos)
    throw InputError(usage + ": the name must be non-empty and must not contain '/'");
  if (ends_with(spec.file, ":nearest")) {
    spec.file.resize(spec.file.size() - 8);
  } else if (ends_with(spec.file, ":trilinear")) {
    spec.method = Interpolation::Trilinear;
    spec.file.resize(spec.file.size() - 10);
  } else if (const auto colon = spec.file.rfind(':'); colon != std::string::npos &&
                                                      spec.file.find('/', colon) == std::string::npos &&
                                                      spec.file.find('.', colon) == std::string::npos) {
    throw InputError(usage + ": unknown interpolation '" + spec.file.substr(colon + 1) + "'");
  }
  if (spec.file.empty()) throw InputError(usage + ": the image file is missing");
  return spec;
}

Eigen::VectorXd sample_cell_field(const Mesh& mesh, const ScalarImage& image, Interpolation method,
                                  const std::string& what, CellFieldReport* report) {
  const Grid& g = image.grid;
  if (image.values.size() != g.voxel_count() || g.voxel_count() == 0) {
    throw InputError(what + ": the image has " + std::to_string(image.values.size()) + " values for " +
                     std::to_string(g.voxel_count()) + " voxels");
  }
  const std::size_t E = mesh.element_count();
  Eigen::VectorXd out(static_cast<Eigen::Index>(E));
  CellFieldReport rep;
  std::size_t outside = 0, first_outside = 0;
  Eigen::Vector3d first_x = Eigen::Vector3d::Zero();
  constexpr double kSlack = 1e-6;
  const Eigen::Matrix3d inv = g.index_to_world.topLeftCorner<3, 3>().inverse();
  const Eigen::Vector3d t = g.index_to_world.topRightCorner<3, 1>();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t e = 0; e < E; ++e) {
    const Eigen::Vector3d x = element_barycentre(mesh, e);
    const Eigen::Vector3d q = inv * (x - t);
    bool in = true, clamped = false;
    for (int c = 0; c < 3; ++c) {
      const double n = static_cast<double>(g.dims[static_cast<std::size_t>(c)]);
      if (q[c] < -0.5 - kSlack || q[c] > n - 0.5 + kSlack) in = false;
      if (q[c] < 0.0 || q[c] > n - 1.0) clamped = true;
    }
    if (!in) {
      if (outside++ == 0) {
        first_outside = e;
        first_x = x;
      }
      continue;
    }
    if (clamped) ++rep.clamped;
    double value = 0.0;
    if (method == Interpolation::Nearest) {
      std::array<std::int64_t, 3> k{};
      for (int c = 0; c < 3; ++c)
        k[static_cast<std::size_t>(c)] = clamp_index(std::llround(q[c]), g.dims[static_cast<std::size_t>(c)]);
      value = image.at(k[0], k[1], k[2]);
    } else {
      std::array<std::int64_t, 3> i0{}, i1{};
      std::array<double, 3> w{};
      for (int c = 0; c < 3; ++c) {
        const auto cs = static_cast<std::size_t>(c);
        const std::int64_t n = g.dims[cs];
        const double qc = std::clamp(q[c], 0.0, static_cast<double>(n - 1));
        const double f = std::floor(qc);
        i0[cs] = clamp_index(static_cast<std::int64_t>(f), n);
        i1[cs] = clamp_index(i0[cs] + 1, n);
        w[cs] = qc - f;
        // Snap rounding noise so that a point on a voxel centre takes exactly that voxel.
        if (w[cs] < 1e-9) w[cs] = 0.0;
        if (w[cs] > 1.0 - 1e-9) w[cs] = 1.0;
      }
      double sum = 0.0, wsum = 0.0;
      for (int corner = 0; corner < 8; ++corner) {
        const std::int64_t a = (corner & 1) ? i1[0] : i0[0];
        const std::int64_t b = (corner & 2) ? i1[1] : i0[1];
        const std::int64_t c = (corner & 4) ? i1[2] : i0[2];
        const double wt = ((corner & 1) ? w[0] : 1.0 - w[0]) * ((corner & 2) ? w[1] : 1.0 - w[1]) *
                          ((corner & 4) ? w[2] : 1.0 - w[2]);
        if (wt == 0.0) continue;
        const double v = image.at(a, b, c);
        if (std::isnan(v)) continue;
        sum += wt * v;
        wsum += wt;
      }
      value = wsum > 0.0 ? sum / wsum : std::numeric_limits<double>::quiet_NaN();
    }
    out[static_cast<Eigen::Index>(e)] = value;
    if (std::isnan(value)) {
      ++rep.nan_elements;
    } else if (std::isfinite(value)) {
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
  }
  if (outside > 0) {
    std::ostringstream os;
    os.precision(6);
    os << what << ": " << outside << " of " << E << " element barycentres lie outside the image (e.g. element "
       << first_outside << " at (" << first_x.x() * 1e3 << ", " << first_x.y() * 1e3 << ", " << first_x.z() * 1e3
       << ") mm); the field image must cover the mesh";
    throw InputError(os.str());
  }
  if (lo <= hi) {
    rep.min = lo;
    rep.max = hi;
  }
  if (report != nullptr) *report = rep;
  return out;
}

CellFieldReport add_cell_field(Mesh& mesh, const std::string& name, const ScalarImage& image, Interpolation method) {
  const std::string what = "cell field '" + name + "'";
  if (name.empty() || name == "." || name.find('/') != std::string::npos)
    throw InputError(what + ": the name must be non-empty and must not contain '/'");
  for (const char* reserved : {"label", "volume", "quality", "fiber", "sheet", "normal"}) {
    if (name == reserved)
      throw InputError(what + ": the name is reserved (label, volume, quality, fiber, sheet, normal are .vtu arrays)");
  }
  if (mesh.cell_scalars.count(name) != 0) throw InputError(what + ": the mesh already has a cell field of that name");
  CellFieldReport rep;
  mesh.cell_scalars.emplace(name, sample_cell_field(mesh, image, method, what, &rep));
  return rep;
}

}  // namespace adamss::preprocess
