#include "printed_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace rtm {

namespace {

/// "1 pixel", "2 pixels".
std::string counted(uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

void print_rays(const TraceCounts& c) {
  std::printf("rays: %llu primary, %llu shadow, %llu reflected, %llu transmitted\n",
              (unsigned long long)c.rays[0], (unsigned long long)c.rays[1],
              (unsigned long long)c.rays[2], (unsigned long long)c.rays[3]);
}

void print_files(const RenderFiles& files) {
  std::printf("image: %s\nstats: %s\n", files.image.c_str(), files.stats.c_str());
  if (!files.id_map.empty()) std::printf("id map: %s\n", files.id_map.c_str());
  if (!files.error_map.empty())
    std::printf("error map: %s (picture: %s)\n", files.error_map.c_str(),
                files.error_picture.c_str());
  if (!files.vcd.empty())
    std::printf("waveform: %s (GTKWave: gtkwave %s)\n", files.vcd.c_str(), files.gtkw.c_str());
}

/// One share per unit that utilisation counts, along the pipeline, each under its label.
void print_units(const char* over, const UnitShares& u) {
  std::printf("utilisation %s", over);
  const char* separator = ": ";
  for (UnitKind k : pipeline_order()) {
    const UnitSpec& s = unit_spec(k);
    if (!s.in_utilisation) continue;
    std::printf("%s%s %.1f%%", separator, s.label, 100 * u[k]);
    separator = ", ";
  }
}

/// The PE's arithmetic: `precision`, and each unit whose own key says otherwise.
std::string precision_text(const MachineConfig& c) {
  std::string s = to_string(c.precision);
  for (auto [name, p] : {std::pair{"intersection", c.intersection_precision_in_force()},
                         {"dda", c.dda_precision_in_force()},
                         {"shading", c.shading_precision_in_force()}})
    if (p != c.precision) s += std::string(", ") + name + " " + to_string(p);
  return s;
}

/// Which machine ran: its preset, then every key on which it differs from the preset.
std::string configuration_text(const MachineConfig& c) {
  std::string s = "preset " + c.preset;
  const char* sep = ", then ";
  for (const std::string& key : keys_apart_from_preset(c)) s += sep + key, sep = ", ";
  return s;
}

/// A line when the machine did other work than the reference (reference.counts_match false):
/// each count that differs, both values, the difference absolute and relative, and how much of it
/// is in the differing pixels' ray trees (what the error map accounts for). At fp64 the counts
/// must be equal: a warning. At fp32 a difference the differing pixels hold is their error; one
/// they do not hold is in pixels within 1/255 of the reference.
void print_count_differences(const TraceCounts& machine, const TraceCounts& reference,
                             const ErrorCauses& causes, const MachineConfig& c) {
  const std::vector<CountGap> gaps = count_gaps(machine, reference, causes);
  if (gaps.empty()) return;
  const bool fp64 = c.intersection_precision_in_force() == Precision::Fp64 &&
                    c.dda_precision_in_force() == Precision::Fp64 &&
                    c.shading_precision_in_force() == Precision::Fp64;
  bool all_explained = true, any_in_trees = false;
  std::printf("%s: counts differ from the reference (machine vs reference):",
              fp64 ? "warning" : "note");
  for (size_t i = 0; i < gaps.size(); ++i) {
    const CountGap& g = gaps[i];
    // Of the reference's count; two significant digits, whole percents from 100 up.
    const double relative =
        100.0 * double(g.difference()) / double(std::max<uint64_t>(1, g.count.b));
    std::printf(std::abs(relative) < 100 ? "%s %s %llu vs %llu (%+lld, %+.2g%%; "
                                         : "%s %s %llu vs %llu (%+lld, %+.0f%%; ",
                i ? "," : "", g.count.what.c_str(), (unsigned long long)g.count.a,
                (unsigned long long)g.count.b, (long long)g.difference(), relative);
    if (g.explained)
      std::printf("all in the differing pixels)");
    else if (g.in_trees == 0)
      std::printf("none in the differing pixels)");
    else
      std::printf("%+lld in the differing pixels)", (long long)g.in_trees);
    all_explained &= g.explained;
    any_in_trees |= g.in_trees != 0;
  }
  const std::string pixels = counted(causes.differing, "differing pixel", "differing pixels");
  if (fp64)
    std::printf("; at fp64 they should be equal (docs/machine.md, \"Statistics\")\n");
  else if (all_explained)
    std::printf("; all of it is in the ray trees of the %s (their causes above, the error map)\n",
                pixels.c_str());
  else if (!causes.trees_whole)
    std::printf(
        "; some differing pixels' trees could not be traced whole, so their part is not known\n");
  else
    std::printf(
        "; %s in rays of pixels within 1/255 of the reference (at fp32 rounding can change a walk "
        "or a hit "
        "without changing its pixel)\n",
        any_in_trees ? "the rest is" : "it is all");
}

/// Why the pixels differ: each cause's pixels, and the generation and kind where most part.
void print_causes(const ErrorCauses& e) {
  if (e.differing == 0) return;
  std::printf("why they differ (first ray to part from the reference):");
  const char* sep = "";
  for (int k = 1; k < kErrorCauses; ++k)
    if (const uint64_t n = e.by_cause[size_t(k)]) {
      const ErrorCause cause = ErrorCause(k);
      const CauseCount* most = nullptr;
      for (const CauseCount& c : e.counts)
        if (c.cause == cause && (!most || c.pixels > most->pixels)) most = &c;
      std::printf("%s %s %s (most at generation %d, %s)", sep,
                  counted(n, "pixel", "pixels").c_str(), error_cause_name(cause), most->generation,
                  ray_kind_name(most->kind));
      sep = ",";
    }
  std::printf("\n");
}

/// Each PE's working window in PE cycles, the first of a frame's PEs, and the range over all of
/// them: where a `--vcd-window` shows something (`peN+FROM:TO` counts from a window's start).
void print_working_windows(const std::vector<PeCounters>& pes, const MachineConfig& c) {
  if (pes.empty()) return;
  const sc_core::sc_time period(c.clock_ns, sc_core::SC_NS);
  auto cycle = [&](uint64_t ticks) {
    return (unsigned long long)(sc_core::sc_time::from_value(ticks) / period);
  };
  constexpr size_t kShown = 4;
  std::printf("PE working windows (cycles):");
  for (size_t i = 0; i < std::min(pes.size(), kShown); ++i)
    std::printf("%s pe%zu %llu-%llu", i ? "," : "", i, cycle(pes[i].start), cycle(pes[i].finish));
  if (pes.size() > kShown) {
    uint64_t first = UINT64_MAX, last = 0;
    for (const PeCounters& p : pes)
      first = std::min(first, p.start), last = std::max(last, p.finish);
    std::printf(", ... all %zu within %llu-%llu", pes.size(), cycle(first), cycle(last));
  }
  std::printf("\n");
}

/// The interconnect in one line: topology, links, bytes, busy time, and the busiest link's share
/// of the frame.
void print_interconnect(const MachineResult& m, const MachineConfig& c) {
  if (m.links.empty()) return;
  const sc_core::sc_time period(c.clock_ns, sc_core::SC_NS);
  const LinkUse* busiest = &m.links.front();
  uint64_t bytes = 0;
  for (const LinkUse& l : m.links) {
    bytes += l.bytes;
    if (l.busy_ticks > busiest->busy_ticks) busiest = &l;
  }
  const double busiest_cycles = sc_core::sc_time::from_value(busiest->busy_ticks) / period;
  const double share = m.cycles ? 100 * busiest_cycles / double(m.cycles) : 0;
  std::printf("interconnect: %s, %zu link%s", to_string(c.link_topology), m.links.size(),
              m.links.size() == 1 ? "" : "s");
  if (c.link_topology == MachineConfig::LinkTopology::Star ||
      c.link_topology == MachineConfig::LinkTopology::Tree)
    std::printf(", %d host port%s", c.host_ports, c.host_ports == 1 ? "" : "s");
  std::printf(": %llu bytes, busy %llu cycles", (unsigned long long)bytes,
              (unsigned long long)std::llround(sc_core::sc_time::from_value(m.host.link_busy) /
                                               period));  // as the stats round it
  if (m.links.size() == 1)
    std::printf(" (%.1f%% of the frame)\n", share);
  else
    std::printf(" over all links; the busiest, %s, %.0f cycles (%.1f%% of the frame)\n",
                busiest->name.c_str(), busiest_cycles, share);
}

void print_local_memory(const std::vector<MemoryLayout>& pes) {
  const size_t fullest = fullest_pe(pes);
  const MemoryLayout& m = pes[fullest];
  std::printf("local memory: pe%zu uses %.1f of %.1f MiB (%s); spill area %llu rays\n", fullest,
              double(m.used) / (1 << 20), double(m.capacity) / (1 << 20), m.describe().c_str(),
              (unsigned long long)m.spill_rays());
}

/// What the PEs' local memories did: traffic, what contention and late data cost, the stores.
/// Stalls and waits are each requester's, summed over requesters and PEs: requester-cycles, which
/// can exceed the working windows.
void print_memory_traffic(const MachineResult& m, const MachineConfig& c) {
  uint64_t requests = 0, bytes = 0, stall = 0, wait = 0, hits = 0, misses = 0;
  for (const MemoryUse& u : m.memory_use) {
    for (const MemoryUse::Requester& q : u.requesters)
      requests += q.requests, bytes += q.bytes, stall += q.stall_cycles;
    wait += u.wait_cycles();
    hits += u.coef_hits;
    misses += u.coef_misses;
  }
  std::printf(
      "memory traffic: %llu requests, %.1f MiB (%s); contention stalls %llu requester-cycles, "
      "results waiting "
      "%llu requester-cycles (%.1f%% of the PEs' working windows); coefficient RAM hit rate "
      "%.1f%%\n",
      (unsigned long long)requests, double(bytes) / (1 << 20),
      c.memory_ports == 0 && c.memory_banks == 0 ? "ideal memory" : "timed",
      (unsigned long long)stall, (unsigned long long)wait, 100 * m.stats.profile.memory_wait,
      hits + misses == 0 ? 100.0 : 100.0 * double(hits) / double(hits + misses));
}

/// What the machine costs in one line (docs/cost.md): on-chip area, the memory's apart, the
/// frame's energy and power, and the unit that spends the most.
void print_cost(const MachineCost& m) {
  const UnitCost* top = nullptr;
  for (const UnitCost& u : m.units)
    if (!top || u.dynamic_pj > top->dynamic_pj) top = &u;
  const double frame = m.energy_pj * 1e-12;
  std::printf(
      "cost (%s): %.3g mm2 on chip (%.3g mm2 a PE), local memory %.3g mm2 of DRAM apart; %.3g J a "
      "frame "
      "(dynamic %.0f%%, of it local memory %.0f%%, link %.0f%%), %.3g J a ray, %.3g W; unit "
      "spending most: %s %.0f%%\n",
      m.technology.c_str(), m.area_mm2(), m.pe_logic_mm2 + m.pe_sram_mm2, m.memory_mm2, frame,
      m.energy_pj > 0 ? 100 * m.dynamic_pj / m.energy_pj : 0.0,
      m.dynamic_pj > 0 ? 100 * m.memory_dynamic_pj / m.dynamic_pj : 0.0,
      m.dynamic_pj > 0 ? 100 * m.link_dynamic_pj / m.dynamic_pj : 0.0, m.energy_per_ray_pj * 1e-12,
      m.power_w, top ? unit_name(top->inventory.kind) : "none",
      top && m.dynamic_pj > 0 ? 100 * top->dynamic_pj / m.dynamic_pj : 0.0);
}

}  // namespace

void print_reference_summary(const Scene& s, const Grid& g, double grid_seconds,
                             const ReferenceResult& r, const RenderFiles& files) {
  std::printf("%s: %dx%d, %zu primitives, grid %dx%dx%d\n", s.name.c_str(), s.camera.width,
              s.camera.height, s.primitives.size(), g.n[0], g.n[1], g.n[2]);
  print_rays(r.counts);
  // The grid is built before the trace and is not part of its time: shown beside it.
  std::printf(
      "wall time: %.3f s (reference renderer), %.2f M rays/s; grid build %.3f s (%zu references)\n",
      r.wall_seconds, double(r.counts.total_rays()) / r.wall_seconds / 1e6, grid_seconds,
      g.items.size());
  print_files(files);
}

void print_machine_summary(const Scene& s, const Grid& g, double grid_seconds,
                           const MachineConfig& c, const MachineResult& m, const MachineCost& cost,
                           const ImageError& err, const ErrorCauses& causes,
                           const ReferenceResult& ref, bool ref_cached, const RenderFiles& files) {
  const FrameStats& st = m.stats;
  std::printf("%s: %dx%d, %zu primitives, grid %dx%dx%d, %d PE%s (%s, %s, %s timing); %s\n",
              s.name.c_str(), s.camera.width, s.camera.height, s.primitives.size(), g.n[0], g.n[1],
              g.n[2], c.pes, c.pes == 1 ? "" : "s", to_string(c.partition),
              precision_text(c).c_str(), to_string(c.timing), configuration_text(c).c_str());
  std::printf("cycles: %llu (%.3f ms simulated at %.4g ns a cycle)\n", (unsigned long long)m.cycles,
              sc_core::sc_time::from_value(m.end).to_seconds() * 1e3, c.clock_ns);
  if (m.frame_done.size() > 1)
    std::printf(
        "frames: %zu; the first whole at the host at cycle %llu, then one every %.0f "
        "cycles (%.4g frames/s)\n",
        m.frame_done.size(), (unsigned long long)m.frame_done.front(), m.frame_cycles(),
        1e9 / (m.frame_cycles() * c.clock_ns));
  print_rays(m.counts);
  std::printf("rays per cycle: %.4f\n",
              double(m.counts.total_rays()) / double(std::max<uint64_t>(1, m.cycles)));
  // Both: the host's pre-processing and the transfer come before the PEs start, so a unit saturated
  // while the PEs work can look half idle over the frame.
  print_units("over the frame", st.utilisation);
  std::printf("\n");
  print_units("over the PEs' working windows", st.profile.busy);
  std::printf(", credit stall %.1f%%\n", 100 * st.profile.credit_stall);
  print_working_windows(m.per_pe, c);
  print_interconnect(m, c);
  print_local_memory(m.memory);
  print_memory_traffic(m, c);
  std::printf("bottleneck: %s: %s\n", st.bottleneck.name.c_str(), st.bottleneck.reason.c_str());
  print_cost(cost);
  std::printf("cycles / MAC bound %.2f, load imbalance %.2f (longest PE working window / mean)\n",
              st.cycles_over_mac_bound, st.profile.imbalance);
  // rmse and max are of channel values on 0..1.
  std::printf(
      "error vs reference: rmse %.3g, psnr %.1f dB, max %.3g, %s off by > 1/255, %s\n", err.rmse,
      err.psnr_db, err.max_abs, counted(err.pixels_over_1_255, "pixel", "pixels").c_str(),
      (counted(err.primary_ids_differing, "primary hit differs", "primary hits differ")).c_str());
  print_causes(causes);
  print_count_differences(m.counts, ref.counts, causes, c);
  std::printf(
      "wall time: %.3f s model (%s), %.3f s reference%s, %.3f s explaining the differing pixels; "
      "grid build %.3f s (%zu references)\n",
      m.wall_seconds,
      m.engine_unsupported.empty() ? "PEs on the PE engine"
                                   : ("PEs as modules: " + m.engine_unsupported).c_str(),
      ref.wall_seconds, ref_cached ? " (cached)" : "", causes.seconds, grid_seconds,
      g.items.size());
  print_files(files);
}

}  // namespace rtm
