#include "machine/sim_time.h"

#include <cmath>
#include <cstdio>

namespace rtm {

namespace {

[[noreturn]] void past_horizon(double ticks, const std::string& what) {
  const std::string msg =
      what + " would take " + describe_ticks(ticks) + " from " +
      describe_ticks(double(sc_core::sc_time_stamp().value())) + ", past the " +
      describe_ticks(double(kTimeHorizonTicks)) +
      " of simulated time a frame may take (SystemC counts time in 64-bit picoseconds)";
  SC_REPORT_ERROR("rtm/time", msg.c_str());
  throw std::logic_error(
      msg);  // not reached: errors throw (main sets it), but never return a wrapped time
}

void check(double ticks, const std::string& what) {
  const double now = double(sc_core::sc_time_stamp().value());
  if (!(ticks >= 0 && now + ticks < double(kTimeHorizonTicks))) past_horizon(ticks, what);
}

}  // namespace

std::string describe_ticks(double ticks) {
  char s[64];
  const double days = ticks * 1e-12 / 86400;
  if (days >= 1)
    std::snprintf(s, sizeof s, "%.3g ps (%.3g days)", ticks, days);
  else
    std::snprintf(s, sizeof s, "%.3g ps (%.3g s)", ticks, ticks * 1e-12);
  return s;
}

sc_core::sc_time checked_periods(const sc_core::sc_time& period, double count,
                                 const std::string& what) {
  check(double(period.value()) * count, what);
  return period * count;
}

sc_core::sc_time checked_seconds(double seconds, const std::string& what) {
  check(seconds / sc_core::sc_get_time_resolution().to_seconds(), what);
  return sc_core::sc_time(seconds, sc_core::SC_SEC);
}

}  // namespace rtm
