// Every SPD scene the project holds (scenes/spd-corpus, the whole SPD corpus) loads
// and renders, small, with the reference renderer on the machine's automatic grid.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {
namespace {

const std::string kCorpus = RTM_SOURCE_DIR "/scenes/spd-corpus";

TEST(SpdCorpus, EverySceneLoadsAndRendersSmall) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(kCorpus))
    if (e.path().extension() == ".nff") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_EQ(files.size(), 37u);  // scenes/spd-corpus/README.md's table
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    Scene s = load_scene(f);
    ASSERT_GT(s.primitives.size(), 0u);
    set_resolution(s, 12, 12);
    const Grid g = build_grid(s.primitives, s.grid);
    const ReferenceResult r = render_reference(s, g, 0);
    int hits = 0;
    for (int32_t id : r.image.ids) hits += id >= 0;
    EXPECT_GT(hits, 0);  // something of the scene is in view
    EXPECT_EQ(r.counts.rays[0], 144u);
    // Only the teapots leave anything out: the smallest has degenerate patches (4 at the lid and
    // bottom), and each has patches whose vertex normals it shades flat (docs/scene-format.md).
    const std::string name = std::filesystem::path(f).filename().string();
    if (name.rfind("teapot-", 0) != 0) {
      EXPECT_TRUE(s.skipped.empty());
    }
    for (const SkippedRecords& k : s.skipped)
      EXPECT_TRUE(k.kind == "'pp' vertex normal" ||
                  (k.kind == "degenerate 'pp'" && name == "teapot-1.nff"))
          << k.kind;
  }
}

}  // namespace
}  // namespace rtm
