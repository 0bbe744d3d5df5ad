#pragma once
// Fibre, sheet and normal per element from vector images on the label lattice.
//
// At each element barycentre the fibre image is sampled trilinearly from the
// eight surrounding voxel centres. Fibres are axes, not arrows (f and -f are the
// same material direction), so every sample is first flipped to agree with the
// sample of the nearest valid voxel before averaging. Zero, NaN and infinite
// samples carry no weight and the remaining weights are renormalised. The sheet
// is sampled the same way, then made orthogonal to the fibre (Gram-Schmidt) and
// the normal is n = f x s, so (f, s, n) is a right-handed orthonormal frame.
//
// An element with no valid sample (or whose sheet is parallel to its fibre) is
// invalid: with `strict` that is an error naming the element; otherwise its frame
// is copied (sign-aligned average) from valid face-neighbours, repeatedly, until
// every element has one.
#include <cstddef>
#include <string>
#include <vector>

#include "preprocess/image/image.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

struct FibreReport {
  std::size_t invalid_samples = 0;           ///< zero/NaN voxel vectors met while sampling
  std::size_t filled_elements = 0;           ///< elements whose frame came from neighbours
  std::vector<std::size_t> filled_examples;  ///< up to 10 of them
};

/// Samples `fiber` and `sheet` (which must share the label image's lattice:
/// same dims and affine, else InputError naming the file) at each element
/// barycentre and stores fiber/sheet/normal in the mesh.
FibreReport assign_fibres(Mesh& mesh, const Grid& label_grid, const VectorImage& fiber, const std::string& fiber_name,
                          const VectorImage& sheet, const std::string& sheet_name, bool strict);

/// Barycentre (mean of the element's nodes) of element e, metres.
Eigen::Vector3d element_barycentre(const Mesh& mesh, std::size_t e);

/// Trilinear, sign-aligned sample of a direction image at a world point.
/// Returns false (and leaves `out` unchanged) when no valid voxel contributes.
bool sample_direction(const VectorImage& image, const Eigen::Vector3d& x_m, Eigen::Vector3d& out,
                      std::size_t* invalid_samples = nullptr);

}  // namespace adamss::preprocess
