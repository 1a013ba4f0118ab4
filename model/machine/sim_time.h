// Simulated time as SystemC holds it: a 64-bit count of ticks of its resolution (1 ps, the
// default, which rtm keeps), 213 days in all. sc_time's own arithmetic wraps or converts an
// out-of-range double silently; every long delay the machine computes goes through here.
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

namespace rtm {

/// A frame must end before this: 2^62 ps, 53 days of simulated time. Well below 2^64, so no
/// single delay scheduled before the machine's monitor sees the horizon passed can wrap.
constexpr uint64_t kTimeHorizonTicks = uint64_t(1) << 62;

/// "4.6e+18 ps (53 days)": a tick count as people read it.
std::string describe_ticks(double ticks);

/// `count` times `period` (rounded as sc_time's own operator* rounds), or, if that would end past
/// the horizon counted from now, an SC_REPORT_ERROR of type "rtm/time" naming `what`.
sc_core::sc_time checked_periods(const sc_core::sc_time& period, double count,
                                 const std::string& what);
/// `seconds` of simulated time, likewise checked.
sc_core::sc_time checked_seconds(double seconds, const std::string& what);

}  // namespace rtm
