// Scene records from the wild through the whole program: concave polygons against POV-Ray's own
// polygons and against a triangulation, degenerate shapes skipped (or --strict), unknown records
// (or --skip-unknown), and what the warnings and the statistics say.
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "render/image_io.h"
#include "scene/scene.h"

using namespace rtm::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kCorpus = std::string(RTM_SOURCE_DIR) + "/scenes/spd-corpus/";

struct Outline {
  std::vector<std::array<double, 2>> corners;
  std::array<double, 2> kernel;  ///< a point that sees every corner: the fan triangulation's centre
};

/// The first gear face of SPD gears-1 (144 corners, 36 teeth), moved to x0.
Outline gear(double x0) {
  std::istringstream f(slurp(kCorpus + "gears-1.nff"));
  std::string line;
  for (int n = 1; n <= 21; ++n) std::getline(f, line);
  Outline o{{}, {x0, 0}};
  for (int i = 0; i < 144 && std::getline(f, line); ++i) {
    std::istringstream s(line);
    double x, y;
    s >> x >> y;
    o.corners.push_back({x + x0, y});
  }
  return o;
}

Outline l_shape(double x0) {
  return {{{x0 - 1, -1}, {x0 + 1, -1}, {x0 + 1, 0}, {x0, 0}, {x0, 1}, {x0 - 1, 1}},
          {x0 - 0.5, -0.5}};
}

Outline star(double x0) {
  Outline o{{}, {x0, 0}};
  for (int i = 0; i < 10; ++i) {
    const double a = kPi * i / 5 + 0.1, r = i % 2 ? 0.4 : 1;
    o.corners.push_back({x0 + r * std::cos(a), r * std::sin(a)});
  }
  return o;
}

const std::string kView =
    "v\nfrom 0 0.3 7\nat 0 0 0\nup 0 1 0\nangle 48\nhither 1\nresolution 160 80\n"
    "l 4 4 8\nf 0.8 0.6 0.2 0.8 0.1 10 0 1\n";

std::string corner(const std::array<double, 2>& c) {
  return std::to_string(c[0]) + " " + std::to_string(c[1]) + " 0\n";
}

/// The outlines as whole polygons, or each as a fan of triangles about its kernel point.
std::string scene(const std::vector<Outline>& shapes, bool triangles) {
  std::string s = kView;
  for (const Outline& o : shapes) {
    if (!triangles) {
      s += "p " + std::to_string(o.corners.size()) + "\n";
      for (const auto& c : o.corners) s += corner(c);
      continue;
    }
    for (size_t i = 0; i < o.corners.size(); ++i)
      s += "p 3\n" + corner(o.kernel) + corner(o.corners[i]) +
           corner(o.corners[(i + 1) % o.corners.size()]);
  }
  return s;
}

/// Per pixel, which outline (0, 1, 2; -1 background) the primary ray hit, from an ID map and the
/// number of primitives each outline became.
std::vector<int> outline_of(const std::vector<int32_t>& ids,
                            const std::vector<int>& primitives_per_outline) {
  std::vector<int> owner;
  for (size_t k = 0; k < primitives_per_outline.size(); ++k)
    owner.insert(owner.end(), size_t(primitives_per_outline[k]), int(k));
  std::vector<int> out;
  for (int32_t id : ids) out.push_back(id < 0 ? -1 : owner.at(size_t(id)));
  return out;
}

std::vector<int> pieces_per_outline(const rtm::Scene& s) {
  std::vector<int> n;
  for (size_t i = 0; i < s.primitives.size(); i += size_t(s.primitives[i].pieces))
    n.push_back(s.primitives[i].pieces);
  return n;
}

const std::vector<Outline> kShapes = {gear(-2.3), l_shape(0.2), star(2.4)};

