#include "frame/bottleneck.h"

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

#include "units/unit_table.h"

namespace rtm {

const std::vector<std::string>& bottleneck_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = {"host_preprocessing", "interconnect", "pe_voxelisation",
                                  "memory"};
    for (const UnitSpec& u : unit_table())
      if (u.in_utilisation) n.push_back(u.name);
    for (const char* verdict : {"loop_credits", "waiting_for_tiles", "load_imbalance", "latency"})
      n.push_back(verdict);
    return n;
  }();
  return names;
}

namespace {

std::string percent(double share) {
  char s[16];
  std::snprintf(s, sizeof s, "%.1f%%", 100 * share);
  return s;
}

}  // namespace

Bottleneck bottleneck(const FrameProfile& p) {
  const double host = p.total > 0 ? p.host_preprocess / p.total : 0;
  const double link = p.total > 0 ? (p.transfer + p.gather) / p.total : 0;
  const double voxels = p.total > 0 ? p.pe_voxelisation / p.total : 0;
  const char* host_or_link = voxels > std::max(host, link) ? "pe_voxelisation"
                             : host >= link                ? "host_preprocessing"
                                                           : "interconnect";
  const std::string host_and_link =
      "host pre-processing " + percent(host) +
      (voxels > 0 ? ", the link " + percent(link) + " and the PEs' voxelisation " + percent(voxels)
                  : " and the link " + percent(link)) +
      " of the frame" +
      (p.gather_streamed && p.total > 0
           ? " (the streamed gather's tail after the last PE " + percent(p.gather / p.total) + ")"
           : "");
  if (p.pipelined) {
    // Pipelined frames: the host, the link or the PEs, whichever takes longest a frame; of the
    // PEs', their voxelisation or their work, whichever is the more.
    const double work = p.total > 0 ? p.pe / p.total : 0;
    if (work + voxels <= std::max(host, link))
      return {host >= link ? "host_preprocessing" : "interconnect", host_and_link};
    if (voxels >= work) return {"pe_voxelisation", host_and_link};
  } else if (host + link + voxels >= 0.5) {
    // One frame: the serial parts against the rest.
    return {host_or_link, host_and_link};
  }
  if (p.memory_access >= 0.5 || p.memory_wait >= 0.5)
    return {"memory",
            "reads of local memory " + percent(p.memory_access) +
                " of the units' item-cycles, results waiting for it " + percent(p.memory_wait) +
                " of the PEs' working windows (summed over the units); the busiest port busy " +
                percent(p.memory_port) + " of the frame"};

  // The unit whose entry is taken most (of equal ones, the first in the unit table).
  double share = -1;
  const char* unit = "";
  for (const UnitSpec& s : unit_table())
    if (s.in_utilisation && p.issue[s.kind] > share) share = p.issue[s.kind], unit = s.name;
  if (share >= 0.6)
    return {unit, "its entry taken " + percent(share) + " of the PEs' working windows"};

  // Nothing saturated: the reason says how close the busiest unit came.
  const std::string busiest =
      std::string("no unit saturated (the busiest, ") + unit + ", " + percent(share) + ")";
  if (p.credit_stall >= 0.3)
    return {"loop_credits", "the front buffer had rays but no credit " + percent(p.credit_stall) +
                                " of the PEs' working windows; " + busiest};
  if (p.tile_wait >= 0.3)
    return {"waiting_for_tiles", "the PEs' loops were empty, waiting for a tile, " +
                                     percent(p.tile_wait) + " of their working windows; " +
                                     busiest};
  if (p.imbalance >= 1.3) {
    char s[64];
    std::snprintf(s, sizeof s, "the longest PE works %.2f x the mean; ", p.imbalance);
    return {"load_imbalance", s + busiest};
  }
  if (std::max({host, link, voxels}) >= 0.25) return {host_or_link, host_and_link + "; " + busiest};
  return {"latency", busiest};
}

}  // namespace rtm
