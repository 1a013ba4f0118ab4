// The local memory's timing on hand-built requests, each expected cycle worked out in the comment
// beside it from the formulas of local_memory_timing.h (docs/memory.md, "Memory timing model").
#include "memory/local_memory_timing.h"

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace rtm {
namespace {

using Config = LocalMemoryTiming::Config;
using Grant = LocalMemoryTiming::Grant;

Config memory(int ports, int banks, uint64_t granule, uint64_t latency, uint64_t width,
              MemoryArbitration a = MemoryArbitration::RoundRobin) {
  return {ports, banks, granule, latency, width, a};
}

LocalMemoryTiming with(const Config& c, int requesters = 3) {
  std::vector<std::string> names;
  for (int i = 0; i < requesters; ++i) names.push_back("r" + std::to_string(i));
  return LocalMemoryTiming(c, names);
}

/// Makes one request and resolves its cycle: its grant.
Grant alone(LocalMemoryTiming& m, int requester, uint64_t address, uint64_t bytes, uint64_t cycle) {
  const auto t = m.request(requester, address, bytes, cycle);
  m.resolve(cycle);
  return m.collect(t);
}

TEST(LocalMemoryTiming, WithoutContentionARequestTakesTheLatencyAndOneCyclePerBeatAfterTheFirst) {
  LocalMemoryTiming m = with(memory(0, 0, 4, 3, 4));
  // T = ceil(B / 4); completion = issue + 3 + T - 1.
  EXPECT_EQ(m.unloaded_latency(1), 3u);
  EXPECT_EQ(m.unloaded_latency(4), 3u);
  EXPECT_EQ(m.unloaded_latency(8), 4u);
  EXPECT_EQ(m.unloaded_latency(9), 5u);
  const Grant g = alone(m, 0, 100, 8, 10);
  EXPECT_EQ(g.issue, 10u);
  EXPECT_EQ(g.start, 10u);
  EXPECT_EQ(g.completion, 14u);
  EXPECT_EQ(g.stall(), 0u);
  EXPECT_EQ(alone(m, 1, 0, 9, 20).completion, 25u);
  EXPECT_EQ(alone(m, 2, 7, 1, 30).completion, 33u);
}

TEST(LocalMemoryTiming, AMultiCycleRequestHoldsItsPortForEveryBeat) {
  LocalMemoryTiming m = with(memory(1, 1, 4, 1, 4));
  // 16 bytes at 4 a cycle: beats in cycles 0..3, the last one's data at 3 + 1.
  const Grant g = alone(m, 0, 0, 16, 0);
  EXPECT_EQ(g.start, 0u);
  EXPECT_EQ(g.completion, 4u);
  EXPECT_EQ(m.ports().at(0).busy_cycles, 4u);
  EXPECT_EQ(m.banks().at(0).busy_cycles, 4u);
}

TEST(LocalMemoryTiming, BackToBackRequestsQueueOnOnePort) {
  LocalMemoryTiming m = with(memory(1, 0, 4, 1, 4));
  // A: cycles 0, 1 -> complete at 2. B, issued at 1, finds the port busy in cycle 1: starts at 2,
  // complete at 2 + 1 + 1 = 4, one cycle stalled. C at 4 finds it free again.
  const auto a = m.request(0, 0, 8, 0);
  const auto b = m.request(0, 8, 8, 1);
  const auto c = m.request(0, 16, 8, 4);
  m.resolve(4);
  const Grant ga = m.collect(a), gb = m.collect(b), gc = m.collect(c);
  EXPECT_EQ(ga.completion, 2u);
  EXPECT_EQ(gb.start, 2u);
  EXPECT_EQ(gb.completion, 4u);
  EXPECT_EQ(gb.stall(), 1u);
  EXPECT_EQ(gb.completion - gb.issue - m.unloaded_latency(8), gb.stall());
  EXPECT_EQ(gc.start, 4u);
  EXPECT_EQ(gc.completion, 6u);
  EXPECT_EQ(m.requesters()[0].requests, 3u);
  EXPECT_EQ(m.requesters()[0].bytes, 24u);
  EXPECT_EQ(m.requesters()[0].stall_cycles, 1u);
  EXPECT_EQ(m.ports()[0].busy_cycles, 6u);
}

TEST(LocalMemoryTiming, TwoRequestsOnOneBankConflictAndTheSecondWaitsABeat) {
  LocalMemoryTiming m = with(memory(0, 4, 4, 2, 4));
  // Addresses 0 and 16 are granules 0 and 4: both bank 0. Round robin from requester 0: r0 goes in
  // cycle 5 (complete at 5 + 2), r1 finds bank 0 booked in cycle 5 and goes in cycle 6 (at 8), on
  // the port r0 has left: one port is enough.
  const auto t1 = m.request(1, 16, 4, 5);
  const auto t0 = m.request(0, 0, 4, 5);
  m.resolve(5);
  const Grant g0 = m.collect(t0), g1 = m.collect(t1);
  EXPECT_EQ(g0.start, 5u);
  EXPECT_EQ(g0.completion, 7u);
  EXPECT_EQ(g1.start, 6u);
  EXPECT_EQ(g1.completion, 8u);
  EXPECT_EQ(m.banks()[0].conflicts, 1u);
  EXPECT_EQ(m.banks()[0].busy_cycles, 2u);
  EXPECT_EQ(m.banks()[1].conflicts + m.banks()[2].conflicts + m.banks()[3].conflicts, 0u);
  EXPECT_EQ(m.ports().size(), 1u);
  EXPECT_EQ(m.requesters()[1].stall_cycles, 1u);
}

TEST(LocalMemoryTiming, RequestsSpreadOverBanksGoTogether) {
  LocalMemoryTiming m = with(memory(0, 4, 4, 2, 4));
  // Addresses 0 and 4: banks 0 and 1. Both go in cycle 5, on two ports.
  const auto t0 = m.request(0, 0, 4, 5);
  const auto t1 = m.request(1, 4, 4, 5);
  m.resolve(5);
  EXPECT_EQ(m.collect(t0).completion, 7u);
  const Grant g1 = m.collect(t1);
  EXPECT_EQ(g1.completion, 7u);
  EXPECT_EQ(g1.port, 1);
  EXPECT_EQ(m.ports().size(), 2u);
  for (const auto& b : m.banks()) EXPECT_EQ(b.conflicts, 0u);
}

TEST(LocalMemoryTiming, AStreamOverInterleavedBanksFollowsOneBeatBehindAnother) {
  LocalMemoryTiming m = with(memory(2, 4, 4, 1, 4));
  // Both read bytes 0..15: beats on banks 0, 1, 2, 3 in turn. The second cannot use bank 0 in
  // cycle 0, but from cycle 1 each of its beats finds its bank just left: stalled 1, not 4.
  const auto a = m.request(0, 0, 16, 0);
  const auto b = m.request(1, 0, 16, 0);
  m.resolve(0);
  EXPECT_EQ(m.collect(a).completion, 4u);
  const Grant gb = m.collect(b);
  EXPECT_EQ(gb.start, 1u);
  EXPECT_EQ(gb.completion, 5u);
  for (const auto& bank : m.banks()) EXPECT_EQ(bank.busy_cycles, 2u);
  EXPECT_EQ(m.banks()[0].conflicts, 1u);
  EXPECT_EQ(m.banks()[1].conflicts, 1u)
      << "its unloaded beat 1 would meet the first's beat 1 on bank 1";
}

TEST(LocalMemoryTiming, ABeatUsesEveryBankHoldingOneOfItsBytes) {
  // An 8-byte port over 4-byte granules: the beat at address 4 covers granules 1 and 2.
  LocalMemoryTiming wide = with(memory(0, 4, 4, 1, 8));
  const auto a = wide.request(0, 4, 8, 0);
  const auto b = wide.request(1, 8, 4, 0);   // granule 2: bank 2, booked by a's beat
  const auto c = wide.request(2, 12, 4, 0);  // granule 3: bank 3, free
  wide.resolve(0);
  EXPECT_EQ(wide.collect(a).start, 0u);
  EXPECT_EQ(wide.collect(b).start, 1u);
  EXPECT_EQ(wide.collect(c).start, 0u);
  // Unaligned: 8 bytes at address 2 with a 4-byte port: beat 0 is bytes 2..5 (banks 0, 1), beat 1
  // bytes 6..9 (banks 1, 2); bank 1 serves both beats.
  LocalMemoryTiming odd = with(memory(0, 4, 4, 1, 4));
  alone(odd, 0, 2, 8, 0);
  EXPECT_EQ(odd.banks()[0].busy_cycles, 1u);
  EXPECT_EQ(odd.banks()[1].busy_cycles, 2u);
  EXPECT_EQ(odd.banks()[2].busy_cycles, 1u);
  EXPECT_EQ(odd.banks()[3].busy_cycles, 0u);
  // A beat wider than all the banks uses each once.
  LocalMemoryTiming all = with(memory(0, 2, 4, 1, 64));
  alone(all, 0, 0, 64, 0);
  EXPECT_EQ(all.banks()[0].busy_cycles, 1u);
  EXPECT_EQ(all.banks()[1].busy_cycles, 1u);
}

/// Three requesters each ask for 4 bytes at cycle c, made in `order`; their start cycles.
std::vector<uint64_t> three_at(LocalMemoryTiming& m, uint64_t c, std::vector<int> order) {
  std::map<int, LocalMemoryTiming::Ticket> t;
  for (int r : order) t[r] = m.request(r, uint64_t(4 * r), 4, c);
  m.resolve(c);
  std::vector<uint64_t> starts(3, ~0ull);
  for (const auto& [r, ticket] : t) starts[size_t(r)] = m.collect(ticket).start;
  return starts;
}

TEST(LocalMemoryTiming, RoundRobinRotatesTheFirstPlaceAmongRequestersThatKeepAsking) {
  LocalMemoryTiming m = with(memory(1, 0, 4, 1, 4));
  // More requesters than ports. Pointer 0: 0, 1, 2 in cycles 0, 1, 2; then 1 first, then 2.
  EXPECT_EQ(three_at(m, 0, {2, 1, 0}), (std::vector<uint64_t>{0, 1, 2}));
  EXPECT_EQ(m.requesters()[2].stall_cycles, 2u);
  EXPECT_EQ(three_at(m, 10, {0, 1, 2}), (std::vector<uint64_t>{12, 10, 11}));
  EXPECT_EQ(three_at(m, 20, {1, 0, 2}), (std::vector<uint64_t>{21, 22, 20}));
  // Only 0 and 1 ask: the pointer is one past 2, at 0.
  const auto a = m.request(1, 0, 4, 30), b = m.request(0, 0, 4, 30);
  m.resolve(30);
  EXPECT_EQ(m.collect(b).start, 30u);
  EXPECT_EQ(m.collect(a).start, 31u);
  // Then one past 0: 1 goes before 0.
  const auto c = m.request(0, 0, 4, 40), d = m.request(1, 0, 4, 40);
  m.resolve(40);
  EXPECT_EQ(m.collect(d).start, 40u);
  EXPECT_EQ(m.collect(c).start, 41u);
}

TEST(LocalMemoryTiming, FixedPriorityPutsTheLowerRequesterFirstAndFcfsTheOneMadeFirst) {
  LocalMemoryTiming fixed = with(memory(1, 0, 4, 1, 4, MemoryArbitration::FixedPriority));
  EXPECT_EQ(three_at(fixed, 0, {2, 1, 0}), (std::vector<uint64_t>{0, 1, 2}));
  EXPECT_EQ(three_at(fixed, 10, {1, 2, 0}), (std::vector<uint64_t>{10, 11, 12}));
  LocalMemoryTiming fcfs = with(memory(1, 0, 4, 1, 4, MemoryArbitration::Fcfs));
  EXPECT_EQ(three_at(fcfs, 0, {2, 0, 1}), (std::vector<uint64_t>{1, 2, 0}));
  EXPECT_EQ(three_at(fcfs, 10, {1, 2, 0}), (std::vector<uint64_t>{12, 10, 11}));
}

TEST(LocalMemoryTiming, OlderRequestsGoFirstWhateverThePolicy) {
  for (MemoryArbitration a :
       {MemoryArbitration::RoundRobin, MemoryArbitration::FixedPriority, MemoryArbitration::Fcfs}) {
    LocalMemoryTiming m = with(memory(1, 0, 4, 1, 4, a));
    // Requester 1 holds the port in cycles 0..2; 2 asked in cycle 1, 0 in cycle 2: 2 first.
    const auto t1 = m.request(1, 0, 12, 0);
    const auto t2 = m.request(2, 0, 4, 1);
    const auto t0 = m.request(0, 0, 4, 2);
    m.resolve(2);
    EXPECT_EQ(m.collect(t1).completion, 3u) << to_string(a);
    EXPECT_EQ(m.collect(t2).start, 3u) << to_string(a);
    EXPECT_EQ(m.collect(t0).start, 4u) << to_string(a);
  }
}

TEST(LocalMemoryTiming, ALaterRequestTakesAnEarlierSlotItsOwnPortAndBanksLeaveFree) {
  LocalMemoryTiming m = with(memory(2, 2, 4, 1, 4, MemoryArbitration::Fcfs));
  const auto a = m.request(0, 0, 4, 0);  // bank 0: cycle 0, port 0
  const auto b = m.request(1, 0, 4, 0);  // bank 0 again: cycle 1, port 0
  const auto c = m.request(2, 4, 4, 0);  // bank 1, free, and port 1 is free: cycle 0, before b
  EXPECT_EQ(m.collect(a).start, 0u);
  const Grant gb = m.collect(b), gc = m.collect(c);
  EXPECT_EQ(gb.start, 1u);
  EXPECT_EQ(gb.port, 0);
  EXPECT_EQ(gc.start, 0u);
  EXPECT_EQ(gc.port, 1);
}

TEST(LocalMemoryTiming, ACyclesRequestsAreResolvedTogetherUnderAPolicyThatCompares) {
  LocalMemoryTiming rr = with(memory(1, 0, 4, 1, 4));
  const auto a = rr.request(1, 0, 4, 5);
  EXPECT_FALSE(rr.resolved(a)) << "requester 0 may still ask in cycle 5";
  EXPECT_THROW(rr.collect(a), std::logic_error);
  const auto b = rr.request(0, 0, 4, 5);
  const auto c = rr.request(2, 0, 4, 6);  // cycle 5 is over
  EXPECT_TRUE(rr.resolved(a));
  EXPECT_TRUE(rr.resolved(b));
  EXPECT_FALSE(rr.resolved(c));
  EXPECT_EQ(rr.collect(b).start, 5u);
  EXPECT_EQ(rr.collect(a).start, 6u);
  EXPECT_THROW(rr.collect(a), std::logic_error) << "collected";
  EXPECT_THROW(rr.request(0, 0, 4, 5), std::logic_error) << "cycle 5 is closed";
  rr.resolve(6);
  EXPECT_EQ(rr.collect(c).start, 7u);
  EXPECT_THROW(rr.request(0, 0, 4, 6), std::logic_error) << "resolved";
  EXPECT_NO_THROW(rr.request(0, 0, 4, 7));
  EXPECT_THROW(rr.collect(99), std::logic_error);
  // fcfs: known on return, and the same cycle stays open.
  LocalMemoryTiming fcfs = with(memory(1, 0, 4, 1, 4, MemoryArbitration::Fcfs));
  const auto d = fcfs.request(1, 0, 4, 5);
  EXPECT_TRUE(fcfs.resolved(d));
  EXPECT_EQ(fcfs.collect(fcfs.request(0, 0, 4, 5)).start, 6u);
  EXPECT_EQ(fcfs.collect(d).start, 5u);
}

TEST(LocalMemoryTiming, BadRequestsAndConfigurationsAreRefused) {
  LocalMemoryTiming m = with(memory(1, 1, 4, 1, 4));
  EXPECT_THROW(m.request(3, 0, 4, 0), std::invalid_argument);
  EXPECT_THROW(m.request(-1, 0, 4, 0), std::invalid_argument);
  EXPECT_THROW(m.request(0, 0, 0, 0), std::invalid_argument);
  m.request(0, 0, 4, 10);
  EXPECT_THROW(m.request(0, 0, 4, 9), std::logic_error) << "time goes forward";
  EXPECT_THROW(with(memory(-1, 0, 4, 1, 4)), std::invalid_argument);
  EXPECT_THROW(with(memory(1, 0, 0, 1, 4)), std::invalid_argument);
  EXPECT_THROW(with(memory(1, 0, 4, 0, 4)), std::invalid_argument);
  EXPECT_THROW(with(memory(1, 0, 4, 1, 0)), std::invalid_argument);
  EXPECT_THROW(with(memory(1, 0, 4, 1, 4), 0), std::invalid_argument);
}

TEST(LocalMemoryTiming, TheConfigurationComesFromTheMachinesKeys) {
  MachineConfig c;
  const Config d = Config::from(c);
  EXPECT_EQ(d.ports, 0) << "the default memory is ideal: the constant costs of the model before it";
  EXPECT_EQ(d.banks, 0);
  EXPECT_EQ(d.interleave_bytes, 16u);
  EXPECT_EQ(d.latency, 2u);
  EXPECT_EQ(d.bytes_per_cycle, 16u);
  EXPECT_EQ(d.arbitration, MemoryArbitration::RoundRobin);
  // A voxel entry, unloaded, takes the 2 cycles the constant voxel_read_cycles gave before the
  // memory timed it, under either preset.
  EXPECT_EQ(with(d).unloaded_latency(8), 2u);
  set_config(c, "memory_ports", "2");
  set_config(c, "memory_banks", "8");
  set_config(c, "memory_interleave_bytes", "16");
  set_config(c, "memory_latency", "3");
  set_config(c, "memory_bytes_per_cycle", "8");
  set_config(c, "memory_arbitration", "fcfs");
  const Config e = Config::from(c);
  EXPECT_EQ(e.ports, 2);
  EXPECT_EQ(e.banks, 8);
  EXPECT_EQ(e.interleave_bytes, 16u);
  EXPECT_EQ(e.latency, 3u);
  EXPECT_EQ(e.bytes_per_cycle, 8u);
  EXPECT_EQ(e.arbitration, MemoryArbitration::Fcfs);
  MachineConfig paper;
  apply_preset(paper, "paper");
  const Config p = Config::from(paper);
  EXPECT_EQ(p.ports, 1);
  EXPECT_EQ(p.banks, 1);
  EXPECT_EQ(p.interleave_bytes, 4u);
  EXPECT_EQ(p.latency, 1u);
  EXPECT_EQ(p.bytes_per_cycle, 4u);
  EXPECT_EQ(with(p).unloaded_latency(8), 2u);
}

// Random requests: no port or bank serves two beats in a cycle, every grant obeys the formulas, the
// statistics add up, the ideal memory never stalls, and under round robin and fixed priority the
// order the requests of a cycle are made in changes nothing.
TEST(LocalMemoryTiming, RandomRequestsNeverDoubleBookAndTheirGrantsObeyTheFormulas) {
  std::mt19937 rng(7);
  for (int run = 0; run < 60; ++run) {
    const int ports = int(rng() % 3), banks = int(rng() % 5), requesters = 1 + int(rng() % 4);
    // The last argument drawn first (geom/test_random.h says why).
    const MemoryArbitration arbitration = MemoryArbitration(rng() % 3);
    const uint64_t width = 1 + rng() % 8, latency = 1 + rng() % 4;
    const Config c = memory(ports, banks, 1 + rng() % 8, latency, width, arbitration);
    struct Req {
      int r;
      uint64_t a, b, cycle;
    };
    std::vector<Req> reqs;
    for (uint64_t cycle = 0; cycle < 40; cycle += rng() % 3)
      for (int n = int(rng() % 4); n > 0; --n)
        reqs.push_back({int(rng() % requesters), rng() % 64, 1 + rng() % 20, cycle});
    // The grants in the order of `reqs`, the requests made in the order of `order` (indices).
    auto run_all = [&](const std::vector<size_t>& order) {
      LocalMemoryTiming m = with(c, requesters);
      std::vector<LocalMemoryTiming::Ticket> t(reqs.size());
      for (size_t i : order) t[i] = m.request(reqs[i].r, reqs[i].a, reqs[i].b, reqs[i].cycle);
      m.resolve(~0ull - 1);
      std::vector<Grant> g;
      for (LocalMemoryTiming::Ticket ticket : t) g.push_back(m.collect(ticket));
      return std::make_pair(std::move(m), g);
    };
    std::vector<size_t> order(reqs.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto [m, grants] = run_all(order);
    std::set<std::pair<int, uint64_t>> port_cycles, bank_cycles;
    std::vector<uint64_t> stall(size_t(requesters), 0);
    for (size_t i = 0; i < reqs.size(); ++i) {
      const Req& q = reqs[i];
      const Grant& g = grants[i];
      const uint64_t beats = (q.b + c.bytes_per_cycle - 1) / c.bytes_per_cycle;
      EXPECT_GE(g.start, q.cycle);
      EXPECT_EQ(g.completion, g.start + c.latency + beats - 1);
      EXPECT_EQ(g.completion - q.cycle - m.unloaded_latency(q.b), g.stall());
      if (ports == 0 && banks == 0) {
        EXPECT_EQ(g.stall(), 0u);
      }
      stall[size_t(q.r)] += g.stall();
      for (uint64_t k = 0; k < beats; ++k) {
        EXPECT_TRUE(port_cycles.insert({g.port, g.start + k}).second)
            << "port " << g.port << " twice in one cycle";
        if (banks == 0) continue;
        const uint64_t lo = q.a + k * c.bytes_per_cycle,
                       hi = q.a + std::min(q.b, (k + 1) * c.bytes_per_cycle);
        std::set<int> used;
        for (uint64_t byte = lo; byte < hi; ++byte)
          used.insert(int(byte / c.interleave_bytes % uint64_t(banks)));
        for (int b : used)
          EXPECT_TRUE(bank_cycles.insert({b, g.start + k}).second)
              << "bank " << b << " twice in one cycle";
      }
    }
    for (int r = 0; r < requesters; ++r)
      EXPECT_EQ(m.requesters()[size_t(r)].stall_cycles, stall[size_t(r)]);
    uint64_t port_busy = 0, bank_busy = 0;
    for (const auto& p : m.ports()) port_busy += p.busy_cycles;
    for (const auto& b : m.banks()) bank_busy += b.busy_cycles;
    EXPECT_EQ(port_busy, port_cycles.size());
    EXPECT_EQ(bank_busy, bank_cycles.size());
    if (ports > 0) {
      EXPECT_EQ(m.ports().size(), size_t(ports));
    }
    if (c.arbitration == MemoryArbitration::Fcfs) continue;
    // Each cycle's requests made highest requester first (each requester's own in their order):
    // the same grants.
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
      return reqs[x].cycle != reqs[y].cycle ? reqs[x].cycle < reqs[y].cycle : reqs[x].r > reqs[y].r;
    });
    const auto [m2, grants2] = run_all(order);
    for (size_t i = 0; i < reqs.size(); ++i) {
      EXPECT_EQ(grants2[i].start, grants[i].start) << "run " << run << ", request " << i;
      EXPECT_EQ(grants2[i].port, grants[i].port) << "run " << run << ", request " << i;
    }
  }
}

// First come, first served, so requests are admitted in the order made: each grant is the earliest
// start, at or after its issue, at which the lowest-numbered port is free for all its beats and
// every bank each beat uses is free, given the grants before it (found here by trying every start
// and port in turn, on sets of booked cycles). Long requests among short ones, on few ports and
// banks, so that a request has to look past many booked cycles.
TEST(LocalMemoryTiming, EachGrantIsTheEarliestFreeStartGivenTheGrantsBeforeIt) {
  std::mt19937 rng(5);
  for (int run = 0; run < 80; ++run) {
    const int ports = int(rng() % 3), banks = int(rng() % 4);
    const uint64_t width = 1 + rng() % 8, granule = 1 + rng() % 8;
    const Config c = memory(ports, banks, granule, 1, width, MemoryArbitration::Fcfs);
    LocalMemoryTiming m = with(c, 2);
    using Booked = std::vector<std::set<uint64_t>>;
    Booked port_booked = Booked(size_t(ports)), bank_booked = Booked(size_t(banks));
    uint64_t cycle = 0;
    for (int i = 0; i < 120; ++i) {
      cycle += rng() % 3;
      const uint64_t address = rng() % 256, bytes = 1 + (rng() % 4 == 0 ? rng() % 96 : rng() % 8);
      const uint64_t beats = (bytes + width - 1) / width;
      const Grant g = m.collect(m.request(int(rng() % 2), address, bytes, cycle));
      if (ports == 0) continue;  // a port for every request: only banks make it wait
      auto fits = [&](uint64_t s, int p) {
        for (uint64_t k = 0; k < beats; ++k) {
          if (port_booked[size_t(p)].count(s + k)) return false;
          const uint64_t lo = address + k * width, hi = address + std::min(bytes, (k + 1) * width);
          for (uint64_t byte = lo; byte < hi && banks > 0; ++byte)
            if (bank_booked[size_t(byte / granule % uint64_t(banks))].count(s + k)) return false;
        }
        return true;
      };
      uint64_t s = cycle;
      int p = 0;
      for (;; ++s) {
        for (p = 0; p < ports && !fits(s, p); ++p) {
        }
        if (p < ports) break;
      }
      ASSERT_EQ(g.start, s) << "run " << run << ", request " << i;
      ASSERT_EQ(g.port, p) << "run " << run << ", request " << i;
      for (uint64_t k = 0; k < beats; ++k) {
        port_booked[size_t(p)].insert(s + k);
        const uint64_t lo = address + k * width, hi = address + std::min(bytes, (k + 1) * width);
        for (uint64_t byte = lo; byte < hi && banks > 0; ++byte)
          bank_booked[size_t(byte / granule % uint64_t(banks))].insert(s + k);
      }
    }
  }
}

// Grants are kept by ticket until collected, however many are held and in whatever order they are
// collected: more than the table of recent tickets holds, so that tickets share its places.
TEST(LocalMemoryTiming, EveryGrantIsKeptUntilCollectedHoweverManyAreHeld) {
  LocalMemoryTiming m = with(memory(0, 0, 4, 2, 4, MemoryArbitration::Fcfs));
  std::vector<LocalMemoryTiming::Ticket> t;
  for (uint64_t i = 0; i < 10000; ++i) t.push_back(m.request(0, 4 * i, 4 * (1 + i % 3), i));
  // Every other one first, then the rest from the newest: each grant is its own request's.
  for (int pass = 0; pass < 2; ++pass)
    for (size_t k = 0; k < t.size(); ++k) {
      const size_t i = pass == 0 ? 2 * k : t.size() - 1 - k;
      if (i >= t.size() || (pass == 1 && i % 2 == 0)) continue;
      ASSERT_TRUE(m.resolved(t[i])) << i;
      const Grant g = m.collect(t[i]);
      ASSERT_EQ(g.issue, i);
      ASSERT_EQ(g.completion, i + 2 + i % 3) << i;  // unloaded: latency + beats - 1
      ASSERT_FALSE(m.resolved(t[i])) << i;
    }
  EXPECT_THROW(m.collect(t[0]), std::logic_error);
  EXPECT_THROW(m.collect(t.back()), std::logic_error);
}

}  // namespace
}  // namespace rtm
