#include "render/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace rtm {
namespace {

std::string duration(double s) {
  char t[32];
  if (s < 60)
    std::snprintf(t, sizeof t, "%.1f s", s);
  else if (s < 3600)
    std::snprintf(t, sizeof t, "%dm%02ds", int(s / 60), int(std::fmod(s, 60)));
  else
    std::snprintf(t, sizeof t, "%dh%02dm", int(s / 3600), int(std::fmod(s, 3600) / 60));
  return t;
}

}  // namespace

std::string progress_line(const Progress& p) {
  const double share = p.pixels ? double(p.pixels_started) / double(p.pixels) : 0;
  // The rate over the whole run so far: the host's phases take little wall time.
  const double rate = p.seconds > 0 ? double(p.pixels_started) / p.seconds : 0;
  const bool pixels = std::string(p.item) == "pixel";
  char line[160];
  int n =
      p.pixels
          ? std::snprintf(line, sizeof line, "%s: at %s %llu/%llu (%.1f%%), %s", p.phase, p.item,
                          (unsigned long long)p.pixels_started, (unsigned long long)p.pixels,
                          100 * share, duration(p.seconds).c_str())
          : std::snprintf(line, sizeof line, "%s: %s", p.phase, duration(p.seconds).c_str());
  // A host step's rate is no figure anyone compares: its time left is.
  if (p.pixels && rate > 0 && pixels && n < int(sizeof line))
    n += std::snprintf(line + n, sizeof line - size_t(n), ", %.0f px/s", rate);
  if (p.pixels && rate > 0 && n < int(sizeof line))
    n += std::snprintf(line + n, sizeof line - size_t(n), ", ETA %s",
                       duration(double(p.pixels - p.pixels_started) / rate).c_str());
  if (p.rays && n < int(sizeof line))
    n += std::snprintf(line + n, sizeof line - size_t(n), ", %.3g rays", double(p.rays));
  if (p.resident_bytes && n < int(sizeof line))
    std::snprintf(line + n, sizeof line - size_t(n), ", %.2f GiB",
                  double(p.resident_bytes) / double(1 << 30));
  return std::string(line).substr(0, 79);
}

void StepLine::operator()(const char* step, const char* item, uint64_t done, uint64_t total) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (step_ != step) {
    step_ = step;
    step_start_ = now;
  }
  if (now - start_ < delay_ || now - last_draw_ < std::chrono::milliseconds(500)) return;
  last_draw_ = now;
  Progress p;
  p.phase = step;
  p.item = item;
  p.pixels_started = done;
  p.pixels = total;
  p.seconds = std::chrono::duration<double>(now - step_start_).count();
  p.resident_bytes = resident_bytes();
  std::fprintf(out_, "\r%-79s", progress_line(p).c_str());
  std::fflush(out_);
  drew_ = true;
}

void StepLine::erase() {
  if (drew_) std::fprintf(out_, "\r%80s\r", "");
  drew_ = false;
}

std::string bytes_text(uint64_t bytes) {
  const bool mib = bytes < (uint64_t(1) << 30);
  char t[32];
  std::snprintf(t, sizeof t, mib ? "%.1f MiB" : "%.2f GiB",
                double(bytes) / double(mib ? 1 << 20 : 1 << 30));
  return t;
}

uint64_t resident_bytes() {
  std::ifstream f("/proc/self/statm");
  uint64_t size = 0, resident = 0;
  if (!(f >> size >> resident)) return 0;
  return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

}  // namespace rtm