TEST(ConcavePolygons, RenderAsTheirTriangulation) {
  Tmp tmp;
  spit(tmp / "whole.nff", scene(kShapes, false));
  spit(tmp / "fan.nff", scene(kShapes, true));
  for (const char* n : {"whole", "fan"}) {
    const Proc r = run_rtm("render " + tmp / (std::string(n) + ".nff") + " --reference -q --out " +
                               tmp / n + ".png --id-map " + tmp / n + "-id.exr",
                           tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const rtm::Scene whole = rtm::load_scene(tmp / "whole.nff");
  EXPECT_EQ(pieces_per_outline(whole),
            (std::vector<int>{37, 2, 5}));  // the star: at least 4, at most 6
  std::vector<int> fan_counts;
  for (const Outline& o : kShapes) fan_counts.push_back(int(o.corners.size()));
  const std::vector<int> a =
      outline_of(rtm::read_id_map(tmp / "whole-id.exr").ids, pieces_per_outline(whole));
  const std::vector<int> b = outline_of(rtm::read_id_map(tmp / "fan-id.exr").ids, fan_counts);
  ASSERT_EQ(a.size(), b.size());
  int differ = 0, hits[3] = {};
  for (size_t i = 0; i < a.size(); ++i) {
    differ += a[i] != b[i];
    if (a[i] >= 0) ++hits[a[i]];
  }
  for (int h : hits) EXPECT_GT(h, 300);  // every shape is in view
  EXPECT_EQ(differ, 0);
}

TEST(ConcavePolygons, MatchPovRaysPolygons) {
  if (std::system("command -v povray >/dev/null 2>&1") != 0)
    FAIL() << "povray is not installed (Debian package povray; scripts/setup installs it)";
  Tmp tmp;
  spit(tmp / "whole.nff", scene(kShapes, false));
  ASSERT_EQ(run_rtm("render " + tmp / "whole.nff --reference -q --out " +
                        tmp / "ours.png --id-map " + tmp / "ours-id.exr",
                    tmp)
                .exit_code,
            0);
  const Proc pov = run_rtm("pov " + tmp / "whole.nff --id --out " + tmp / "id.pov", tmp);
  ASSERT_EQ(pov.exit_code, 0) << pov.err;
  // POV-Ray draws each concave polygon whole: `rtm pov` writes it once, numbered as its first
  // piece.
  EXPECT_NE(slurp(tmp / "id.pov").find("// polygon pieces 0 37\n"), std::string::npos);
  const Proc r = sh("povray +I" + tmp / "id.pov" + " +O" + tmp / "pov-id.png" +
                        " +W160 +H80 -D -A +FN8 File_Gamma=1.0 +WT1",
                    tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const rtm::Image p = rtm::read_image(tmp / "pov-id.png");
  std::vector<int32_t> pov_ids;
  for (const rtm::Vec3& c : p.rgb) {
    const int k = int(std::lround(c.x * 255)) << 16 | int(std::lround(c.y * 255)) << 8 |
                  int(std::lround(c.z * 255));
    pov_ids.push_back(k - 1);
  }
  const rtm::Scene whole = rtm::load_scene(tmp / "whole.nff");
  const std::vector<int> ours =
      outline_of(rtm::read_id_map(tmp / "ours-id.exr").ids, pieces_per_outline(whole));
  const std::vector<int> theirs = outline_of(pov_ids, pieces_per_outline(whole));
  ASSERT_EQ(ours.size(), theirs.size());
  int differ = 0, hit = 0;
  for (size_t i = 0; i < ours.size(); ++i) differ += ours[i] != theirs[i], hit += ours[i] >= 0;
  EXPECT_GT(hit, 1000);
  EXPECT_EQ(differ, 0);
}

TEST(SceneRecords, DegeneratePatchesWarnCountAndStrict) {
  Tmp tmp;
  const std::string teapot = kCorpus + "teapot-1.nff";
  const Proc r =
      run_rtm("render " + teapot + " --reference -q --size 16x16 --out " + tmp / "t.png", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rtm: warning: " + teapot +
                       ":163: skipped 4 degenerate 'pp' records (polygon has zero area; lines 163, "
                       "167, 171, 175)"),
            std::string::npos)
      << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(tmp / "t.json"));
  EXPECT_NE(r.err.find("rtm: warning: " + teapot + ":19: skipped 20 'pp' vertex normal records"),
            std::string::npos)
      << r.err;
  ASSERT_EQ(j["skipped"].size(), 2u);
  EXPECT_EQ(j["skipped"][0]["kind"], "'pp' vertex normal");
  EXPECT_EQ(j["skipped"][0]["count"], 20);
  EXPECT_EQ(j["skipped"][1]["kind"], "degenerate 'pp'");
  EXPECT_EQ(j["skipped"][1]["count"], 4);
  EXPECT_EQ(j["skipped"][1]["lines"], nlohmann::json({163, 167, 171, 175}));
  EXPECT_EQ(j["primitives"], 53);

  const Proc strict = run_rtm(
      "render " + teapot + " --reference -q --strict --size 16x16 --out " + tmp / "s.png", tmp);
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_EQ(strict.err, "rtm: " + teapot + ":163: pp: polygon has zero area (--strict)\n");
  EXPECT_FALSE(std::filesystem::exists(tmp / "s.png"));
}

TEST(SceneRecords, SkipUnknownOnEveryKindOfExtensionRecord) {
  Tmp tmp;
  const std::string file = tmp / "ext.nff";
  spit(file,
       "number 2\n" + kView +
           "la 0 5 0 1 0 0 0 0 1 1 1 1\nls 0 5 5 0 -1 -1 30 1 1 1\ntex brick.ppm 4 4\nenv sky.hdr\n"
           "s 0 0 0 1\ntpp 3 brick.ppm\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\nla 1 5 "
           "0 1 0 0 0 0 1 1 1 1\n"
           "s 1 0 0 0.5\n");
  const Proc plain =
      run_rtm("render " + file + " --reference -q --size 16x16 --out " + tmp / "a.png", tmp);
  EXPECT_EQ(plain.exit_code, 1);
  EXPECT_EQ(plain.err,
            "rtm: " + file +
                ":1: unknown keyword 'number' (--skip-unknown skips records rtm does not know)\n");

  const Proc r = run_rtm(
      "render " + file + " --reference -q --skip-unknown --size 16x16 --out " + tmp / "b.png", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string w :
       {":1: skipped 1 unknown 'number' record", ":11: skipped 2 unknown 'la' records",
        ":12: skipped 1 unknown 'ls' record", ":13: skipped 1 unknown 'tex' record",
        ":14: skipped 1 unknown 'env' record", ":16: skipped 1 unknown 'tpp' record"})
    EXPECT_NE(r.err.find("rtm: warning: " + file + w), std::string::npos) << w << "\n" << r.err;
  // rtm pov reads the file the same way, so the same scene can be checked against POV-Ray.
  const Proc pov = run_rtm("pov " + file + " --skip-unknown --out " + tmp / "b.pov", tmp);
  EXPECT_EQ(pov.exit_code, 0) << pov.err;
  EXPECT_NE(pov.err.find(":16: skipped 1 unknown 'tpp' record"), std::string::npos) << pov.err;
  EXPECT_EQ(run_rtm("pov " + file + " --out " + tmp / "c.pov", tmp).exit_code, 1);
  const nlohmann::json j = nlohmann::json::parse(slurp(tmp / "b.json"));
  EXPECT_EQ(j["primitives"], 2);
  EXPECT_EQ(j["skipped"].size(), 6u);
  EXPECT_EQ(j["skipped"][1]["lines"], nlohmann::json({11, 20}));
}

}  // namespace

namespace {

TEST(SceneRecords, BuildTimeBesideTheTraceTime) {
  Tmp tmp;
  const Proc r = run_rtm("render --reference --size 16x16 --out " + tmp / "d.png", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(tmp / "d.json"));
  ASSERT_TRUE(j.contains("grid_build_seconds"));
  EXPECT_EQ(j["grid_build_seconds"], j["grid"]["build_seconds"]);
  EXPECT_GE(j["grid_build_seconds"].get<double>(), 0.0);
  EXPECT_NE(r.out.find("(reference renderer), "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" M rays/s; grid build "), std::string::npos) << r.out;
  EXPECT_NE(
      r.out.find(" s (" + std::to_string(j["grid"]["references"].get<int>()) + " references)"),
      std::string::npos)
      << r.out;
}

}  // namespace
