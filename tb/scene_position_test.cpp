// The default fp32 machine's accuracy does not depend on where the scene is (docs/numerics.md,
// "Where the scene is"): each scene moved in fp64 by scripts/move-scene, far along a skewed
// direction or scaled, renders with the primary hits of the scene where it was, and with at most
// twice its pixels over 1/255 (against each one's own fp64 reference) plus five.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"

namespace {

using namespace rtm::test;
using nlohmann::json;

const std::string kRoot = RTM_SOURCE_DIR;

struct Placement {
  const char* name;
  const char* by;
  double scale;
};
const Placement kPlacements[] = {
    {"by_1e2", "100,37,-61", 1},
    {"by_1e4", "-5300,10000,2900", 1},
    {"by_1e6", "710000,-430000,1000000", 1},
    {"scaled_1e_minus3", "0.0013,-0.0007,0.0002", 1e-3},
    {"scaled_1e3", "1300,-700,200", 1e3},
};
const char* const kScenes[] = {"spd/balls-2.nff",       "spd/rings-1.nff",       "spd/tree-3.nff",
                               "spd/mount-2.nff",       "spd/lattice-1.nff",     "spd/jacks-1.nff",
                               "position/near-eye.nff", "position/cone-tree.nff"};

struct Case {
  const char* scene;
  Placement at;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << " " << c.at.name; }

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const char* s : kScenes)
    for (const Placement& p : kPlacements) all.push_back({s, p});
  return all;
}

class ScenePosition : public ::testing::TestWithParam<Case> {};

TEST_P(ScenePosition, DefaultMachineRendersTheSameWhereverTheSceneIs) {
  Tmp tmp;
  const Case c = GetParam();
  const std::string scene = kRoot + "/scenes/" + c.scene, moved = tmp / "moved.nff";
  const Proc mv = sh(kRoot + "/scripts/move-scene " + scene + " " + moved + " --by=" + c.at.by +
                         " --scale " + std::to_string(c.at.scale),
                     tmp);
  ASSERT_EQ(mv.exit_code, 0) << mv.err;
  const std::string common = " --size 96x96 --pes 2";
  const json here = render(tmp, "here", scene + common);
  const json there = render(tmp, "there", moved + common);
  ASSERT_FALSE(here.is_null() || there.is_null());
  const rtm::Image a = rtm::read_id_map(tmp / "here-id.exr"),
                   b = rtm::read_id_map(tmp / "there-id.exr");
  ASSERT_EQ(a.ids.size(), b.ids.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.ids.size(); ++i) differing += a.ids[i] != b.ids[i];
  EXPECT_EQ(differing, 0u) << "primary hits differing from the scene where it was";
  const int px_here = here["error"]["pixels_over_1_255"].get<int>(),
            px_there = there["error"]["pixels_over_1_255"].get<int>();
  EXPECT_LE(px_there, 2 * px_here + 5)
      << "pixels over 1/255: " << px_there << " moved, " << px_here << " where it was";
  EXPECT_EQ(there["error"]["causes"]["by_cause"]["unknown"].get<int>(), 0)
      << "the error map explains every pixel";
  std::cout << "[ position ] " << c.scene << " " << c.at.name << ": pixels over 1/255 " << px_here
            << " -> " << px_there << ", primary hits differing " << differing << "\n";
}

INSTANTIATE_TEST_SUITE_P(Moved, ScenePosition, ::testing::ValuesIn(cases()), [](const auto& info) {
  std::string s = info.param.scene;
  s = s.substr(s.find('/') + 1);
  s = s.substr(0, s.find('.'));
  for (char& ch : s)
    if (ch == '-') ch = '_';
  return s + "_" + info.param.at.name;
});

}  // namespace
