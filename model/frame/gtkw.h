// The GTKWave save file for a waveform: every signal that was traced, in the order traced, one
// group per PE holding one group per unit (a PE's FIFOs in a group of their own), each signal
// under its hierarchical name; the window opens large, on the time the traced PEs worked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rtm {

/// One signal traced into the VCD, named after the object hierarchy (sc_object::name() + "." +
/// the signal).
struct TracedSignal {
  enum class Format { Bit, Decimal, Real };
  std::string name;  ///< hierarchical, e.g. machine.pe0.search2.busy
  Format format;
  int bits;  ///< of a Decimal value
};

/// What the save file shows first.
struct GtkwView {
  uint64_t from_ns = 0, to_ns = 0;  ///< the time range in view (the VCD's time unit is 1 ns)
  double clock_ns = 10;             ///< the PE clock period: how the ruler's ns become cycles
};

void write_gtkw(const std::string& gtkw_path, const std::string& vcd_path,
                const std::vector<TracedSignal>& signals, const GtkwView& view);

/// The name GTKWave shows for a traced signal: its hierarchy below the machine, joined by '/'
/// (GTKWave cuts a name at its dots and shows only the last part, four `busy` in a row).
std::string gtkw_alias(const std::string& signal);

}  // namespace rtm
