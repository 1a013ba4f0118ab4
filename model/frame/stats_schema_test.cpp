// The stats schema (docs/stats.schema.json) names what the tables declare: every unit of the unit
// table in each per-unit group and in the flat summary, and exactly the bottlenecks the model
// gives.
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cost/unit_cost.h"
#include "frame/bottleneck.h"
#include "units/unit_table.h"

namespace rtm {
namespace {

nlohmann::json schema() {
  std::ifstream in(std::string(RTM_SOURCE_DIR) + "/docs/stats.schema.json");
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

std::vector<std::string> utilisation_units() {
  std::vector<std::string> names;
  for (const UnitSpec& u : unit_table())
    if (u.in_utilisation) names.push_back(u.name);
  return names;
}

TEST(StatsSchema, NamesEveryUnitOfTheUnitTable) {
  const nlohmann::json s = schema();
  const nlohmann::json& defs = s["$defs"];
  const std::vector<std::string> units = utilisation_units();
  EXPECT_EQ(defs["units"]["required"].get<std::vector<std::string>>(), units);
  for (const char* group : {"unit_shares", "unit_means", "unit_cycles"})
    EXPECT_EQ(defs[group]["maxProperties"], units.size()) << group;
  const nlohmann::json& summary = defs["summary"];
  const auto required = summary["required"].get<std::vector<std::string>>();
  for (const std::string& u : units)
    for (const char* prefix : {"util_", "pe_util_", "pe_issue_", "pe_starved_"}) {
      const std::string key = prefix + u;
      EXPECT_TRUE(summary["properties"].contains(key)) << key;
      EXPECT_NE(std::find(required.begin(), required.end(), key), required.end()) << key;
    }
}

TEST(StatsSchema, TheCostNamesEveryUnitAndElement) {
  const nlohmann::json s = schema();
  const nlohmann::json& defs = s["$defs"];
  std::vector<std::string> units, elements;
  for (const UnitSpec& u : unit_table()) units.push_back(u.name);
  EXPECT_EQ(defs["cost"]["properties"]["units"]["required"].get<std::vector<std::string>>(), units);
  for (size_t o = 0; o < kOps; ++o) {
    const std::string n = op_name(Op(o));
    if (n.rfind("int_", 0) == 0) {
      elements.push_back(n);
    } else {
      elements.push_back(n + "_fp32");
      elements.push_back(n + "_fp64");
    }
  }
  EXPECT_EQ(defs["unit_cost"]["properties"]["elements"]["propertyNames"]["enum"]
                .get<std::vector<std::string>>(),
            elements);
  const auto required = defs["summary"]["required"].get<std::vector<std::string>>();
  for (const std::string& u : units) {
    const std::string key = "energy_" + u + "_j";
    EXPECT_TRUE(defs["summary"]["properties"].contains(key)) << key;
    EXPECT_NE(std::find(required.begin(), required.end(), key), required.end()) << key;
  }
}

TEST(StatsSchema, NamesTheBottlenecksTheModelGives) {
  EXPECT_EQ(schema()["$defs"]["bottleneck"]["enum"].get<std::vector<std::string>>(),
            bottleneck_names());
}

}  // namespace
}  // namespace rtm
