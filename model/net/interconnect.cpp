#include "net/interconnect.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace rtm {

namespace {

using Topology = MachineConfig::LinkTopology;

/// `v` units of `ticks_per_unit` picoseconds, rounded as sc_time(double, unit) rounds.
uint64_t ticks(double v, double ticks_per_unit) {
  return v == 0 ? 0 : uint64_t(int64_t(v * ticks_per_unit + 0.5));
}

}  // namespace

Interconnect::Interconnect(const MachineConfig& c, uint64_t horizon_ticks)
    : topology_(c.link_topology),
      pes_(c.pes),
      host_ports_(c.host_ports),
      fanout_(c.tree_fanout),
      cut_through_(c.tree_forwarding == MachineConfig::TreeForwarding::CutThrough),
      latency_ticks_(ticks(c.link_latency_ns, 1e3)),
      bytes_per_second_(c.link_bandwidth_mb_s * 1e6),
      horizon_(horizon_ticks) {
  switch (topology_) {
    case Topology::Serial:
      links_.push_back({"link"});
      break;
    case Topology::Bus:
      links_.push_back({"bus"});
      break;
    case Topology::Star:
    case Topology::Tree:
      for (int i = 0; i < pes_; ++i) links_.push_back({"pe" + std::to_string(i)});
      break;
  }
  link_free_.assign(links_.size(), 0);
  if (topology_ == Topology::Star) port_free_.assign(size_t(host_ports_), 0);
}

uint64_t Interconnect::hop_ticks(uint64_t bytes) const {
  const double seconds = double(bytes) / bytes_per_second_;  // as the original link computed it
  if (!(seconds * 1e12 < double(horizon_)))
    throw InterconnectTimeError("a transfer of " + std::to_string(bytes) +
                                " bytes would take longer than " + std::to_string(horizon_) +
                                " ps");
  return latency_ticks_ + ticks(seconds, 1e12);
}

Interconnect::Hop Interconnect::hop(size_t link, uint64_t bytes, uint64_t earliest, bool in_gap) {
  const uint64_t d = hop_ticks(bytes);
  uint64_t start = std::max(earliest, link_free_[link]);
  std::vector<Hop>* busy = busy_.empty() ? nullptr : &busy_[link];
  auto at = busy ? busy->end() : std::vector<Hop>::iterator{};
  if (in_gap && busy) {
    // The hops on a link never overlap: by start, their ends grow too.
    at = std::upper_bound(busy->begin(), busy->end(), earliest,
                          [](uint64_t t, const Hop& h) { return t < h.end; });
    for (start = earliest; at != busy->end() && start + d > at->start; ++at)
      start = std::max(start, at->end);
  }
  if (start >= horizon_ || d >= horizon_ - start) {
    char s[200];
    std::snprintf(
        s, sizeof s, "a transfer of %llu bytes over %s from %.3g ps would end past %.3g ps",
        (unsigned long long)bytes, links_[link].name.c_str(), double(start), double(horizon_));
    throw InterconnectTimeError(s);
  }
  link_free_[link] = std::max(link_free_[link], start + d);
  if (busy) busy->insert(at, {start, start + d});
  LinkUse& u = links_[link];
  u.busy_ticks += d;
  u.bytes += bytes;
  ++u.hops;
  return {start, start + d};
}

size_t Interconnect::star_port(size_t link, uint64_t ready) const {
  size_t best = 0;
  uint64_t best_start = UINT64_MAX;
  for (size_t p = 0; p < port_free_.size(); ++p) {
    const uint64_t start = std::max({ready, port_free_[p], link_free_[link]});
    if (start < best_start) best = p, best_start = start;
  }
  return best;
}

int Interconnect::parent(int pe) const {
  return topology_ != Topology::Tree || pe < host_ports_ ? -1 : (pe - host_ports_) / fanout_;
}

int Interconnect::depth(int pe) const {
  int d = 1;
  for (int p = parent(pe); p >= 0; p = parent(p)) ++d;
  return d;
}

std::vector<size_t> Interconnect::path(int pe) const {
  std::vector<size_t> down;
  for (int p = pe; p >= 0; p = parent(p)) down.push_back(size_t(p));
  std::reverse(down.begin(), down.end());
  return down;
}

uint64_t Interconnect::forwardable(const Hop& h) const {
  // Cut-through: every link has the same bandwidth, so a hop started once the header is in never
  // outruns the data still arriving on the link before it.
  return cut_through_ ? h.start + latency_ticks_ : h.end;
}

