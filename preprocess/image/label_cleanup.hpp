#pragma once
// Label-image clean-up before meshing (issue 20 item 1): segmentations of clinical images carry
// islands (a myocardium fragment apart from the wall, a papillary muscle cut off in the blood
// pool) and holes (background voxels enclosed by the heart). A mesher turns every island into a
// free-floating part that no boundary condition holds, and rule-based fibres need every part to
// lie between a cavity and the outside. clean_labels:
//   1. keeps the largest 6-connected component of the solid labels (all solid labels together);
//      every other component takes the label most frequent among its outside face neighbours
//      (e.g. the blood pool around a papillary island; the background for an outlying fragment);
//   2. fills every 6-connected component of label 0 that does not touch the image border (a hole)
//      with the label most frequent among its face neighbours.
#include <cstdint>
#include <vector>

#include "preprocess/image/image.hpp"

namespace adamss::preprocess {

struct LabelCleanupReport {
  std::size_t solid_components = 0;    ///< before the clean-up
  std::int64_t largest_voxels = 0;     ///< the component kept
  std::int64_t relabelled_voxels = 0;  ///< solid voxels of the other components
  std::size_t holes = 0;               ///< enclosed background components filled
  std::int64_t filled_voxels = 0;
};

/// Cleans `image` in place (above). InputError when no voxel carries a solid label.
LabelCleanupReport clean_labels(LabelImage& image, const std::vector<std::int32_t>& solid_labels);

}  // namespace adamss::preprocess
