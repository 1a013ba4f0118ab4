// The interconnect's times against figures worked out by hand (docs/machine.md, "The host-PE
// interconnect"). Every case uses a 1 µs latency and 400 MB/s, so a hop of b bytes takes
// 1'000'000 + 2'500·b ps: the scene (4000 bytes) 11 µs, a PE's rays (400 bytes) 2 µs, its frame
// buffer (800 bytes) 3 µs.
#include "net/interconnect.h"

#include <gtest/gtest.h>

namespace rtm {
namespace {

using Topology = MachineConfig::LinkTopology;

constexpr uint64_t kHorizon = uint64_t(1) << 62;
constexpr uint64_t kScene = 4000, kRays = 400, kFrame = 800;
constexpr uint64_t S = 11'000'000, R = 2'000'000, G = 3'000'000;  // their hops, ps

MachineConfig net(Topology t, int pes, int host_ports = 1, int fanout = 2) {
  MachineConfig c;
  c.link_topology = t;
  c.pes = pes;
  c.host_ports = host_ports;
  c.tree_fanout = fanout;
  c.link_latency_ns = 1000;
  c.link_bandwidth_mb_s = 400;
  return c;
}

/// The host's send phase as machine/host.cpp runs it: the scene (to all at once, or before each
/// PE's rays), each PE's rays, each transfer asked for once the host has a free port. Returns
/// when each PE's rays arrived.
std::vector<TransferTimes> host_sends(Interconnect& n, int pes, bool broadcast, uint64_t& now) {
  std::vector<TransferTimes> rays;
  auto after = [&](auto t) {
    now = std::max(now, n.host_free());
    return t;
  };
  if (broadcast) after(n.broadcast(kScene, now));
  for (int pe = 0; pe < pes; ++pe) {
    if (!broadcast) after(n.send(pe, kScene, now));
    rays.push_back(after(n.send(pe, kRays, now)));
  }
  return rays;
}

uint64_t total_bytes(const Interconnect& n) {
  uint64_t b = 0;
  for (const LinkUse& l : n.links()) b += l.bytes;
  return b;
}
uint64_t total_busy(const Interconnect& n) {
  uint64_t b = 0;
  for (const LinkUse& l : n.links()) b += l.busy_ticks;
  return b;
}

TEST(Interconnect, AHopIsLatencyPlusBytesOverBandwidthInWholePicoseconds) {
  Interconnect n(net(Topology::Serial, 1), kHorizon);
  EXPECT_EQ(n.hop_ticks(kScene), S);
  EXPECT_EQ(n.hop_ticks(0), 1'000'000u);
  MachineConfig odd = net(Topology::Serial, 1);
  odd.link_bandwidth_mb_s = 3;   // a byte: 333333.33 ps
  odd.link_latency_ns = 0.0004;  // 0.4 ps: rounds to 0
  EXPECT_EQ(Interconnect(odd, kHorizon).hop_ticks(1), 333'333u);
  EXPECT_EQ(Interconnect(odd, kHorizon).hop_ticks(2), 666'667u);
}

// Serial, the original link: every transfer in turn. Without broadcast PE i's rays arrive after
// i + 1 scenes and i rays; with it the scene goes once.
TEST(Interconnect, SerialCarriesOneTransferAtATime) {
  for (int pes : {1, 2, 5, 16}) {
    for (bool broadcast : {false, true}) {
      Interconnect n(net(Topology::Serial, pes), kHorizon);
      uint64_t now = 0;
      const auto rays = host_sends(n, pes, broadcast, now);
      for (int i = 0; i < pes; ++i) {
        const uint64_t arrive = broadcast ? S + i * R : (i + 1) * S + i * R;
        EXPECT_EQ(rays[size_t(i)].arrive, arrive)
            << pes << " PEs, PE " << i << ", broadcast " << broadcast;
        EXPECT_EQ(rays[size_t(i)].end, arrive + R);
      }
      const uint64_t scenes = broadcast ? 1 : uint64_t(pes);
      EXPECT_EQ(now, scenes * S + pes * R) << "the host waits for each transfer";
      EXPECT_EQ(n.idle_at(), now);
      ASSERT_EQ(n.links().size(), 1u);
      EXPECT_EQ(n.links()[0].name, "link");
      EXPECT_EQ(n.links()[0].bytes, scenes * kScene + pes * kRays);
      EXPECT_EQ(n.links()[0].busy_ticks, scenes * S + pes * R);
      EXPECT_EQ(n.links()[0].hops, scenes + pes);
    }
  }
}

// A bus is one medium too: the same times; its name is the bus.
TEST(Interconnect, ABusSerialisesTransfersAndBroadcastsInOne) {
  for (int pes : {1, 2, 5, 16}) {
    for (bool broadcast : {false, true}) {
      Interconnect bus(net(Topology::Bus, pes), kHorizon),
          serial(net(Topology::Serial, pes), kHorizon);
      uint64_t a = 0, b = 0;
      const auto on_bus = host_sends(bus, pes, broadcast, a);
      const auto on_serial = host_sends(serial, pes, broadcast, b);
      for (int i = 0; i < pes; ++i)
        EXPECT_EQ(on_bus[size_t(i)].arrive, on_serial[size_t(i)].arrive);
      EXPECT_EQ(a, b);
      EXPECT_EQ(bus.links()[0].name, "bus");
      EXPECT_EQ(bus.links()[0].bytes, (broadcast ? 1 : uint64_t(pes)) * kScene + pes * kRays);
    }
    Interconnect bus(net(Topology::Bus, pes), kHorizon);
    for (const TransferTimes& t : bus.broadcast(kScene, 5)) {
      EXPECT_EQ(t.arrive, 5u);
      EXPECT_EQ(t.end, 5 + S);
    }
  }
}

// A star: a link per PE, host_ports of them driven at once. PE i is served in round i / ports,
// its scene then its rays: ceil(pes / ports) rounds of S + R.
TEST(Interconnect, AStarDrivesHostPortsLinksAtOnce) {
  for (int pes : {1, 2, 5, 16}) {
    for (int ports : {1, 2, 4, 16}) {
      Interconnect n(net(Topology::Star, pes, ports), kHorizon);
      uint64_t now = 0;
      const auto rays = host_sends(n, pes, false, now);
      for (int i = 0; i < pes; ++i)
        EXPECT_EQ(rays[size_t(i)].arrive, uint64_t(i / ports) * (S + R) + S)
            << pes << " PEs, " << ports << " ports, PE " << i;
      const uint64_t rounds = uint64_t((pes + ports - 1) / ports);
      EXPECT_EQ(n.idle_at(), rounds * (S + R));
      ASSERT_EQ(n.links().size(), size_t(pes));
      for (int i = 0; i < pes; ++i) {
        EXPECT_EQ(n.links()[size_t(i)].name, "pe" + std::to_string(i));
        EXPECT_EQ(n.links()[size_t(i)].bytes, kScene + kRays);
        EXPECT_EQ(n.links()[size_t(i)].busy_ticks, S + R);
      }
    }
  }
}

// With a port per PE a star's broadcast drives every link at once: the same time as copies,
// each link carrying the scene once.
TEST(Interconnect, AStarBroadcastsWithAPortPerPe) {
  for (int pes : {1, 2, 5, 16}) {
    Interconnect n(net(Topology::Star, pes, pes), kHorizon);
    uint64_t now = 0;
    const auto rays = host_sends(n, pes, true, now);
    for (int i = 0; i < pes; ++i) EXPECT_EQ(rays[size_t(i)].arrive, S);
    EXPECT_EQ(n.idle_at(), S + R);
    EXPECT_EQ(total_bytes(n), pes * (kScene + kRays));
  }
  Interconnect few(net(Topology::Star, 4, 2), kHorizon);
  EXPECT_THROW(few.broadcast(kScene, 0), std::logic_error) << "validate refuses it first";
}

// A tree: the host's host_ports children are PEs 0..h-1, PE i's children PEs h + f·i ... The
// broadcast reaches depth d at (d - 1)·S and ends at depth·S, every link carrying it once.
TEST(Interconnect, ATreeForwardsABroadcastStoreAndForward) {
  struct Case {
    int pes, ports, fanout;
    std::vector<int> depths;
  };
  for (const Case& c : {Case{1, 1, 2, {1}}, Case{2, 1, 2, {1, 2}}, Case{5, 1, 2, {1, 2, 2, 3, 3}},
                        Case{16, 1, 2, {1, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5}},
                        Case{16, 4, 3, {1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2}},
                        Case{5, 1, 1, {1, 2, 3, 4, 5}}}) {
    Interconnect n(net(Topology::Tree, c.pes, c.ports, c.fanout), kHorizon);
    const auto t = n.broadcast(kScene, 0);
    int deepest = 0;
    for (int i = 0; i < c.pes; ++i) {
      const int d = c.depths[size_t(i)];
      EXPECT_EQ(n.depth(i), d) << c.pes << " PEs, PE " << i;
      EXPECT_EQ(t[size_t(i)].arrive, uint64_t(d - 1) * S) << c.pes << " PEs, PE " << i;
      EXPECT_EQ(t[size_t(i)].end, uint64_t(d) * S);
      EXPECT_EQ(n.links()[size_t(i)].bytes, kScene);
      deepest = std::max(deepest, d);
    }
    EXPECT_EQ(n.idle_at(), uint64_t(deepest) * S);
    EXPECT_EQ(total_busy(n), c.pes * S);
  }
  Interconnect n(net(Topology::Tree, 16, 4, 3), kHorizon);
  EXPECT_EQ(n.parent(3), -1);
  EXPECT_EQ(n.parent(4), 0);
  EXPECT_EQ(n.parent(6), 0);
  EXPECT_EQ(n.parent(7), 1);
  EXPECT_EQ(n.parent(15), 3);
}

// Cut-through: a PE passes a transfer on once its header is in, the latency L after the hop
// before began. On an idle tree a transfer over d links then takes d·L + its serialisation, the
// store-and-forward time less (d - 1)·(t(b) - L).
TEST(Interconnect, ATreeCutThroughForwardsOnceTheHeaderIsIn) {
  constexpr uint64_t L = 1'000'000;
  for (int fanout : {1, 2, 3}) {
    MachineConfig c = net(Topology::Tree, 16, 1, fanout);
    c.tree_forwarding = MachineConfig::TreeForwarding::CutThrough;
    Interconnect cut(c, kHorizon);
    const auto t = cut.broadcast(kScene, 0);
    uint64_t deepest = 0;
    for (int i = 0; i < 16; ++i) {
      const uint64_t d = uint64_t(cut.depth(i));
      EXPECT_EQ(t[size_t(i)].arrive, (d - 1) * L) << "fan-out " << fanout << ", PE " << i;
      EXPECT_EQ(t[size_t(i)].end, (d - 1) * L + S);
      EXPECT_EQ(cut.links()[size_t(i)].bytes, kScene) << "each link carries it once, as before";
      deepest = std::max(deepest, d);
    }
    EXPECT_EQ(cut.idle_at(), deepest * S - (deepest - 1) * (S - L));
    EXPECT_EQ(total_busy(cut), 16 * S) << "the links' busy time is the same";
  }
  for (int pes : {1, 2, 5, 16}) {  // a chain: PE k is k + 1 links from the host
    MachineConfig c = net(Topology::Tree, pes, 1, 1);
    c.tree_forwarding = MachineConfig::TreeForwarding::CutThrough;
    for (int k = 0; k < pes; ++k) {
      Interconnect cut(c, kHorizon), stored(net(Topology::Tree, pes, 1, 1), kHorizon);
      const uint64_t d = uint64_t(k) + 1;
      const TransferTimes down = cut.send(k, kRays, 0);
      EXPECT_EQ(down.arrive, (d - 1) * L) << pes << " PEs, PE " << k;
      EXPECT_EQ(down.end, d * L + (R - L));
      EXPECT_EQ(stored.send(k, kRays, 0).end - down.end, (d - 1) * (R - L));
      const TransferTimes up = cut.gather(k, kFrame, down.end);
      EXPECT_EQ(up.end - up.start, d * L + (G - L));
      EXPECT_EQ(stored.gather(k, kFrame, down.end + (d - 1) * (R - L)).end -
                    (down.end + (d - 1) * (R - L)),
                d * G);
    }
  }
  // A busy link down the path holds the transfer in the PE before it, as store-and-forward would.
  MachineConfig c = net(Topology::Tree, 3, 1, 1);
  c.tree_forwarding = MachineConfig::TreeForwarding::CutThrough;
  Interconnect cut(c, kHorizon);
  cut.send(1, kScene, 0);  // links 0 and 1: [0, S) and [L, L + S)
  const TransferTimes t = cut.send(2, kRays, 0);
  EXPECT_EQ(t.start, S);           // link 0 once the scene has left it
  EXPECT_EQ(t.arrive, 2 * L + S);  // link 1 once the scene has left it (L + S), link 2 L later
  EXPECT_EQ(t.end, 2 * L + S + R);
}

// Without broadcast a tree routes each PE's copy through its ancestors, hop after hop. On a chain
// the host's link frees after each first hop: PE k's rays start on the host's link at k·R and
// reach it at 2k·R.
TEST(Interconnect, ATreeRoutesEachTransferThroughTheAncestors) {
  for (int pes : {1, 2, 5, 16}) {
    Interconnect n(net(Topology::Tree, pes, 1, 1), kHorizon);
    uint64_t now = 0;
    for (int k = 0; k < pes; ++k) {
      const TransferTimes t = n.send(k, kRays, now);
      now = std::max(now, n.host_free());
      EXPECT_EQ(t.start, k * R) << pes << " PEs, PE " << k;
      EXPECT_EQ(t.arrive, 2 * k * R);
      EXPECT_EQ(t.end, (2 * k + 1) * R);
    }
    for (int k = 0; k < pes; ++k)
      EXPECT_EQ(n.links()[size_t(k)].bytes, (pes - k) * kRays) << "PE " << k << "'s link";
  }
  // The whole send phase without broadcast on 5 PEs, fan-out 2: worked through by hand.
  Interconnect n(net(Topology::Tree, 5, 1, 2), kHorizon);
  uint64_t now = 0;
  const auto rays = host_sends(n, 5, false, now);
  // The host waits for its link (PE 0's) after each transfer, so it carries S0 R0 S1 R1 ... back
  // to back. PE 1's copy then waits on PE 1's link for R1's first hop; PE 2's rays for its own
  // scene's second hop (S2 on link 2 to 4S + 2R); PE 3's and PE 4's behind PE 1's link as well.
  EXPECT_EQ(rays[0].arrive, S);
  EXPECT_EQ(rays[1].arrive, 3 * S + R);
  EXPECT_EQ(rays[2].arrive, 4 * S + 2 * R);
  EXPECT_EQ(rays[3].arrive, 6 * S + 3 * R);
  EXPECT_EQ(rays[4].arrive, 7 * S + 4 * R);
  EXPECT_EQ(n.idle_at(), 7 * S + 5 * R);
}

// Gathers and transfers take the same links, first come first served.
TEST(Interconnect, GathersContendWithTransfers) {
  {  // One medium: a gather asked for during a transfer waits for it.
    Interconnect n(net(Topology::Serial, 2), kHorizon);
    n.send(1, kRays, 0);
    const TransferTimes g = n.gather(0, kFrame, 500'000);
    EXPECT_EQ(g.start, R);
    EXPECT_EQ(g.end, R + G);
  }
  {  // A star with one port: the port is shared; with two, the links are separate.
    Interconnect one(net(Topology::Star, 2, 1), kHorizon), two(net(Topology::Star, 2, 2), kHorizon);
    one.send(1, kRays, 0);
    two.send(1, kRays, 0);
    EXPECT_EQ(one.gather(0, kFrame, 0).start, R);
    EXPECT_EQ(two.gather(0, kFrame, 0).start, 0u);
    EXPECT_EQ(two.gather(1, kFrame, 0).start, R) << "its own link is busy";
  }
  {  // A tree of 5, fan-out 2: rays to PE 4 hold links 0, 1 and 4; PE 3's gather climbs 3, 1, 0.
    Interconnect n(net(Topology::Tree, 5, 1, 2), kHorizon);
    const TransferTimes r = n.send(4, kRays, 0);
    EXPECT_EQ(r.end, 3 * R);
    const TransferTimes g = n.gather(3, kFrame, 0);
    EXPECT_EQ(g.start, 0u);           // PE 3's own link is free
    EXPECT_EQ(g.end, 2 * R + 2 * G);  // link 1 once the rays left it (2R), then link 0
    EXPECT_EQ(n.links()[1].bytes, kRays + kFrame);
    EXPECT_EQ(n.links()[0].busy_ticks, R + G);
  }
  {  // After all: N gathers in turn on one medium, each G.
    for (int pes : {1, 2, 5, 16}) {
      Interconnect n(net(Topology::Bus, pes), kHorizon);
      uint64_t now = 100;
      for (int pe = 0; pe < pes; ++pe) {
        n.gather(pe, kFrame, now);
        now = std::max(now, n.host_free());
      }
      EXPECT_EQ(now, 100 + pes * G);
    }
  }
}

// A transfer asked for after later ones (a streamed gather's block among a dynamic partition's
// tile records) takes the first gap long enough on its link; the others stay put.
TEST(Interconnect, AGatherInGapsGoesBetweenTransfersAskedForEarlier) {
  Interconnect n(net(Topology::Serial, 2), kHorizon);
  n.keep_busy();
  // The link busy over [0, R) and [R + G + 1, 2R + G + 1): a gap of G + 1 between them.
  EXPECT_EQ(n.send(0, kRays, 0).end, R);
  EXPECT_EQ(n.send(1, kRays, R + G + 1).start, R + G + 1);
  // A frame buffer (G) fits in the gap, from when it is ready ...
  const TransferTimes a = n.gather_in_gaps(0, kFrame, 0);
  EXPECT_EQ(a.start, R);
  EXPECT_EQ(a.end, R + G);
  // ... a second no longer does: after the last.
  const TransferTimes b = n.gather_in_gaps(1, kFrame, 0);
  EXPECT_EQ(b.start, 2 * R + G + 1);
  EXPECT_EQ(n.idle_at(), 2 * R + 2 * G + 1);
  // A later transfer asked for in order still follows everything.
  EXPECT_EQ(n.gather(0, kFrame, 0).start, 2 * R + 2 * G + 1);
}

TEST(Interconnect, NothingToCarryTakesNoLinkAndNoTime) {
  for (Topology t : {Topology::Serial, Topology::Bus, Topology::Star, Topology::Tree}) {
    Interconnect n(net(t, 3, 3), kHorizon);
    n.send(0, kRays, 0);
    const TransferTimes g = n.gather(1, 0, 7);
    EXPECT_EQ(g.start, 7u);
    EXPECT_EQ(g.end, 7u);
    for (const TransferTimes& b : n.broadcast(0, 9)) EXPECT_EQ(b.end, 9u);
    EXPECT_EQ(total_bytes(n), kRays);
    EXPECT_EQ(total_busy(n), R);
  }
}

TEST(Interconnect, ATransferPastTheHorizonIsAnError) {
  MachineConfig c = net(Topology::Serial, 1);
  c.link_bandwidth_mb_s = 0.001;  // 1 kB/s: a GB takes 1e18 ps
  Interconnect n(c, uint64_t(1e18));
  EXPECT_NO_THROW(n.send(0, 1000, 0));
  EXPECT_THROW(n.send(0, 1'000'000'000, 0), InterconnectTimeError);
  EXPECT_THROW(n.send(0, ~uint64_t(0), 0), InterconnectTimeError);
}

}  // namespace
}  // namespace rtm
