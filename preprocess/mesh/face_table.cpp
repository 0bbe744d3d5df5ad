#include "preprocess/mesh/face_table.hpp"

#include <algorithm>

#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {

std::vector<FaceRecord> sorted_face_records(const Mesh& mesh) {
  const bool tet = is_tetrahedron(mesh.type);
  const int faces_per = tet ? 4 : 6;
  std::vector<FaceRecord> faces;
  faces.reserve(mesh.element_count() * static_cast<std::size_t>(faces_per));
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const Index* n = mesh.element(e);
    for (int f = 0; f < faces_per; ++f) {
      FaceRecord r{};
      if (tet) {
        const auto& lf = kTetFaces[static_cast<std::size_t>(f)];
        r.key = {n[lf[0]], n[lf[1]], n[lf[2]], -1};
      } else {
        const auto& lf = kHexFaces[static_cast<std::size_t>(f)];
        r.key = {n[lf[0]], n[lf[1]], n[lf[2]], n[lf[3]]};
      }
      std::sort(r.key.begin(), r.key.end());
      // A face with fewer than three distinct nodes has no area (the collapsed face of a
      // degenerate hexahedron, e.g. the apex wedges of preprocess/meshers/ellipsoid_mesh.hpp): not a face.
      int distinct = 0;
      for (std::size_t a = 0; a < 4; ++a) distinct += r.key[a] >= 0 && (a == 0 || r.key[a] != r.key[a - 1]) ? 1 : 0;
      if (distinct < 3) continue;
      r.element = static_cast<std::uint32_t>(e);
      r.local = static_cast<std::uint8_t>(f);
      faces.push_back(r);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const FaceRecord& a, const FaceRecord& b) {
    return a.key != b.key ? a.key < b.key : a.element < b.element;
  });
  return faces;
}

}  // namespace adamss::preprocess
