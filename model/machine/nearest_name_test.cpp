#include "machine/nearest_name.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(NearestName, EditDistanceCountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("--pe", "--pes"), 1u);
  EXPECT_EQ(edit_distance("--sizee", "--size"), 1u);
  EXPECT_EQ(edit_distance("tiling", "timing"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
}

TEST(NearestName, SuggestsOnlyANameCloseEnoughToHaveBeenMeant) {
  const std::vector<std::string> options{"--pes", "--size", "--stats", "--set", "--vcd", "--vcd-window"};
  EXPECT_EQ(nearest_name("--pe", options), "--pes");
  EXPECT_EQ(nearest_name("--sizee", options), "--size");
  EXPECT_EQ(nearest_name("--vcdwindow", options), "--vcd-window");
  EXPECT_EQ(nearest_name("--no-such-option", options), "");
  EXPECT_EQ(nearest_name("--st", options), "--set");
  EXPECT_EQ(nearest_name("-x", {"-q"}), "");  // in a short name one edit is already a guess
  EXPECT_EQ(nearest_name("search_unit", {"search_units", "search_walk"}), "search_units");
}

}  // namespace
}  // namespace rtm
