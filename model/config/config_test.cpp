// The configuration keys: each declared once, and parsing, range checks and the YAML that
// `rtm config` prints all agree with that declaration. Plain C++, no simulation.
#include "config/config.h"

#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

namespace rtm {
namespace {

const ConfigKey& key(const std::string& name) {
  for (const ConfigKey& k : config_keys())
    if (k.name == name) return k;
  throw std::invalid_argument("no key " + name);
}

/// The message set_config refuses `value` with, or "" if it takes it.
std::string refusal(const std::string& name, const std::string& value) {
  MachineConfig c;
  try {
    set_config(c, name, value);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::string text(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", x);
  return s;
}

/// Every key's value, by name.
std::map<std::string, std::string> values(const MachineConfig& c) {
  std::map<std::string, std::string> v;
  for (const ConfigKey& k : config_keys()) v[k.name] = k.get(c);
  return v;
}

/// A configuration with every key off its default (where it has another value), so a key that
/// reads or writes the wrong member shows.
MachineConfig off_default() {
  MachineConfig c;
  for (const ConfigKey& k : config_keys()) {
    const std::string d = k.get(c);
    switch (k.type) {
      case ConfigKey::Type::Integer:
      case ConfigKey::Type::Number:
        set_config(c, k.name, text(k.range.min + 3));
        break;
      case ConfigKey::Type::Flag:
      case ConfigKey::Type::Choice:
        set_config(c, k.name, k.values.back() == d ? k.values.front() : k.values.back());
        break;
      case ConfigKey::Type::Text:
        set_config(c, k.name, "other/" + d + ".yaml");
        break;
    }
  }
  return c;
}

TEST(ConfigKeys, NamesAreUniqueAndMeaningsOneLine) {
  std::set<std::string> names;
  for (const ConfigKey& k : config_keys()) {
    EXPECT_TRUE(names.insert(k.name).second) << k.name;
    EXPECT_FALSE(k.meaning.empty()) << k.name;
    EXPECT_EQ(k.meaning.find('\n'), std::string::npos) << k.name;
    EXPECT_EQ(k.values.empty(), k.type == ConfigKey::Type::Integer ||
                                    k.type == ConfigKey::Type::Number ||
                                    k.type == ConfigKey::Type::Text)
        << k.name;
  }
}

TEST(ConfigKeys, EveryKeyRoundTrips) {
  for (const MachineConfig& c : {MachineConfig{}, off_default()}) {
    for (const ConfigKey& k : config_keys()) {
      MachineConfig d;
      set_config(d, k.name, k.get(c));
      EXPECT_EQ(k.get(d), k.get(c)) << k.name;
    }
  }
  // Each key writes its own member: setting them all one by one gives the same values.
  const MachineConfig c = off_default();
  MachineConfig d;
  for (const ConfigKey& k : config_keys()) set_config(d, k.name, k.get(c));
  EXPECT_EQ(values(d), values(c));
  EXPECT_NE(values(c), values(MachineConfig{}));
}

TEST(ConfigKeys, ANumberNeedingMoreThanSixDigitsReadsBackExactly) {
  MachineConfig c;
  c.link_latency_ns = 1.0 / 3;
  MachineConfig d;
  set_config(d, "link_latency_ns", key("link_latency_ns").get(c));
  EXPECT_EQ(d.link_latency_ns, c.link_latency_ns);
  // What fits six digits reads as it always did (the stats' config strings).
  c.clock_ns = 2.5;
  EXPECT_EQ(key("clock_ns").get(c), "2.5");
  c.link_latency_ns = 1e6;
  EXPECT_EQ(key("link_latency_ns").get(c), "1e+06");
}

/// The range's ends are taken; one past them is refused naming the key, the value and the range.
TEST(ConfigKeys, EachRangeEndIsAcceptedAndOnePastItRefused) {
  for (const ConfigKey& k : config_keys()) {
    auto refused = [&](const std::string& v) {
      const std::string why = refusal(k.name, v);
      EXPECT_EQ(why.rfind(k.name + ": ", 0), 0u) << k.name << " = " << v << ": " << why;
      EXPECT_NE(why.find(v), std::string::npos) << k.name << " = " << v << ": " << why;
      return why;
    };
    const ConfigKey::Range r = k.range;
    if (k.type == ConfigKey::Type::Integer || k.type == ConfigKey::Type::Number) {
      // Every number has both ends: what the model can represent and finish (config.cpp).
      EXPECT_NE(r.max, HUGE_VAL) << k.name;
      EXPECT_FALSE(r.above_min) << k.name;
    }
    if (k.type == ConfigKey::Type::Integer) {
      const long lo = long(r.min), hi = long(r.max);
      EXPECT_EQ(refusal(k.name, std::to_string(lo)), "") << k.name;
      EXPECT_EQ(refusal(k.name, std::to_string(hi)), "") << k.name;
      EXPECT_NE(refused(std::to_string(lo - 1)).find(k.accepted()), std::string::npos) << k.name;
      EXPECT_NE(refused(std::to_string(hi + 1)).find(k.accepted()), std::string::npos) << k.name;
      refused("1.5");
    } else if (k.type == ConfigKey::Type::Number) {
      EXPECT_EQ(refusal(k.name, text(r.min)), "") << k.name;
      EXPECT_EQ(refusal(k.name, text(r.max)), "") << k.name;
      EXPECT_NE(refused(text(std::nextafter(r.min, -HUGE_VAL))).find(k.accepted()),
                std::string::npos)
          << k.name;
      EXPECT_NE(refused(text(std::nextafter(r.max, HUGE_VAL))).find(k.accepted()),
                std::string::npos)
          << k.name;
      refused("inf");
    } else if (k.type == ConfigKey::Type::Text) {
      EXPECT_EQ(refusal(k.name, "tech/16nm-v2.yaml"), "") << k.name;
      for (const std::string v : {"a b", "a#b", "-a", "'a'"})
        EXPECT_NE(refused(v).find(k.accepted()), std::string::npos) << k.name;
    } else {
      for (const std::string& v : k.values)
        EXPECT_EQ(refusal(k.name, v), "") << k.name << " = " << v;
      EXPECT_NE(refused("bogus").find(k.accepted()), std::string::npos) << k.name;
    }
  }
}

// The ranges' ends are derived in config.cpp (what the time arithmetic, memory and the host hold).
TEST(ConfigKeys, TheRangesAreTheModelsLimits) {
  EXPECT_EQ(key("pes").accepted(), "an integer in 1..16384");
  EXPECT_EQ(key("search_units").accepted(), "an integer in 1..256");
  EXPECT_EQ(key("intersection_units").accepted(), "an integer in 1..64");
  EXPECT_EQ(key("shade_cycles").accepted(), "an integer in 0..65536");
  EXPECT_EQ(key("root_latency").accepted(), "an integer in 1..65536");
  EXPECT_EQ(key("mul_latency").accepted(), "an integer in 1..1024");
  EXPECT_EQ(key("feedback_fifo_depth").accepted(), "an integer in 1..65536");
  EXPECT_EQ(key("clock_ns").accepted(), "a number in 0.002..1000, a multiple of 0.001");
  EXPECT_EQ(key("link_latency_ns").accepted(), "a number in 0..1e+06");
  EXPECT_EQ(key("link_bandwidth_mb_s").accepted(), "a number in 0.001..1e+09");
  EXPECT_EQ(key("broadcast").accepted(), "true or false");
  EXPECT_EQ(refusal("pes", "0"), "pes: expected an integer in 1..16384, got 0");
  EXPECT_EQ(refusal("clock_ns", "1e-300"),
            "clock_ns: expected a number in 0.002..1000, a multiple of 0.001, got 1e-300");
  EXPECT_EQ(refusal("clock_ns", "1e300"),
            "clock_ns: expected a number in 0.002..1000, a multiple of 0.001, got 1e300");
  // Whole picoseconds, SystemC's time resolution: 2.5 ps would silently become 3 (or 2).
  EXPECT_EQ(refusal("clock_ns", "0.0025"),
            "clock_ns: expected a number in 0.002..1000, a multiple of 0.001, got 0.0025");
  EXPECT_EQ(refusal("clock_ns", "0.3"), "");
  EXPECT_EQ(refusal("host_clock_ns", "7.5"), "");
  EXPECT_EQ(refusal("mul_latency", "2147483647"),
            "mul_latency: expected an integer in 1..1024, got 2147483647");
}

TEST(ConfigKeys, ValidateChecksEachRangeAndTheRulesAcrossKeys) {
  MachineConfig c;
  EXPECT_NO_THROW(c.validate());
  auto refused = [](const MachineConfig& m) {
    try {
      m.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  MachineConfig bad;
  bad.pes = 16385;
  EXPECT_EQ(refused(bad), "pes: expected an integer in 1..16384, got 16385");
  bad = {};
  bad.clock_ns = 0;
  EXPECT_EQ(refused(bad), "clock_ns: expected a number in 0.002..1000, a multiple of 0.001, got 0");
  bad = {};
  bad.link_latency_ns = -1;
  EXPECT_EQ(refused(bad), "link_latency_ns: expected a number in 0..1e+06, got -1");
  bad = {};
  bad.root_fifo_depth = 3;
  bad.loop_credits = 4;
  EXPECT_EQ(
      refused(bad).rfind(
          "loop_credits: must not exceed the smallest FIFO depth past the front buffer (3)", 0),
      0u)
      << refused(bad);
  // A broadcast on a star needs every link driven at once; serial keeps its old broadcast.
  bad = {};
  bad.pes = 4;
  bad.link_topology = MachineConfig::LinkTopology::Star;
  bad.host_ports = 3;
  bad.broadcast = true;
  EXPECT_EQ(refused(bad).rfind(
                "broadcast: true with link_topology = star needs host_ports >= pes (3 < 4)", 0),
            0u)
      << refused(bad);
  bad.host_ports = 4;
  EXPECT_NO_THROW(bad.validate());
  for (auto t : {MachineConfig::LinkTopology::Serial, MachineConfig::LinkTopology::Bus,
                 MachineConfig::LinkTopology::Tree}) {
    bad.link_topology = t;
    bad.host_ports = 1;
    EXPECT_NO_THROW(bad.validate()) << to_string(t);
  }
}

TEST(ConfigKeys, EveryEnumNameParsesToItsValueAndBack) {
  MachineConfig c;
  set_config(c, "partition", "pixels");
  EXPECT_EQ(c.partition, Partition::Pixels);
  set_config(c, "search_walk", "until_occupied");
  EXPECT_EQ(c.search_walk, MachineConfig::SearchWalk::UntilOccupied);
  set_config(c, "gather", "as_finished");
  EXPECT_EQ(c.gather, MachineConfig::Gather::AsFinished);
  set_config(c, "origin_latch", "advance");
  EXPECT_EQ(c.origin_latch, OriginLatch::Advance);
  EXPECT_STREQ(to_string(Partition::Scanlines), "scanlines");
  EXPECT_STREQ(to_string(MachineConfig::SearchWalk::PerVoxel), "per_voxel");
  EXPECT_STREQ(to_string(MachineConfig::Gather::AfterAll), "after_all");
  for (const ConfigKey& k : config_keys()) {
    if (k.type != ConfigKey::Type::Choice) continue;
    std::set<std::string> seen;
    for (const std::string& v : k.values) {
      MachineConfig d;
      set_config(d, k.name, v);
      EXPECT_EQ(k.get(d), v) << k.name;
      EXPECT_TRUE(seen.insert(v).second) << k.name << ": " << v << " twice";
    }
    EXPECT_GE(seen.size(), 2u) << k.name;
  }
}

TEST(ConfigKeys, AnUnknownKeyIsRefusedWithWhereTheyAreListed) {
  EXPECT_EQ(refusal("warp_drive", "1"),
            "warp_drive: unknown machine configuration key (rtm config lists them)");
}

const Preset& preset(const std::string& name) {
  for (const Preset& p : presets())
    if (p.name == name) return p;
  throw std::invalid_argument("no preset " + name);
}

/// The message apply_preset refuses `name` with on c, or "" if it takes it.
std::string preset_refusal(MachineConfig c, const std::string& name) {
  try {
    apply_preset(c, name);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Presets, EachIsDeclaredOnceWithKnownKeysAndValuesAsTheKeysPrintThem) {
  std::set<std::string> names;
  for (const Preset& p : presets()) {
    EXPECT_TRUE(names.insert(p.name).second) << p.name;
    EXPECT_FALSE(p.meaning.empty()) << p.name;
    EXPECT_EQ(p.meaning.find('\n'), std::string::npos) << p.name;
    std::set<std::string> keys;
    for (const Preset::Override& o : p.overrides) {
      EXPECT_TRUE(keys.insert(o.key).second) << p.name << ": " << o.key << " twice";
      EXPECT_FALSE(o.why.empty()) << p.name << ": " << o.key;
      EXPECT_EQ(o.why.find('\n'), std::string::npos) << p.name << ": " << o.key;
      EXPECT_EQ(refusal(o.key, o.value), "") << p.name;
    }
    MachineConfig c;
    ASSERT_EQ(preset_refusal(c, p.name), "");
    apply_preset(c, p.name);
    EXPECT_NO_THROW(c.validate()) << p.name;
    for (const Preset::Override& o : p.overrides)
      EXPECT_EQ(key(o.key).get(c), o.value) << p.name << ": " << o.key;
  }
  EXPECT_EQ(presets().front().name, kDefaultPreset);
  EXPECT_TRUE(preset(kDefaultPreset).overrides.empty()) << "default is MachineConfig{} itself";
}

TEST(Presets, PaperSetsEveryKeyAsDeclaredAndLeavesTheOthers) {
  MachineConfig c;
  apply_preset(c, "paper");
  EXPECT_EQ(c.preset, "paper");
  for (const Preset::Override& o : preset("paper").overrides)
    EXPECT_EQ(key(o.key).get(c), o.value) << o.key;
  // Every key the preset does not set is the default's.
  std::set<std::string> set_keys;
  for (const Preset::Override& o : preset("paper").overrides) set_keys.insert(o.key);
  for (const ConfigKey& k : config_keys()) {
    if (!set_keys.count(k.name)) {
      EXPECT_EQ(k.get(c), k.get(MachineConfig{})) << k.name;
    }
  }
  // The paper's machine in the members themselves: a slip in the declaration's text shows here.
  EXPECT_EQ(c.mac_schedule, MachineConfig::MacSchedule::Full);
  EXPECT_FALSE(c.recentre);
  EXPECT_EQ(c.coef_scaling, CoefScaling::None);
  EXPECT_EQ(c.origin_latch, OriginLatch::Machine);
  EXPECT_EQ(c.search_walk, MachineConfig::SearchWalk::PerVoxel);
  EXPECT_EQ(c.ray_generation, MachineConfig::RayGeneration::Host);
  EXPECT_EQ(c.ray_block, 0);
  EXPECT_FALSE(c.broadcast);
  EXPECT_EQ(c.gather, MachineConfig::Gather::AfterAll);
  EXPECT_EQ(c.search_units, 4);
  EXPECT_EQ(c.intersection_units, 1);
  EXPECT_EQ(c.flow_control, FlowControl::Credits);
}

TEST(Presets, AnUnknownOrASecondDifferentPresetIsRefused) {
  EXPECT_EQ(preset_refusal({}, "papr"), "preset: expected one of default, paper, got 'papr'");
  MachineConfig paper;
  apply_preset(paper, "paper");
  EXPECT_EQ(preset_refusal(paper, "paper"), "") << "the same one again changes nothing";
  EXPECT_EQ(preset_refusal(paper, "default"),
            "preset: 'default' after 'paper': a configuration starts from one preset");
  MachineConfig d;
  apply_preset(d, kDefaultPreset);
  EXPECT_EQ(values(d), values(MachineConfig{}));
  EXPECT_EQ(preset_refusal(d, "paper"), "")
      << "default changes no key, so any preset may follow it";
  EXPECT_EQ(refusal("preset", "paper"),
            "preset: not a key but where the keys start: --preset NAME, or preset: NAME in a "
            "--config file");
}

// docs/machine.md's table: the keys on which paper differs from default, each with its why.
TEST(Presets, TheMarkdownTableListsExactlyTheKeysThatDiffer) {
  MachineConfig paper;
  apply_preset(paper, "paper");
  const std::string table = preset_markdown("paper");
  EXPECT_EQ(table.rfind("| key | default | paper | why |\n|---|---|---|---|\n", 0), 0u) << table;
  size_t rows = 0;
  for (const ConfigKey& k : config_keys()) {
    const bool differs = k.get(paper) != k.get(MachineConfig{});
    rows += differs;
    EXPECT_EQ(table.find("| `" + k.name + "` |") != std::string::npos, differs) << k.name;
  }
  EXPECT_GE(rows, 5u);
  EXPECT_EQ(size_t(std::count(table.begin(), table.end(), '\n')), rows + 2);
  for (const Preset::Override& o : preset("paper").overrides) {
    if (key(o.key).get(paper) != key(o.key).get(MachineConfig{})) {
      EXPECT_NE(table.find(" | " + o.why + " |\n"), std::string::npos) << o.key;
    }
  }
  EXPECT_EQ(preset_markdown(kDefaultPreset),
            "| key | default | default | why |\n|---|---|---|---|\n");
  EXPECT_THROW(preset_markdown("papr"), std::invalid_argument);
}

class ConfigFile : public ::testing::Test {
 protected:
  // Each test runs in its own process, perhaps beside others.
  std::string path = ::testing::TempDir() + "config_test_" + std::to_string(getpid()) + ".yaml";
  void TearDown() override { std::remove(path.c_str()); }
  void write(const std::string& text) { std::ofstream(path) << text; }
};

TEST_F(ConfigFile, TheDescriptionReadsBackAsTheSameConfiguration) {
  const MachineConfig c = off_default();
  write(describe_config(c));
  MachineConfig d;
  load_config_file(d, path);
  EXPECT_EQ(values(d), values(c));
}

TEST_F(ConfigFile, APresetsDescriptionReadsBackAsTheSameConfiguration) {
  MachineConfig c;
  apply_preset(c, "paper");
  set_config(c, "pes", "8");
  write(describe_config(c));
  MachineConfig d;
  load_config_file(d, path);
  EXPECT_EQ(values(d), values(c));
  EXPECT_EQ(d.preset, "paper");
}

// A preset is what the file's keys change, wherever in the file it is written.
TEST_F(ConfigFile, ThePresetGoesFirstWhereverItIsWritten) {
  write("mac_schedule: sparse\npes: 3\npreset: paper\n");
  MachineConfig c;
  load_config_file(c, path);
  EXPECT_EQ(c.preset, "paper");
  EXPECT_EQ(c.mac_schedule, MachineConfig::MacSchedule::Sparse)
      << "the file's key wins over its preset";
  EXPECT_FALSE(c.recentre) << "the preset's other keys stay";
  EXPECT_EQ(c.pes, 3);
}

TEST_F(ConfigFile, ABadPresetNamesTheFileAndTheLine) {
  write("pes: 4\n\npreset: papr\n");
  MachineConfig c;
  try {
    load_config_file(c, path);
    FAIL() << "preset: papr was taken";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(std::string(e.what()),
              path + ":3: preset: expected one of default, paper, got 'papr'");
  }
  write("preset: [paper]\n");
  EXPECT_THROW(load_config_file(c, path), ConfigError);
  write("preset: default\n");
  MachineConfig paper;
  apply_preset(paper, "paper");
  try {
    load_config_file(paper, path);
    FAIL() << "a file starting from default was applied on top of paper";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ":1: preset: 'default' after 'paper': a configuration starts from one preset");
  }
}

TEST_F(ConfigFile, ErrorsNameTheFileTheLineAndTheKey) {
  write("pes: 4\n\nsearch_units: 0\n");
  MachineConfig c;
  try {
    load_config_file(c, path);
    FAIL() << "search_units: 0 was taken";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(std::string(e.what()),
              path + ":3: search_units: expected an integer in 1..256, got 0");
  }
  write("pes: 4\nwarp_drive: 9\n");
  EXPECT_THROW(load_config_file(c, path), ConfigError);
  EXPECT_THROW(load_config_file(c, path + ".missing"), ConfigError);
}

}  // namespace
}  // namespace rtm
