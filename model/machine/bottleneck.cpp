#include "machine/bottleneck.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace rtm {

std::string bottleneck(const FrameProfile& p) {
  const double host = p.total > 0 ? p.host_preprocess / p.total : 0;
  const double link = p.total > 0 ? (p.transfer + p.gather) / p.total : 0;
  if (host + link >= 0.5) return host >= link ? "host_preprocessing" : "interconnect";
  const UnitShares& u = p.issue;
  const std::vector<std::pair<double, const char*>> units = {
      {u.mac, "mac"}, {u.search, "search"}, {u.root, "root"}, {u.shading, "shading"}, {u.front_buffer, "front_buffer"}};
  const auto top = *std::max_element(units.begin(), units.end());
  if (top.first >= 0.6) return top.second;
  if (p.credit_stall >= 0.3) return "loop_credits";
  if (p.imbalance >= 1.3) return "load_imbalance";
  if (std::max(host, link) >= 0.25) return host >= link ? "host_preprocessing" : "interconnect";
  return "latency";
}

}  // namespace rtm
