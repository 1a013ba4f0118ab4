// The interconnect model counts picoseconds itself (net/interconnect.h); its hops must be exactly
// the times the original link computed with SystemC: sc_time(latency, SC_NS) plus
// sc_time(bytes / bandwidth, SC_SEC), each rounded by the kernel.
#include <random>

#include <gtest/gtest.h>
#include <systemc>

#include "machine/sim_time.h"
#include "net/interconnect.h"

namespace rtm {
namespace {

TEST(InterconnectTime, AHopIsTheOriginalLinksSystemCTimeToThePicosecond) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> latency(0, 1e6), log_bandwidth(-3, 9);
  std::uniform_int_distribution<uint64_t> bytes(0, uint64_t(1) << 24);
  for (int i = 0; i < 20000; ++i) {
    MachineConfig c;
    c.link_latency_ns = i % 7 ? latency(rng) : std::round(latency(rng) / 1000) * 1000;
    c.link_bandwidth_mb_s = std::pow(10.0, log_bandwidth(rng));
    const uint64_t b = i % 5 ? bytes(rng) : uint64_t(i);
    const double seconds = double(b) / (c.link_bandwidth_mb_s * 1e6);
    if (seconds * 1e12 > 1e18) continue;
    const sc_core::sc_time original = sc_core::sc_time(c.link_latency_ns, sc_core::SC_NS) +
                                      sc_core::sc_time(seconds, sc_core::SC_SEC);
    EXPECT_EQ(Interconnect(c, kTimeHorizonTicks).hop_ticks(b), original.value())
        << c.link_latency_ns << " ns, " << c.link_bandwidth_mb_s << " MB/s, " << b << " bytes";
  }
}

}  // namespace
}  // namespace rtm
