// "Did you mean" (common/suggest.hpp): edit distances and the closest-name rule.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/suggest.hpp"

using adamss::closest_name;
using adamss::did_you_mean;
using adamss::edit_distance;

TEST(Suggest, EditDistanceCountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(edit_distance("run", "run"), 0u);
  EXPECT_EQ(edit_distance("rnu", "run"), 1u);  // one transposition
  EXPECT_EQ(edit_distance("tend", "t_end"), 1u);
  EXPECT_EQ(edit_distance("lawz", "law"), 1u);
  EXPECT_EQ(edit_distance("mmHG", "mmHg"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);  // the textbook pair
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // OSA (not full Damerau, which gives 2)
}

TEST(Suggest, OnlyCloseNamesAreSuggested) {
  const std::vector<std::string> commands{"phantom", "mesh", "info", "run", "fit", "verify"};
  EXPECT_EQ(closest_name("rnu", commands), "run");
  EXPECT_EQ(closest_name("mesg", commands), "mesh");
  EXPECT_EQ(closest_name("phantmo", commands), "phantom");
  EXPECT_FALSE(closest_name("simulate", commands).has_value());
  EXPECT_FALSE(closest_name("run", commands).has_value());  // the word itself is not a suggestion
  EXPECT_FALSE(closest_name("xy", commands).has_value());
  const std::vector<std::string> options{"--fiber-out", "--sheet-out", "--scar-out", "--voxel-size"};
  EXPECT_EQ(closest_name("--fibre-out", options), "--fiber-out");
  EXPECT_EQ(closest_name("--fiber", options), "--fiber-out");  // a prefix
  EXPECT_EQ(closest_name("--voxelsize", options), "--voxel-size");
  EXPECT_EQ(did_you_mean("tend", {"t_end", "frame_interval"}), "; did you mean 't_end'?");
  EXPECT_EQ(closest_name("a_sf", {"a", "a_f", "a_fs", "a_s"}), "a_fs");  // equal distance: the same length wins
  EXPECT_EQ(did_you_mean("flux", {"t_end", "frame_interval"}), "");
}
