#include "preprocess/fibres/fibre_field.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/face_table.hpp"

namespace adamss::preprocess {
namespace {

bool valid(const Eigen::Vector3f& v) {
  return v.allFinite() && v.squaredNorm() > 1e-12f;
}

void require_same_lattice(const Grid& label, const Grid& img, const std::string& name) {
  if (label.dims != img.dims) {
    std::ostringstream os;
    os << name << ": dimensions " << img.dims[0] << "x" << img.dims[1] << "x" << img.dims[2]
       << " differ from the label image's " << label.dims[0] << "x" << label.dims[1] << "x" << label.dims[2];
    throw InputError(os.str());
  }
  const double scale = label.index_to_world.topLeftCorner<3, 3>().norm();
  if ((label.index_to_world - img.index_to_world).norm() > 1e-6 * scale) {
    throw InputError(name + ": its affine (voxel-to-world transform) differs from the label image's");
  }
}

/// Face-adjacency of elements (-1 where a face is on the boundary).
std::vector<std::array<std::int64_t, 6>> face_neighbours(const Mesh& mesh) {
  const std::vector<FaceRecord> faces = sorted_face_records(mesh);
  std::vector<std::array<std::int64_t, 6>> nb(mesh.element_count());
  for (auto& a : nb) a.fill(-1);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    if (faces[i].key != faces[i + 1].key) continue;
    const FaceRecord& a = faces[i];
    const FaceRecord& b = faces[i + 1];
    nb[a.element][a.local] = b.element;
    nb[b.element][b.local] = a.element;
  }
  return nb;
}

/// Orthonormal frame from a fibre and a sheet guess; false if degenerate.
bool make_frame(const Eigen::Vector3d& f_in, const Eigen::Vector3d& s_in, Eigen::Vector3d& f, Eigen::Vector3d& s,
                Eigen::Vector3d& n) {
  const double fn = f_in.norm();
  if (!(fn > 1e-12)) return false;
  f = f_in / fn;
  Eigen::Vector3d t = s_in - s_in.dot(f) * f;
  const double tn = t.norm();
  if (!(tn > 1e-6 * std::max(1.0, s_in.norm()))) return false;
  s = t / tn;
  n = f.cross(s);
  return true;
}

}  // namespace

Eigen::Vector3d element_barycentre(const Mesh& mesh, std::size_t e) {
  const int k = nodes_per_element(mesh.type);
  const Index* n = mesh.element(e);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int a = 0; a < k; ++a) c += mesh.nodes.col(n[a]);
  return c / k;
}

bool sample_direction(const VectorImage& image, const Eigen::Vector3d& x_m, Eigen::Vector3d& out,
                      std::size_t* invalid_samples) {
  const Grid& g = image.grid;
  const Eigen::Vector3d p = g.to_index(x_m);
  const std::array<std::int64_t, 3> base{static_cast<std::int64_t>(std::floor(p[0])),
                                         static_cast<std::int64_t>(std::floor(p[1])),
                                         static_cast<std::int64_t>(std::floor(p[2]))};
  const Eigen::Vector3d t(p[0] - static_cast<double>(base[0]), p[1] - static_cast<double>(base[1]),
                          p[2] - static_cast<double>(base[2]));
  std::array<Eigen::Vector3d, 8> v;
  std::array<double, 8> w{};
  int nearest = -1;
  double nearest_w = -1.0;
  for (int c = 0; c < 8; ++c) {
    const std::int64_t i = base[0] + (c & 1), j = base[1] + ((c >> 1) & 1), k = base[2] + ((c >> 2) & 1);
    const double wc =
        ((c & 1) ? t[0] : 1.0 - t[0]) * (((c >> 1) & 1) ? t[1] : 1.0 - t[1]) * (((c >> 2) & 1) ? t[2] : 1.0 - t[2]);
    if (!g.contains(i, j, k) || wc <= 0.0) continue;
    const Eigen::Vector3f s = image.vectors.col(static_cast<Eigen::Index>(g.linear(i, j, k)));
    if (!valid(s)) {
      if (invalid_samples) ++*invalid_samples;
      continue;
    }
    v[static_cast<std::size_t>(c)] = s.cast<double>().normalized();
    w[static_cast<std::size_t>(c)] = wc;
    if (wc > nearest_w) {
      nearest_w = wc;
      nearest = c;
    }
  }
  if (nearest < 0) return false;
  const Eigen::Vector3d ref = v[static_cast<std::size_t>(nearest)];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t c = 0; c < 8; ++c) {
    if (w[c] <= 0.0) continue;
    sum += w[c] * (v[c].dot(ref) < 0.0 ? -v[c] : v[c]);
  }
  const double norm = sum.norm();
  if (!(norm > 1e-12)) return false;
  out = sum / norm;
  return true;
}

