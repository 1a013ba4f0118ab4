// Ray counts against SPD's published table (scenes/spd-corpus/README.md, from SPD's Readme.txt):
// each default-size scene traced from 513 x 513 eye rays, maximum depth 5, no adaptive cutoff, and
// "the numbers ... should all be within about 10%" of any classical ray tracer.
// docs/validation-spd.md.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {
namespace {

struct SpdCounts {
  const char* file;
  uint64_t eye_hits, reflected, refracted, shadow;
  bool all;  ///< false: only the eye rays are compared (docs/validation-spd.md says why)
};

// SPD's table, at its default sizes.
const SpdCounts kTable[] = {
    {"balls-4.nff", 263169, 175095, 0, 954368, true},
    {"gears-4.nff", 245086, 304643, 207564, 2246955, false},
    {"mount-6.nff", 173125, 354769, 354769, 412922, true},
    {"rings-7.nff", 263169, 315236, 0, 1085002, true},
    {"teapot-6.nff", 161120, 225248, 0, 407656, true},
    {"tetra-6.nff", 49788, 0, 0, 46112, true},
    {"tree-11.nff", 169836, 0, 0, 1097419, true},
};

class SpdTable : public testing::TestWithParam<SpdCounts> {};

void expect_within_10_percent(const char* what, uint64_t ours, uint64_t spd) {
  // A figure SPD gives as 0 must be 0 here too.
  EXPECT_LE(std::abs(double(ours) - double(spd)), 0.10 * double(spd))
      << what << ": ours " << ours << ", SPD " << spd;
}

TEST_P(SpdTable, CountsWithinTenPercent) {
  const SpdCounts& row = GetParam();
  Scene s = load_scene(RTM_SOURCE_DIR "/scenes/spd-corpus/" + std::string(row.file));
  // 513 x 513 rays through pixel centres: SPD shoots them at the corners of a 512 x 512 image,
  // edge to edge; ours span 512/513 of that angle, a difference of one ray's spacing.
  set_resolution(s, 513, 513);
  size_for_cpu(s.grid);
  const Grid g = build_grid(s.primitives, s.grid);
  const ReferenceResult r = render_reference(s, g, 0);
  uint64_t hits = 0;
  for (int32_t id : r.image.ids) hits += id >= 0;
  const TraceCounts& c = r.counts;
  std::printf(
      "%s: eye rays that hit %llu (SPD %llu), reflected %llu (%llu), refracted %llu (%llu), shadow "
      "%llu (%llu)\n",
      row.file, (unsigned long long)hits, (unsigned long long)row.eye_hits,
      (unsigned long long)c.rays[2], (unsigned long long)row.reflected,
      (unsigned long long)c.rays[3], (unsigned long long)row.refracted,
      (unsigned long long)c.rays[1], (unsigned long long)row.shadow);
  EXPECT_EQ(c.rays[0], 513u * 513u);
  expect_within_10_percent("eye rays that hit", hits, row.eye_hits);
  if (!row.all) return;
  expect_within_10_percent("reflected rays", c.rays[2], row.reflected);
  expect_within_10_percent("refracted rays", c.rays[3], row.refracted);
  expect_within_10_percent("shadow rays", c.rays[1], row.shadow);
}

INSTANTIATE_TEST_SUITE_P(Spd, SpdTable, testing::ValuesIn(kTable),
                         [](const testing::TestParamInfo<SpdCounts>& i) {
                           std::string n = i.param.file;
                           return n.substr(0, n.find('-'));
                         });

}  // namespace
}  // namespace rtm
