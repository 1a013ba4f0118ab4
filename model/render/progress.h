// The progress line rtm redraws on a terminal while a frame renders, on the machine or the
// reference: the phase of the frame, then one measure of the work, the frame's pixels ("at pixel
// N of all": on the machine those whose primary ray has been handed out, on the reference those
// finished), with the wall time so far, the rate and the time left at that rate; the reference
// adds the rays traced, which still move while one pixel's ray tree grows. Before the frame, the
// host's long steps (a mesh's load, the grid build, the voxelisation) show the same line with
// what they count (StepLine).
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace rtm {

struct Progress {
  const char* phase =
      "host";  ///< host, transfer, PEs or gather (docs/machine.md, the phases), or reference
  const char* item = "pixel";  ///< what is counted; with pixels 0, nothing is
  uint64_t pixels_started = 0, pixels = 0;
  double seconds = 0;           ///< wall time since the render started
  uint64_t rays = 0;            ///< rays traced so far; 0: not shown
  uint64_t resident_bytes = 0;  ///< the process's memory; 0: unknown
};

/// One line, at most 79 characters.
std::string progress_line(const Progress& p);

/// The line of the host's steps before a frame, on stderr when `enabled` (a terminal, no -q):
/// nothing in its first second, then redrawn at most twice a second with the step's name, what
/// it has done, its own time and the process's memory; erased at the end. Called as a
/// StepProgress (geom/grid.h) from one thread at a time.
class StepLine {
 public:
  /// `out` and `delay` (the quiet first second) are for tests.
  explicit StepLine(bool enabled, std::FILE* out = stderr,
                    std::chrono::milliseconds delay = std::chrono::seconds(1))
      : enabled_(enabled), out_(out), delay_(delay) {}
  StepLine(const StepLine&) = delete;
  StepLine& operator=(const StepLine&) = delete;
  ~StepLine() { erase(); }
  void operator()(const char* step, const char* item, uint64_t done, uint64_t total);
  /// Erases the line, if one is drawn, before other output.
  void erase();

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_, drew_ = false;
  std::FILE* out_;
  Clock::duration delay_;
  std::string step_;
  Clock::time_point start_ = Clock::now(), step_start_ = start_, last_draw_{};  // none yet
};

/// A memory size as the budget messages give it: "220.0 MiB", "1.50 GiB".
std::string bytes_text(uint64_t bytes);

/// The process's resident size now (/proc/self/statm); 0 where it cannot be read. What the
/// memory budget is held to while a render runs.
uint64_t resident_bytes();

}  // namespace rtm