FibreReport assign_fibres(Mesh& mesh, const Grid& label_grid, const VectorImage& fiber, const std::string& fiber_name,
                          const VectorImage& sheet, const std::string& sheet_name, bool strict) {
  require_same_lattice(label_grid, fiber.grid, fiber_name);
  require_same_lattice(label_grid, sheet.grid, sheet_name);
  FibreReport rep;
  const std::size_t ne = mesh.element_count();
  const auto nel = static_cast<Eigen::Index>(ne);
  mesh.fiber.setZero(3, nel);
  mesh.sheet.setZero(3, nel);
  mesh.normal.setZero(3, nel);
  std::vector<std::uint8_t> ok(ne, 0);
  std::size_t n_bad = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    const Eigen::Vector3d x = element_barycentre(mesh, e);
    Eigen::Vector3d f, s, ff, ss, nn;
    if (sample_direction(fiber, x, f, &rep.invalid_samples) && sample_direction(sheet, x, s, &rep.invalid_samples) &&
        make_frame(f, s, ff, ss, nn)) {
      const auto ei = static_cast<Eigen::Index>(e);
      mesh.fiber.col(ei) = ff;
      mesh.sheet.col(ei) = ss;
      mesh.normal.col(ei) = nn;
      ok[e] = 1;
    } else {
      ++n_bad;
      if (strict) {
        std::ostringstream os;
        os << "--strict: element " << e << " at (" << x[0] * 1e3 << ", " << x[1] * 1e3 << ", " << x[2] * 1e3
           << ") mm has no valid fibre/sheet sample in '" << fiber_name << "' / '" << sheet_name
           << "' (zero, NaN, or sheet parallel to fibre)";
        throw InputError(os.str());
      }
    }
  }
  if (n_bad == ne) {
    throw InputError(fiber_name + ": no element of the mesh has a valid fibre/sheet sample (all zero or NaN?)");
  }
  if (n_bad == 0) return rep;

  // Flood-fill invalid elements from valid face-neighbours, layer by layer.
  const auto nb = face_neighbours(mesh);
  std::vector<std::size_t> pending;
  for (std::size_t e = 0; e < ne; ++e)
    if (!ok[e]) pending.push_back(e);
  while (!pending.empty()) {
    std::vector<std::size_t> next, done;
    for (std::size_t e : pending) {
      Eigen::Vector3d fsum = Eigen::Vector3d::Zero(), ssum = Eigen::Vector3d::Zero();
      Eigen::Vector3d fref = Eigen::Vector3d::Zero(), sref = Eigen::Vector3d::Zero();
      int count = 0;
      for (std::int64_t o : nb[e]) {
        if (o < 0 || !ok[static_cast<std::size_t>(o)]) continue;
        const Eigen::Vector3d fo = mesh.fiber.col(o), so = mesh.sheet.col(o);
        if (count == 0) {
          fref = fo;
          sref = so;
        }
        fsum += fo.dot(fref) < 0 ? Eigen::Vector3d(-fo) : fo;
        ssum += so.dot(sref) < 0 ? Eigen::Vector3d(-so) : so;
        ++count;
      }
      Eigen::Vector3d ff, ss, nn;
      if (count > 0 && make_frame(fsum, ssum, ff, ss, nn)) {
        const auto ei = static_cast<Eigen::Index>(e);
        mesh.fiber.col(ei) = ff;
        mesh.sheet.col(ei) = ss;
        mesh.normal.col(ei) = nn;
        done.push_back(e);
      } else {
        next.push_back(e);
      }
    }
    if (done.empty()) {
      throw InputError(fiber_name + ": " + std::to_string(next.size()) +
                       " elements have no valid fibre sample and no valid neighbour to fill from");
    }
    for (std::size_t e : done) {
      ok[e] = 1;
      ++rep.filled_elements;
      if (rep.filled_examples.size() < 10) rep.filled_examples.push_back(e);
    }
    pending.swap(next);
  }
  return rep;
}

}  // namespace adamss::preprocess
