// The progress line rtm redraws on a terminal while a frame renders, on the machine or the
// reference: the phase of the frame, then one measure of the work, the frame's pixels ("at pixel
// N of all": on the machine those whose primary ray has been handed out, on the reference those
// finished), with the wall time so far, the rate and the time left at that rate; the reference
// adds the rays traced, which still move while one pixel's ray tree grows.
#pragma once

#include <cstdint>
#include <string>

namespace rtm {

struct Progress {
  const char* phase = "host";  ///< host, transfer, PEs or gather (docs/machine.md, the phases), or reference
  uint64_t pixels_started = 0, pixels = 0;
  double seconds = 0;           ///< wall time since the render started
  uint64_t rays = 0;            ///< rays traced so far; 0: not shown
  uint64_t resident_bytes = 0;  ///< the process's memory; 0: unknown
};

/// One line, at most 79 characters.
std::string progress_line(const Progress& p);

/// A memory size as the budget messages give it: "220.0 MiB", "1.50 GiB".
std::string bytes_text(uint64_t bytes);

/// The process's resident size now (/proc/self/statm); 0 where it cannot be read. What the
/// memory budget is held to while a render runs.
uint64_t resident_bytes();

}  // namespace rtm
