#include "frame/gtkw.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "render/image_io.h"

namespace rtm {
namespace {

// GTKWave 3.3's trace flags (analyzer.h, TR_*): the flag word of the traces that follow.
constexpr unsigned kDec = 0x4, kBin = 0x8, kRightJustify = 0x20, kBlank = 0x200, kReal = 0x40000,
                   kGroupBegin = 0x800000, kGroupEnd = 0x1000000;

// The window GTKWave opens, and the width of its name column: the longest alias fits.
constexpr int kWidth = 1600, kHeight = 900, kNamesWidth = 340;
// Of the window's width, what the waves get (the rest: names, borders, scroll bar), kept a little
// short so the whole range is in view.
constexpr double kWavePixels = kWidth - kNamesWidth - 120;

std::vector<std::string> parts_of(const std::string& name) {
  std::vector<std::string> parts;
  std::istringstream s(name);
  for (std::string p; std::getline(s, p, '.');) parts.push_back(p);
  return parts;
}

/// The PE and unit a signal machine.peN.UNIT... belongs to: "peN", "peN/UNIT" ("peN/FIFOs" for
/// a FIFO of the PE's own).
std::pair<std::string, std::string> group_of(const std::string& name) {
  const std::vector<std::string> parts = parts_of(name);
  if (parts.size() < 4) return {"machine", "machine"};
  const std::string& unit = parts[2];
  const bool fifo = unit.size() > 5 && unit.compare(unit.size() - 5, 5, "_fifo") == 0;
  return {parts[1], parts[1] + "/" + (fifo ? "FIFOs" : unit)};
}

std::string flags(unsigned f) {
  char text[16];
  std::snprintf(text, sizeof text, "@%x\n", f);
  return text;
}

}  // namespace

std::string gtkw_alias(const std::string& signal) {
  std::vector<std::string> parts = parts_of(signal);
  if (!parts.empty() && parts.front() == "machine") parts.erase(parts.begin());
  std::string alias;
  for (const std::string& p : parts) alias += (alias.empty() ? "" : "/") + p;
  return alias;
}

void write_gtkw(const std::string& gtkw_path, const std::string& vcd_path,
                const std::vector<TracedSignal>& signals, const GtkwView& view) {
  // GTKWave shows 2^-zoom ns over 200 pixels.
  const double span = double(std::max<uint64_t>(1, view.to_ns - view.from_ns));
  const double zoom = -std::log2(span * 200 / kWavePixels);
  char clock[32];
  std::snprintf(clock, sizeof clock, "%g", view.clock_ns);
  const std::string cycle = std::string("PE cycle = time / ") + clock + " ns";
  std::ostringstream out;
  out << "[*] rtm waveform; " << cycle
      << "\n"
      // Both absolute: GTKWave then finds the VCD from any folder, and after both were moved.
      << "[dumpfile] \"" << std::filesystem::absolute(vcd_path).string() << "\"\n"
      << "[savefile] \"" << std::filesystem::absolute(gtkw_path).string() << "\"\n"
      << "[timestart] " << view.from_ns << "\n"
      << "[size] " << kWidth << " " << kHeight << "\n"
      << "[pos] -1 -1\n";
  char zoom_line[64];
  std::snprintf(zoom_line, sizeof zoom_line, "*%.6f -1\n", zoom);  // no marker
  out << zoom_line << "[signals_width] " << kNamesWidth << "\n[sst_expanded] 0\n";
  out << flags(kBlank) << "-" << cycle << "\n";

  // Groups in the order their first signal was traced; GTKWave closes them in reverse.
  std::vector<std::string> open;
  auto close_to = [&](size_t depth) {
    for (; open.size() > depth; open.pop_back())
      out << flags(kBlank | kGroupEnd) << "-" << open.back() << "\n";
  };
  auto enter = [&](size_t depth, const std::string& title) {
    if (open.size() > depth && open[depth] == title) return;
    close_to(depth);
    out << flags(kBlank | kGroupBegin) << "-" << title << "\n";
    open.push_back(title);
  };
  for (const TracedSignal& s : signals) {
    const auto [pe, unit] = group_of(s.name);
    enter(0, pe);
    enter(1, unit);
    const unsigned f = s.format == TracedSignal::Format::Bit    ? kBin | kRightJustify
                       : s.format == TracedSignal::Format::Real ? kReal | kDec | kRightJustify
                                                                : kDec | kRightJustify;
    // The VCD's top scope is SystemC's; a multi-bit value's name carries its bit range.
    out << flags(f) << "+{" << gtkw_alias(s.name) << "} SystemC." << s.name
        << (s.format == TracedSignal::Format::Decimal ? "[" + std::to_string(s.bits - 1) + ":0]"
                                                      : "")
        << "\n";
  }
  close_to(0);
  write_text_atomically(gtkw_path, out.str());
}

}  // namespace rtm
