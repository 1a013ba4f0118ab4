#include "byte_size.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace rtm {

uint64_t parse_byte_size(const std::string& text) {
  const auto bad = [&]() -> uint64_t {
    throw std::invalid_argument(
        "expected a size such as 512M or 4G (K, M, G, T: powers of 1024), got '" + text + "'");
  };
  if (text.empty() || !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.'))
    return bad();
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  std::string unit(end);
  for (char& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (!unit.empty() && unit.back() == 'B') unit.pop_back();  // KB, MB, ... and B
  if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();   // KiB, MiB, ...
  double scale = 1;
  if (unit == "K")
    scale = 0x1p10;
  else if (unit == "M")
    scale = 0x1p20;
  else if (unit == "G")
    scale = 0x1p30;
  else if (unit == "T")
    scale = 0x1p40;
  else if (!unit.empty())
    return bad();
  const double bytes = x * scale;
  if (!std::isfinite(bytes) || bytes < 1 || bytes > 0x1p60) return bad();
  return uint64_t(bytes);
}

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) bytes /= 1024, ++u;
  char s[32];
  std::snprintf(s, sizeof s, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return s;
}

}  // namespace rtm
