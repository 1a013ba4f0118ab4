#include "config/nearest_name.h"

#include <chrono>

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
  const std::vector<std::string> options{"--pes", "--size", "--stats",
                                         "--set", "--vcd",  "--vcd-window"};
  EXPECT_EQ(nearest_name("--pe", options), "--pes");
  EXPECT_EQ(nearest_name("--sizee", options), "--size");
  EXPECT_EQ(nearest_name("--vcdwindow", options), "--vcd-window");
  EXPECT_EQ(nearest_name("--no-such-option", options), "");
  EXPECT_EQ(nearest_name("--st", options), "--set");
  EXPECT_EQ(nearest_name("-x", {"-q"}), "");  // in a short name one edit is already a guess
  EXPECT_EQ(nearest_name("search_unit", {"search_units", "search_walk"}), "search_units");
}

TEST(NearestName, ALongNameIsComparedOnlyWithNamesOfNearlyItsLength) {
  const std::vector<std::string> keys{"search_units", "search_walk", "pes"};
  const std::string long_name(1'000'000, 'x');  // was 1.8 s in rtm, as a configuration file's key
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(nearest_name(long_name, keys), "");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.1);
  EXPECT_EQ(nearest_name("search_unitsxx", keys), "search_units");  // two longer: still near
  EXPECT_EQ(nearest_name("pe", keys), "");  // one edit in a short name: a guess
}

}  // namespace
}  // namespace rtm