TransferTimes Interconnect::along(const std::vector<size_t>& route, uint64_t bytes, uint64_t ready,
                                  bool in_gaps) {
  TransferTimes t{0, 0, ready};
  uint64_t earliest = ready;
  for (size_t i = 0; i < route.size(); ++i) {
    const Hop h = hop(route[i], bytes, earliest, in_gaps);
    if (i == 0) t.start = h.start;
    t.arrive = h.start;
    t.end = h.end;
    earliest = forwardable(h);
  }
  return t;
}

TransferTimes Interconnect::send(int pe, uint64_t bytes, uint64_t ready) {
  if (bytes == 0) return {ready, ready, ready};
  switch (topology_) {
    case Topology::Serial:
    case Topology::Bus:
      return along({0}, bytes, ready);
    case Topology::Star: {
      const size_t p = star_port(size_t(pe), ready);
      const TransferTimes t = along({size_t(pe)}, bytes, std::max(ready, port_free_[p]));
      port_free_[p] = t.end;
      return t;
    }
    case Topology::Tree:
      break;
  }
  return along(path(pe), bytes, ready);
}

std::vector<TransferTimes> Interconnect::broadcast(uint64_t bytes, uint64_t ready) {
  std::vector<TransferTimes> t(static_cast<size_t>(pes_), TransferTimes{ready, ready, ready});
  if (bytes == 0) return t;
  switch (topology_) {
    case Topology::Serial:
    case Topology::Bus: {
      const Hop h = hop(0, bytes, ready);
      std::fill(t.begin(), t.end(), TransferTimes{h.start, h.start, h.end});
      break;
    }
    case Topology::Star: {
      if (host_ports_ < pes_)
        throw std::logic_error("a broadcast on a star needs a host port per PE");
      // The pes ports free first, and every link, carry it at once.
      std::vector<size_t> ports(port_free_.size());
      std::iota(ports.begin(), ports.end(), size_t(0));
      std::stable_sort(ports.begin(), ports.end(),
                       [&](size_t a, size_t b) { return port_free_[a] < port_free_[b]; });
      ports.resize(size_t(pes_));
      uint64_t start = ready;
      for (size_t p : ports) start = std::max(start, port_free_[p]);
      for (uint64_t f : link_free_) start = std::max(start, f);
      for (int i = 0; i < pes_; ++i) {
        const Hop h = hop(size_t(i), bytes, start);
        t[size_t(i)] = {h.start, h.start, h.end};
        port_free_[ports[size_t(i)]] = h.end;
      }
      break;
    }
    case Topology::Tree:
      // Parents come before their children in PE order: each forwards as tree_forwarding says,
      // from the hop that reached it (its arrive and end).
      for (int i = 0; i < pes_; ++i) {
        const int p = parent(i);
        const uint64_t earliest =
            p < 0 ? ready : forwardable({t[size_t(p)].arrive, t[size_t(p)].end});
        const Hop h = hop(size_t(i), bytes, earliest);
        t[size_t(i)] = {p < 0 ? h.start : t[size_t(p)].start, h.start, h.end};
      }
      break;
  }
  return t;
}

TransferTimes Interconnect::gather(int pe, uint64_t bytes, uint64_t ready) {
  if (topology_ != Topology::Tree || bytes == 0)
    return send(pe, bytes, ready);  // one link carries either way alike
  std::vector<size_t> up = path(pe);
  std::reverse(up.begin(), up.end());
  return along(up, bytes, ready);
}

TransferTimes Interconnect::gather_in_gaps(int pe, uint64_t bytes, uint64_t ready) {
  if (bytes == 0) return {ready, ready, ready};
  if (busy_.empty()) throw std::logic_error("gather_in_gaps without keep_busy");
  std::vector<size_t> up = topology_ == Topology::Tree ? path(pe)
                           : topology_ == Topology::Serial || topology_ == Topology::Bus
                               ? std::vector<size_t>{0}
                               : std::vector<size_t>{size_t(pe)};
  std::reverse(up.begin(), up.end());
  return along(up, bytes, ready, true);
}

uint64_t Interconnect::host_free() const {
  switch (topology_) {
    case Topology::Serial:
    case Topology::Bus:
      return link_free_[0];
    case Topology::Star:
      return *std::min_element(port_free_.begin(), port_free_.end());
    case Topology::Tree:
      break;
  }
  // The host's own links are its children's.
  return *std::min_element(link_free_.begin(), link_free_.begin() + std::min(host_ports_, pes_));
}

uint64_t Interconnect::idle_at() const {
  uint64_t t = 0;
  for (uint64_t f : link_free_) t = std::max(t, f);
  for (uint64_t f : port_free_) t = std::max(t, f);
  return t;
}

}  // namespace rtm
