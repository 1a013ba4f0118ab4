// The clock-level MAC without a kernel: its sums against the schedule (form_abg) and its cycles
// against MacTiming on random jobs, and the MAC driven edge by edge (EdgeByEdgeMac) against the
// fast pipeline's due times, with and without a stalled result holding it.
#include "units/clock_level_mac.h"

#include <random>

#include <gtest/gtest.h>

#include "units/test_mac_jobs.h"

namespace rtm {
namespace {

TEST(ClockLevelMac, GivesTheScheduleSumsInTheCyclesMacTimingCounts) {
  std::mt19937_64 rng(777);
  const std::pair<MacTiming, Precision> cases[] = {{MacTiming(1, 1, 0), Precision::Fp32},
                                                   {MacTiming(2, 3, 5), Precision::Fp64},
                                                   {MacTiming(3, 1, 90), Precision::Fp32}};
  for (const auto& [timing, precision] : cases) {
    ClockLevelMac mac(timing, precision);
    for (int round = 0; round < 40; ++round) {
      std::vector<int> counts;
      const MacJob job = random_job(rng, 1 + int(rng() % 5), precision, round % 2, counts);
      mac.start(job);
      uint64_t edges = 0;
      ClockLevelMac::Done done;
      while (!mac.finish(done)) {
        mac.edge();
        ASSERT_LT(++edges, 100000u) << "the job never finishes";
      }
      EXPECT_EQ(done.cycles, timing.job(counts).cycles());
      EXPECT_EQ(edges, done.cycles) << "a job posted to an idle MAC starts at its next edge";
      EXPECT_TRUE(mac.idle());
      for (size_t k = 0; k < counts.size(); ++k)
        EXPECT_EQ(done.sums[k], expected_sums(job, k, precision)) << "primitive " << k;
    }
  }
}

/// A MAC result as the fast model gives it: the schedule's sums.
MacResult fast_result(const MacJob& job, Precision p) {
  MacResult m;
  for (size_t k = 0; k < job.rams.size(); ++k) {
    const auto s = expected_sums(job, k, p);
    m.abg32.push_back({float(s[0]), float(s[1]), float(s[2])});
  }
  return m;
}

TEST(EdgeByEdgeMac, AJobIsDoneWhenTheFastPipelineSaysAndNotACycleBefore) {
  std::mt19937_64 rng(31);
  const MacTiming timing(2, 1, 3);
  const uint64_t period = 1000;
  for (uint64_t late = 0; late < 2; ++late) {
    EdgeByEdgeMac mac(timing, Precision::Fp32, period);
    std::vector<int> counts;
    const MacJob job = random_job(rng, 3, Precision::Fp32, false, counts);
    const uint64_t cycles = timing.job(counts).cycles(), start = 17 * period;
    mac.start(start, job, cycles);
    MacResult fast = fast_result(job, Precision::Fp32);
    const std::string said = mac.check(start + (cycles - 1 + late) * period, fast, true);
    if (late)
      EXPECT_EQ(said, "");
    else
      EXPECT_NE(said.find("still running"), std::string::npos) << said;
  }
}

TEST(EdgeByEdgeMac, AStalledResultHoldsTheNextJobForAsManyCycles) {
  std::mt19937_64 rng(5);
  const MacTiming timing(1, 2, 0);
  const uint64_t period = 10;
  // Job a, then b taken once a's products have issued, while a's drain; a's result waits `held`
  // cycles for room, and the whole pipeline with it. What checking b at `early` cycles before its
  // fast due time, moved by `held`, says.
  auto check_b = [&](uint64_t held, uint64_t early) {
    EdgeByEdgeMac mac(timing, Precision::Fp32, period);
    std::vector<int> ca, cb;
    const MacJob a = random_job(rng, 2, Precision::Fp32, false, ca);
    const MacJob b = random_job(rng, 1, Precision::Fp32, true, cb);
    const MacTiming::Job ja = timing.job(ca), jb = timing.job(cb);
    const uint64_t a_due = 4 + ja.cycles(), b_start = 4 + ja.issue_span();
    EXPECT_LT(b_start, a_due);
    mac.start(4 * period, a, ja.cycles());
    mac.start(b_start * period, b, jb.cycles());
    MacResult fa = fast_result(a, Precision::Fp32), fb = fast_result(b, Precision::Fp32);
    EXPECT_EQ(mac.check(a_due * period, fa, true), "");
    mac.stall(a_due * period, held > 0);
    mac.stall((a_due + held) * period, false);
    mac.retired();
    return mac.check((b_start + jb.cycles() + held - early) * period, fb, true);
  };
  for (uint64_t held = 0; held < 4; ++held) {
    EXPECT_EQ(check_b(held, 0), "") << "held " << held;
    EXPECT_NE(check_b(held, 1).find("still running"), std::string::npos) << "held " << held;
  }
}

TEST(EdgeByEdgeMac, SaysWhenTheFastModelsSumsDiffer) {
  std::mt19937_64 rng(9);
  const MacTiming timing(1, 1, 0);
  EdgeByEdgeMac mac(timing, Precision::Fp32, 10);
  std::vector<int> counts;
  const MacJob job = random_job(rng, 2, Precision::Fp32, false, counts);
  const uint64_t cycles = timing.job(counts).cycles();
  mac.start(0, job, cycles);
  MacResult fast = fast_result(job, Precision::Fp32);
  fast.abg32[1].b = std::nextafter(fast.abg32[1].b, 1e30f);
  EXPECT_NE(mac.check(cycles * 10, fast, true).find("disagrees"), std::string::npos);
  EXPECT_THROW(mac.start(5, job, cycles), std::logic_error) << "an action between cycle boundaries";
}

}  // namespace
}  // namespace rtm
