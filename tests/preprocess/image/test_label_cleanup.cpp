// Label clean-up (preprocess/image/label_cleanup.hpp) on a synthetic heart: a 3-voxel-thick wall
// (label 1) around a cavity (2), with a papillary island of wall label inside the cavity, a
// fragment of wall label outside the heart, and a background hole inside the wall. After the
// clean-up the island is cavity, the fragment background, the hole wall, and the border background
// and the wall itself are untouched.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "preprocess/image/label_cleanup.hpp"

using namespace adamss::preprocess;

TEST(LabelCleanup, IslandsTakeTheirSurroundingsAndHolesAreFilled) {
  LabelImage im;
  im.grid.dims = {20, 20, 20};
  im.labels.assign(im.grid.voxel_count(), 0);
  const auto set = [&](std::int64_t i, std::int64_t j, std::int64_t k, std::int32_t l) {
    im.labels[im.grid.linear(i, j, k)] = l;
  };
  for (std::int64_t k = 2; k < 14; ++k)
    for (std::int64_t j = 2; j < 14; ++j)
      for (std::int64_t i = 2; i < 14; ++i) {
        const bool inner = i >= 5 && i < 11 && j >= 5 && j < 11 && k >= 5 && k < 11;
        set(i, j, k, inner ? 2 : 1);
      }
  set(7, 7, 7, 1);  // papillary island in the cavity
  set(8, 7, 7, 1);
  set(17, 17, 17, 1);  // fragment outside
  set(3, 8, 8, 0);     // hole in the wall
  const LabelImage before = im;
  const LabelCleanupReport r = clean_labels(im, {1});
  EXPECT_EQ(r.solid_components, 3u);
  EXPECT_EQ(r.relabelled_voxels, 3);
  EXPECT_EQ(r.holes, 1u);
  EXPECT_EQ(r.filled_voxels, 1);
  EXPECT_EQ(im.at(7, 7, 7), 2);
  EXPECT_EQ(im.at(8, 7, 7), 2);
  EXPECT_EQ(im.at(17, 17, 17), 0);
  EXPECT_EQ(im.at(3, 8, 8), 1);
  std::size_t changed = 0;
  for (std::size_t v = 0; v < im.labels.size(); ++v) changed += im.labels[v] != before.labels[v] ? 1 : 0;
  EXPECT_EQ(changed, 4u) << "nothing else moves";
  EXPECT_THROW((void)clean_labels(im, {5}), adamss::InputError);
}
