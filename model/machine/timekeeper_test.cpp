#define SC_INCLUDE_DYNAMIC_PROCESSES  // sc_spawn
#include "machine/timekeeper.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace rtm {
namespace {

/// Processes that sleep through the keeper and log who woke when.
struct Sleepers : sc_core::sc_module {
  struct Plan {
    int rank;
    std::vector<int> naps_ns;
  };
  SC_HAS_PROCESS(Sleepers);
  Sleepers(sc_core::sc_module_name name, std::vector<Plan> plans)
      : sc_module(name), keeper("keeper"), plans_(plans) {
    for (size_t i = 0; i < plans_.size(); ++i) {
      sleepers_.push_back(std::make_unique<Sleeper>(&keeper, plans_[i].rank));
      sc_core::sc_spawn([this, i] { run(i); });
    }
  }
  void run(size_t i) {
    for (int ns : plans_[i].naps_ns) {
      (*sleepers_[i])(sc_core::sc_time(ns, sc_core::SC_NS));
      log.push_back(std::to_string(int(sc_core::sc_time_stamp().to_seconds() * 1e9 + 0.5)) + ":" +
                    std::to_string(plans_[i].rank));
    }
  }
  Timekeeper keeper;
  std::vector<std::string> log;

 private:
  std::vector<Plan> plans_;
  std::vector<std::unique_ptr<Sleeper>> sleepers_;
};

TEST(Timekeeper, WakesWhoeverIsDueAtOneTimeByRankWhateverTheOrderTheyWentToSleep) {
  // Ranks 3, 1 and 2 all due at 10 ns (rank 3 by two naps, the others by one), rank 0 at 7 and
  // then 10 ns, rank 5 at 4 ns: each time, lowest rank first.
  Sleepers s("sleepers", {{3, {5, 5}}, {1, {10}}, {5, {4}}, {2, {10}}, {0, {7, 3}}});
  sc_core::sc_start();
  EXPECT_EQ(s.log, (std::vector<std::string>{"4:5", "5:3", "7:0", "10:0", "10:1", "10:2", "10:3"}));
}

}  // namespace
}  // namespace rtm
