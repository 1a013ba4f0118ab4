// The checked time arithmetic: a delay that would end past the horizon is an error, never a
// wrapped or saturated sc_time.
#include "machine/sim_time.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

std::string refusal(const sc_core::sc_time& period, double count) {
  try {
    checked_periods(period, count, "the test's delay");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(SimTime, DelaysWithinTheHorizonAreExactlySystemCsOwn) {
  const sc_core::sc_time period(7.5, sc_core::SC_NS);
  EXPECT_EQ(checked_periods(period, 1e6, "x"), period * 1e6);
  EXPECT_EQ(checked_periods(period, 0, "x"), sc_core::SC_ZERO_TIME);
  EXPECT_EQ(checked_seconds(0.25, "x"), sc_core::sc_time(0.25, sc_core::SC_SEC));
  // Just inside: the horizon (2^62 ps) in 1 µs periods.
  const sc_core::sc_time us(1, sc_core::SC_US);
  EXPECT_EQ(refusal(us, double(kTimeHorizonTicks) / 1e6 - 1), "");
}

TEST(SimTime, ADelayPastTheHorizonIsAnErrorNamingIt) {
  const sc_core::sc_time us(1, sc_core::SC_US);
  // 65536 host cycles for each of 2^40 references at 1 µs: 7e22 ps, past 2^64 ps, where sc_time's
  // own operator* would convert an out-of-range double (undefined behaviour).
  const std::string why = refusal(us, 65536.0 * double(uint64_t(1) << 40));
  EXPECT_NE(why.find("the test's delay would take 7.21e+22 ps"), std::string::npos) << why;
  EXPECT_NE(why.find("past the 4.61e+18 ps (53.4 days) of simulated time a frame may take"),
            std::string::npos)
      << why;
  EXPECT_NE(refusal(us, double(kTimeHorizonTicks) / 1e6), "");
  EXPECT_NE(refusal(us, HUGE_VAL), "");
  EXPECT_NE(refusal(us, std::nan("")), "");
  try {
    checked_seconds(1e300 / 1e-3, "a transfer");  // a petabyte at 1 kB/s
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("a transfer would take"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rtm
