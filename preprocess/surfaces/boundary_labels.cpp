#include "preprocess/surfaces/boundary_labels.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/face_table.hpp"

namespace adamss::preprocess {

std::int32_t label_at(const LabelImage& image, const Eigen::Vector3d& x, std::int32_t outside) {
  const Eigen::Vector3d ijk = image.grid.to_index(x);
  std::array<std::int64_t, 3> q{};
  for (int c = 0; c < 3; ++c) {
    q[static_cast<std::size_t>(c)] = static_cast<std::int64_t>(std::llround(ijk[c]));
    if (q[static_cast<std::size_t>(c)] < 0 ||
        q[static_cast<std::size_t>(c)] >= image.grid.dims[static_cast<std::size_t>(c)])
      return outside;
  }
  return image.at(q[0], q[1], q[2]);
}

std::vector<BoundaryFace> boundary_faces_with_labels(const Mesh& mesh, const LabelImage& image) {
  const std::vector<FaceRecord> recs = sorted_face_records(mesh);
  const double d = 0.25 * image.grid.spacing().minCoeff();
  const bool tet = is_tetrahedron(mesh.type);
  std::vector<BoundaryFace> out;
  for (std::size_t k = 0; k < recs.size();) {
    std::size_t m = k + 1;
    while (m < recs.size() && recs[m].key == recs[k].key) ++m;
    if (m - k == 1) {
      const FaceRecord& r = recs[k];
      BoundaryFace f;
      f.element = r.element;
      f.local = r.local;
      const Index* en = mesh.element(r.element);
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      Eigen::Vector3d area = Eigen::Vector3d::Zero();
      if (tet) {
        for (int a = 0; a < 3; ++a)
          f.nodes[static_cast<std::size_t>(a)] = en[kTetFaces[r.local][static_cast<std::size_t>(a)]];
        const Eigen::Vector3d x0 = mesh.nodes.col(f.nodes[0]), x1 = mesh.nodes.col(f.nodes[1]),
                              x2 = mesh.nodes.col(f.nodes[2]);
        c = (x0 + x1 + x2) / 3.0;
        area = 0.5 * (x1 - x0).cross(x2 - x0);
      } else {
        for (int a = 0; a < 4; ++a)
          f.nodes[static_cast<std::size_t>(a)] = en[kHexFaces[r.local][static_cast<std::size_t>(a)]];
        Eigen::Vector3d xs[4];
        for (int a = 0; a < 4; ++a) xs[a] = mesh.nodes.col(f.nodes[static_cast<std::size_t>(a)]);
        c = 0.25 * (xs[0] + xs[1] + xs[2] + xs[3]);
        area = 0.5 * (xs[2] - xs[0]).cross(xs[3] - xs[1]);
      }
      f.inside_label = mesh.labels[r.element];
      const double an = area.norm();
      f.outside_label = an > 0.0 ? label_at(image, c + d * area / an, 0) : 0;
      out.push_back(f);
    }
    k = m;
  }
  return out;
}

}  // namespace adamss::preprocess
