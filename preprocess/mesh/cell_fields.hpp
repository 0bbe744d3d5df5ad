#pragma once
// Per-voxel fields sampled to elements (`adamss mesh --cell-field NAME=IMAGE[:nearest|:trilinear]`),
// stored as mesh.cell_scalars[NAME] (mesh.h5 /elements/scalars/NAME, .vtu cell data NAME).
//
// The field image may have any lattice (it need not match the label image): each element
// barycentre x (mean of its nodes, metres, world frame) is mapped to continuous voxel
// coordinates q = A^-1 (x - t) of the field image (A, t its affine), and
//   nearest    the value of voxel round(q) (ties round away from zero: std::llround).
//              Right for label-like fields (a scar label); never invents values.
//   trilinear  the weighted mean of the 8 voxel centres around q with the usual trilinear
//              weights. Right for smooth fields (a stiffness map); reproduces a field that
//              is linear in the voxel indices exactly (weights within 1e-9 of 0 or 1 are
//              snapped, so a voxel centre takes exactly its voxel's value). NaN voxels carry no weight and the
//              other weights are renormalised; if all 8 are NaN the sample is NaN.
// Points within half a voxel outside the outermost voxel centres (still inside the image's
// voxel boxes) are clamped to the border voxels (constant extrapolation). A barycentre
// outside the image's voxel boxes (some q_c outside [-1/2, n_c - 1/2], with a slack of 1e-6
// voxel) is an InputError naming the field, the count and the first element.
// Default interpolation: nearest.
#include <cstddef>
#include <string>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

enum class Interpolation { Nearest, Trilinear };

struct CellFieldSpec {
  std::string name;
  std::string file;
  Interpolation method = Interpolation::Nearest;
};

/// Parses "NAME=FILE[:nearest|:trilinear]". The suffix is recognised only when it is exactly
/// one of the two words, so file names with ':' still work. InputError naming `option`.
[[nodiscard]] CellFieldSpec parse_cell_field_spec(const std::string& text, const std::string& option = "--cell-field");

[[nodiscard]] const char* interpolation_name(Interpolation m);

struct CellFieldReport {
  std::size_t nan_elements = 0;  ///< elements whose sample is NaN (NaN voxels only)
  std::size_t clamped = 0;       ///< barycentres in the half-voxel border (clamped)
  double min = 0.0, max = 0.0;   ///< over the finite samples (0 if none)
};

/// Samples `image` at every element barycentre of `mesh`. `what` names the field in errors.
[[nodiscard]] Eigen::VectorXd sample_cell_field(const Mesh& mesh, const ScalarImage& image, Interpolation method,
                                                const std::string& what, CellFieldReport* report = nullptr);

/// sample_cell_field into mesh.cell_scalars[name]. InputError if the name is taken, not a
/// usable HDF5 name, or one of the .vtu's own cell arrays (label, volume, quality, fiber,
/// sheet, normal).
CellFieldReport add_cell_field(Mesh& mesh, const std::string& name, const ScalarImage& image, Interpolation method);

}  // namespace adamss::preprocess
