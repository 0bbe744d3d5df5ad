#pragma once
// Label smoothing before meshing (issue 20 item 1, "optional smoothing"): a clinical segmentation
// at 1 mm carries strands one voxel thick that touch the rest only along voxel edges or corners
// (the staircase at the base of the biv-me heart). A mesher resolves them with elements far below
// the requested size, and such a fin of a few small tetrahedra is a near-mechanism of the mesh: on
// the biv-me filling one of its local stiffness eigenvalues crossed zero near LV 0.42 kPa, where
// Newton stalled (cases/anatomy/README.md). Smoothing each label's signed distance removes them:
//
//   d_l(x)  = D(x, {label l}) - D(x, {not label l})     (m; < 0 inside l; resample.hpp's transform)
//   d~_l    = G_sigma * d_l                              separable Gaussian, sigma (m) per axis
//                                                        sigma / h_axis voxels, truncated at 3 sigma,
//                                                        the edge voxel repeated beyond the image
//   label(x) = argmin_l d~_l(x)
//
// What survives, for sigma = 0.7 voxel (computed from the kernel weights, tested): a flat wall one
// voxel thick stays (its centre's smoothed distance -0.13 voxel), a strand of voxels joined only
// diagonally goes (+0.45 voxel), a convex region shrinks by about sigma^2 / R (the Laplacian of
// the distance to a sphere of radius R is 2 / R): 0.03 mm on a 15 mm ventricle for sigma 0.7 mm.
// A larger sigma removes thicker features: sigma = 1 voxel already deletes one-voxel walls.
#include <cstdint>
#include <map>

#include "preprocess/image/image.hpp"

namespace adamss::preprocess {

struct SmoothReport {
  double sigma_m = 0.0;
  std::int64_t changed_voxels = 0;                                   ///< voxels whose label changed
  std::map<std::int32_t, std::int64_t> voxels_before, voxels_after;  ///< per label
  double seconds = 0.0;
};

/// Smooths the labels of `image` in place (above). InputError for sigma not finite or <= 0 or an
/// empty image.
SmoothReport smooth_labels(LabelImage& image, double sigma_m);

}  // namespace adamss::preprocess
