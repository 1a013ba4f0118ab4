// The host <-> PE interconnect's timing (docs/machine.md, "The host-PE interconnect"): which links
// a transfer uses, when it starts and ends on each, and how long every link was busy carrying how
// many bytes. Plain arithmetic on picoseconds, no SystemC: the host (machine/host.cpp) asks it
// when each transfer happens and waits accordingly.
//
// Every hop takes latency + bytes / bandwidth on one link, and a link carries one hop at a time.
// Transfers take the links in the order they are asked for (first come, first served: a link is
// never given to a later transfer while an earlier one waits for it). A transfer's data counts as
// arrived when its last hop starts, as the original link's did: the PE reads its rays from local
// memory as they come in. A transfer of no bytes (a PE without pixels has no frame buffer) takes
// no link and no time, as on the original link.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/config.h"

namespace rtm {

/// One link's use over a frame.
struct LinkUse {
  std::string name;         ///< "link" (serial), "bus", or "peN": PE N's own link (star, tree)
  uint64_t busy_ticks = 0;  ///< picoseconds carrying data
  uint64_t bytes = 0;
  uint64_t hops = 0;  ///< transfers it carried (a broadcast counts once per link)
};

/// When one transfer happens, in picoseconds.
struct TransferTimes {
  uint64_t start = 0;   ///< its first hop begins
  uint64_t arrive = 0;  ///< its last hop begins: the far end has the data from then
  uint64_t end = 0;     ///< its last hop ends
};

/// A transfer that would end past the simulated-time horizon.
struct InterconnectTimeError : std::range_error {
  using std::range_error::range_error;
};

class Interconnect {
 public:
  /// Reads link_topology, pes, host_ports, tree_fanout, tree_forwarding, link_bandwidth_mb_s and
  /// link_latency_ns.
  /// A transfer ending at or past `horizon_ticks` throws InterconnectTimeError.
  Interconnect(const MachineConfig& c, uint64_t horizon_ticks);

  /// One hop of `bytes`: latency + bytes / bandwidth, each rounded to whole picoseconds as
  /// SystemC rounds a time (v · scale + 0.5, truncated), so the serial link's times are the
  /// original link's to the picosecond.
  uint64_t hop_ticks(uint64_t bytes) const;

  /// Host -> PE `pe`, no earlier than `ready`.
  TransferTimes send(int pe, uint64_t bytes, uint64_t ready);
  /// Host -> every PE as one transfer (MachineConfig::validate has refused the topologies that
  /// cannot); the times per PE, indexed by PE.
  std::vector<TransferTimes> broadcast(uint64_t bytes, uint64_t ready);
  /// PE `pe` -> host, no earlier than `ready`.
  TransferTimes gather(int pe, uint64_t bytes, uint64_t ready);
  /// PE `pe` -> host, no earlier than `ready`, each hop in the first gap long enough for it that
  /// the transfers asked for so far leave on its link (a star's host ports aside): a transfer asked
  /// for after others that happen later (a streamed gather's block, reserved once the PEs are
  /// done, among the tile records of a dynamic partition) goes between them, and they stay put.
  /// Needs keep_busy().
  TransferTimes gather_in_gaps(int pe, uint64_t bytes, uint64_t ready);
  /// From now on every link remembers when it is busy (for gather_in_gaps).
  void keep_busy() { busy_.resize(links_.size()); }

  /// The earliest time one of the host's ports is free: the host can start another transfer.
  uint64_t host_free() const;
  /// Every link and port is idle from then on.
  uint64_t idle_at() const;

  const std::vector<LinkUse>& links() const { return links_; }
  /// Hops from the host to PE `pe`: its depth in the tree, 1 elsewhere.
  int depth(int pe) const;
  /// PE `pe`'s parent in the tree; -1: the host.
  int parent(int pe) const;

 private:
  struct Hop {
    uint64_t start, end;
  };
  /// `in_gap`: in the first gap long enough on the link, not after everything asked for so far.
  Hop hop(size_t link, uint64_t bytes, uint64_t earliest, bool in_gap = false);
  /// The earliest a PE may pass on a hop `h` it receives: when all of it is in
  /// (store-and-forward), or when its header is (cut-through: the latency after the hop starts).
  uint64_t forwardable(const Hop& h) const;
  /// Hop after hop over `route`, the first no earlier than `ready`.
  TransferTimes along(const std::vector<size_t>& route, uint64_t bytes, uint64_t ready,
                      bool in_gaps = false);
  /// The port of a star taking a transfer on `link`: the one letting it start first.
  size_t star_port(size_t link, uint64_t ready) const;
  /// The tree's links from the host down to `pe`.
  std::vector<size_t> path(int pe) const;

  MachineConfig::LinkTopology topology_;
  int pes_, host_ports_, fanout_;
  bool cut_through_;
  uint64_t latency_ticks_;
  double bytes_per_second_;
  uint64_t horizon_;
  std::vector<LinkUse> links_;
  std::vector<uint64_t> link_free_;     ///< each link is idle from then
  std::vector<uint64_t> port_free_;     ///< a star's host ports
  std::vector<std::vector<Hop>> busy_;  ///< keep_busy(): each link's hops, by start
};

}  // namespace rtm
