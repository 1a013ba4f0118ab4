// The progress line rtm redraws on a terminal while a frame simulates: the phase of the frame,
// then one measure of the work, the frame's pixels whose primary ray has been handed out ("at
// pixel N of all"), with the wall time so far, the rate and the time left at that rate.
#pragma once

#include <cstdint>
#include <string>

namespace rtm {

struct Progress {
  const char* phase = "host";  ///< host, transfer, PEs or gather (docs/machine.md, the phases)
  uint64_t pixels_started = 0, pixels = 0;
  double seconds = 0;           ///< wall time since the simulation started
  uint64_t resident_bytes = 0;  ///< the process's memory; 0: unknown
};

/// One line, at most 79 characters.
std::string progress_line(const Progress& p);

}  // namespace rtm
