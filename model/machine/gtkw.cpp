#include "machine/gtkw.h"

#include <map>
#include <sstream>
#include <vector>

#include "render/image_io.h"

namespace rtm {
namespace {

/// The group of a signal machine.peN.UNIT...: "PE N UNIT", or "PE N FIFOs" for a PE's FIFOs.
std::string group_of(const std::string& name) {
  std::vector<std::string> parts;
  std::istringstream s(name);
  for (std::string p; std::getline(s, p, '.');) parts.push_back(p);
  if (parts.size() < 4) return "machine";
  const std::string pe = "PE " + parts[1].substr(2);
  const std::string& unit = parts[2];
  const bool fifo = unit.size() > 5 && unit.compare(unit.size() - 5, 5, "_fifo") == 0;
  return pe + " " + (fifo ? "FIFOs" : unit);
}

}  // namespace

void write_gtkw(const std::string& gtkw_path, const std::string& vcd_path, const Waveform& wave) {
  // GTKWave's trace flags: 0x4 decimal, 0x8 binary, 0x20 right-justified, 0x40000 real.
  static const char* const kFlags[] = {"@28", "@24", "@40024"};
  std::vector<std::string> order;
  std::map<std::string, std::vector<const Waveform::Signal*>> groups;
  for (const Waveform::Signal& s : wave.signals()) {
    auto& g = groups[group_of(s.name)];
    if (g.empty()) order.push_back(group_of(s.name));
    g.push_back(&s);
  }
  std::ostringstream out;
  out << "[dumpfile] \"" << vcd_path << "\"\n[timestart] 0\n";
  for (const std::string& title : order) {
    out << "@200\n-" << title << "\n";
    for (const Waveform::Signal* s : groups[title]) {
      // The VCD's top scope is SystemC; a 32-bit value's name carries its bit range.
      out << kFlags[int(s->format)] << "\nSystemC." << s->name
          << (s->format == Waveform::Format::Decimal ? "[" + std::to_string(s->bits - 1) + ":0]" : "") << "\n";
    }
  }
  write_text_atomically(gtkw_path, out.str());
}

}  // namespace rtm
