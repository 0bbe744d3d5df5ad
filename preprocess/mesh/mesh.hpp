#pragma once
// The mesh data model every layer shares (written to mesh.h5, read by the solver).
// Structure of arrays: nodes as a 3xN matrix (metres), connectivity as one flat
// index array, per-element fields as 3xE matrices. Node order within an element
// follows VTK (VTK_TETRA, VTK_HEXAHEDRON) and every element has positive volume.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace adamss::preprocess {

using Index = std::int32_t;

/// Tet10 (the quadratic tetrahedron, VTK_QUADRATIC_TETRA: corners 0..3, then the mid-edge nodes
/// of kTetEdges) is made from a Tet4 mesh by preprocess/mesh/quadratic.hpp; the corner nodes keep
/// their numbers and the mid-edge nodes come after them. Only the solver's FEM path takes it
/// (fem_element, volume isotropic, pressure loads, boundary conditions, output); the other
/// terms and the preprocessing refuse it by name.
/// Hex27 (the triquadratic hexahedron, VTK_TRIQUADRATIC_HEXAHEDRON: corners 0..7, the mid-edge
/// nodes of kHexEdges, the six face centres, the centre; preprocess/mesh/shape_functions_q2.hpp) is
/// made from a Hex8 mesh the same way and takes the same FEM path.
enum class ElementType { Tet4, Hex8, Tet10, Hex27 };

[[nodiscard]] constexpr int nodes_per_element(ElementType t) {
  switch (t) {
    case ElementType::Tet4:
      return 4;
    case ElementType::Hex8:
      return 8;
    case ElementType::Tet10:
      return 10;
    case ElementType::Hex27:
      return 27;
  }
  return 0;
}
/// The element's corners (vertices): 4 for both tetrahedra, 8 for both hexahedra.
[[nodiscard]] constexpr int corners_per_element(ElementType t) {
  return t == ElementType::Hex8 || t == ElementType::Hex27 ? 8 : 4;
}
[[nodiscard]] constexpr bool is_tetrahedron(ElementType t) {
  return t == ElementType::Tet4 || t == ElementType::Tet10;
}
/// The quadratic elements (tet10, hex27): only the solver's FEM path takes them.
[[nodiscard]] constexpr bool is_quadratic(ElementType t) {
  return t == ElementType::Tet10 || t == ElementType::Hex27;
}
[[nodiscard]] constexpr const char* element_type_name(ElementType t) {
  switch (t) {
    case ElementType::Tet4:
      return "tet4";
    case ElementType::Hex8:
      return "hex8";
    case ElementType::Tet10:
      return "tet10";
    case ElementType::Hex27:
      return "hex27";
  }
  return "?";
}

/// A closed surface bounding a cavity (built by preprocess/surfaces/cavities.hpp). Every face and
/// lid triangle is ordered so that its vector area points INTO the cavity (for wall faces:
/// outward of the solid). Tetrahedral meshes give wall triangles, hexahedral meshes wall
/// quads (VTK quad order, bilinear); the lid is always triangles and carries no load.
struct Cavity {
  std::vector<std::array<Index, 3>> faces;  ///< wall triangles, normals into the cavity
  std::vector<std::array<Index, 4>> quads;  ///< wall quads (hex meshes), normals into the cavity
  std::vector<std::array<Index, 3>> lid;    ///< closing triangles (not part of the wall)
  double volume_m3 = 0.0;                   ///< reference volume (divergence theorem over faces + quads + lid)
  bool closed = false;                      ///< every edge's two orientations cancel (watertight)
};

struct Mesh {
  ElementType type = ElementType::Tet4;
  Eigen::Matrix3Xd nodes;            ///< positions in metres, column = node
  std::vector<Index> connectivity;   ///< nodes_per_element(type) entries per element
  std::vector<std::int32_t> labels;  ///< image label per element
  Eigen::Matrix3Xd fiber;            ///< unit fibre per element (0 columns if none)
  Eigen::Matrix3Xd sheet;            ///< unit sheet, orthogonal to fibre
  Eigen::Matrix3Xd normal;           ///< fibre x sheet
  std::map<std::string, std::vector<Index>> node_tags;
  std::map<std::string, Eigen::VectorXd> cell_scalars;  ///< extra per-element fields
  std::map<std::string, Cavity> cavities;
  std::map<std::string, std::string> attributes;  ///< source, topology, version, ...
  double voxel_size_m = 0.0;                      ///< source lattice spacing (0 if none)

  [[nodiscard]] std::size_t node_count() const { return static_cast<std::size_t>(nodes.cols()); }
  [[nodiscard]] std::size_t element_count() const {
    return connectivity.size() / static_cast<std::size_t>(nodes_per_element(type));
  }
  [[nodiscard]] const Index* element(std::size_t e) const {
    return connectivity.data() + e * static_cast<std::size_t>(nodes_per_element(type));
  }
  [[nodiscard]] bool has_fibres() const { return fiber.cols() > 0; }
};

}  // namespace adamss::preprocess
