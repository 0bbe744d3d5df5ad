// The checks every mesh importer shares (mesh_import.hpp): the file exists, fibre frames given
// per cell and the elements' orientation. Compiled into adamss_preprocess and into the VTK module
// (vtk_io.hpp).
#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_import.hpp"

namespace adamss::preprocess {

namespace {

/// Signed volume measure at the element centre (tet: 6 V; hex: det of the centre Jacobian).
double centre_jacobian(const Mesh& mesh, std::size_t e) {
  const Index* n = mesh.element(e);
  Eigen::Matrix3d j;
  if (mesh.type == ElementType::Tet4) {
    for (int k = 0; k < 3; ++k) j.col(k) = mesh.nodes.col(n[k + 1]) - mesh.nodes.col(n[0]);
    return j.determinant();
  }
  static constexpr int kXi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  j.setZero();
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) j.col(d) += mesh.nodes.col(n[a]) * (kXi[a][d] / 8.0);
  return j.determinant();
}

}  // namespace

void set_imported_fibres(Mesh& mesh, const Eigen::Matrix3Xd& fibre, const Eigen::Matrix3Xd& sheet,
                         Eigen::Matrix3Xd normal, const std::string& where, const std::string& no_sheet) {
  if (sheet.cols() == 0) throw InputError(where + ": " + no_sheet);
  if (normal.cols() == 0) {
    normal.resize(3, fibre.cols());
    for (Eigen::Index e = 0; e < fibre.cols(); ++e) normal.col(e) = fibre.col(e).cross(sheet.col(e));
  }
  for (Eigen::Index e = 0; e < fibre.cols(); ++e) {
    const bool unit = std::abs(fibre.col(e).norm() - 1) < 1e-3 && std::abs(sheet.col(e).norm() - 1) < 1e-3 &&
                      std::abs(fibre.col(e).dot(sheet.col(e))) < 1e-3;
    if (!unit) throw InputError(where + ": fiber and sheet of cell " + std::to_string(e) + " are not orthonormal");
  }
  mesh.fiber = fibre;
  mesh.sheet = sheet;
  mesh.normal = std::move(normal);
}

std::string existing_mesh_file(const std::filesystem::path& path) {
  std::string where(1, '\'');  // (not "'" + ...: GCC 12 warns -Wrestrict on that operator+)
  where += path.string();
  where += '\'';
  if (!std::filesystem::exists(path)) throw InputError("cannot open mesh " + where + ": no such file");
  return where;
}

void check_element_orientation(const Mesh& mesh, const std::string& where, const std::string& hint) {
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (!(centre_jacobian(mesh, e) > 0.0)) {
      throw InputError(where + ": element " + std::to_string(e) +
                       " is inverted or degenerate (volume <= 0 at its centre; " + hint + ")");
    }
  }
}

}  // namespace adamss::preprocess
