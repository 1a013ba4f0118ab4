// The clocked MAC against the schedule and MacTiming: the same sums, bit for bit, and the same
// cycle counts, on random jobs (one simulation in this process).
#include "machine/clocked_mac.h"

#include <random>

#include <gtest/gtest.h>

#include "units/test_mac_jobs.h"

namespace rtm {
namespace {

TEST(MacTiming, MatchesTheHandCountForOnePrimitive) {
  // 28 products one per cycle; the last issues at cycle 27, leaves multiplier 1 at 28,
  // multiplier 2 at 29 and the adder at 30: 31 cycles including cycle 0.
  const MacTiming t(1, 1, 0);
  EXPECT_EQ(t.done(0), 30u);
  EXPECT_EQ(t.job_cycles(1), 31u);
  EXPECT_EQ(t.job_cycles(3), 31u + 2 * 28);
  EXPECT_EQ(t.job_cycles(0), 0u);
  // A slow coefficient load becomes the period; a slow adder stretches the issue interval.
  EXPECT_EQ(MacTiming(1, 1, 40).period(), 40u);
  EXPECT_EQ(MacTiming(2, 3, 0).done(0), 27u * 3 + 4 + 3);
}

struct Case {
  MacTiming timing;
  Precision precision;
};

class Driver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Driver);
  Driver(sc_core::sc_module_name n, std::vector<ClockedMac*> macs, std::vector<Case> cases)
      : sc_module(n), macs_(std::move(macs)), cases_(std::move(cases)) {
    SC_THREAD(run);
  }
  int jobs = 0, value_mismatches = 0, cycle_mismatches = 0, time_mismatches = 0;

 private:
  void run() {
    std::mt19937_64 rng(12345);
    std::uniform_int_distribution<int> prims(1, 6);
    const sc_core::sc_time period(10, sc_core::SC_NS);
    for (int round = 0; round < 60; ++round) {
      for (size_t m = 0; m < macs_.size(); ++m) {
        const Case& c = cases_[m];
        const int n = prims(rng);
        // Every other round runs sparse schedules: random coefficient words are zero and skipped.
        const bool sparse = round % 2 == 1;
        std::vector<int> counts;
        const MacJob job = random_job(rng, n, c.precision, sparse, counts);
        const sc_core::sc_time start = sc_core::sc_time_stamp();
        const ClockedMac::Done done = macs_[m]->run(job);
        ++jobs;
        if (done.cycles != c.timing.job(counts).cycles() ||
            (!sparse && done.cycles != c.timing.job_cycles(n)))
          ++cycle_mismatches;
        if (sc_core::sc_time_stamp() - start != period * double(done.cycles)) ++time_mismatches;
        for (int p = 0; p < n; ++p)
          if (done.sums[size_t(p)] != expected_sums(job, size_t(p), c.precision))
            ++value_mismatches;
        sc_core::wait(period * 3);
      }
    }
    sc_core::sc_stop();  // the clock would run on forever
  }
  std::vector<ClockedMac*> macs_;
  std::vector<Case> cases_;
};

TEST(ClockedMac, AgreesWithTheScheduleAndTheTimingFormulaOnRandomFullAndSparseJobs) {
  const sc_core::sc_time period(10, sc_core::SC_NS);
  sc_core::sc_clock clk("clk", period, 0.5, period / 2, true);
  const std::vector<Case> cases = {{MacTiming(1, 1, 0), Precision::Fp32},
                                   {MacTiming(1, 1, 4), Precision::Fp64},
                                   {MacTiming(2, 3, 5), Precision::Fp32},
                                   {MacTiming(3, 1, 90), Precision::Fp64},
                                   {MacTiming(1, 1, 12), Precision::Fp32}};
  std::vector<std::unique_ptr<ClockedMac>> macs;
  std::vector<ClockedMac*> raw;
  for (size_t i = 0; i < cases.size(); ++i) {
    macs.push_back(std::make_unique<ClockedMac>(("mac" + std::to_string(i)).c_str(),
                                                cases[i].timing, cases[i].precision, period));
    macs.back()->clk(clk);
    raw.push_back(macs.back().get());
  }
  Driver d("driver", raw, cases);
  sc_core::sc_start();
  EXPECT_EQ(d.jobs, 60 * int(cases.size()));
  EXPECT_EQ(d.value_mismatches, 0);
  EXPECT_EQ(d.cycle_mismatches, 0);
  EXPECT_EQ(d.time_mismatches, 0);
}

}  // namespace
}  // namespace rtm
