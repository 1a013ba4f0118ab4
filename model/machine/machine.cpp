#include "machine/machine.h"

#include "machine/engine_hosted_pe.h"
#include "machine/gtkw.h"
#include "machine/modules_pe.h"
#include "machine/partition.h"
#include "render/image_io.h"
#include "render/scene_needs.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

namespace rtm {

using sc_core::sc_time;

namespace {

class Machine : public sc_core::sc_module {
 public:
  std::unique_ptr<sc_core::sc_clock> clock;  ///< clocked timing only; edges mid-cycle
  std::unique_ptr<Timekeeper> keeper;        ///< arbitration = ranked only
  std::vector<std::unique_ptr<Pe>> pes;
  std::unique_ptr<Host> host;
  SceneNeeds needs;
  PeUnits units;
  uint64_t scene_bytes = 0;

  SC_HAS_PROCESS(Machine);
  std::string engine_unsupported;  ///< why the PEs run as modules; empty: on the engine

  Machine(sc_core::sc_module_name name, const Scene& s, const Grid& g, const MachineConfig& c, bool progress,
          bool tracing)
      : sc_module(name), engine_unsupported(rtm::engine_unsupported(c, tracing)), config_(c), progress_(progress) {
    const sc_time period(c.clock_ns, sc_core::SC_NS);
    if (c.timing == Timing::Clocked)
      clock = std::make_unique<sc_core::sc_clock>("clk", period, 0.5, period / 2, true);
    if (c.arbitration == MachineConfig::Arbitration::Ranked) keeper = std::make_unique<Timekeeper>("timekeeper");
    auto parts = partition_screen(s.camera.width, s.camera.height, c);
    auto image = std::make_shared<SceneImage>(s, g, c);
    needs = image->visit([&](const auto& mem) { return analyse_scene(s, mem.rams); });
    scene_bytes = image->bytes;
    if (c.leave_out) {
      units.shadow_rays = needs.shadow_rays;
      units.reflection = needs.reflected_rays;
      units.refraction = needs.transmitted_rays;
      units.spawn_path = needs.spawns_rays();
    }
    std::vector<Pe*> raw;
    for (int i = 0; i < c.pes; ++i) {
      const std::string pe = "pe" + std::to_string(i);
      const size_t pixels = parts[size_t(i)].size();
      if (engine_unsupported.empty())
        pes.push_back(std::make_unique<EngineHostedPe>(pe.c_str(), i, c, units, pixels, keeper.get()));
      else
        pes.push_back(std::make_unique<ModulesPe>(pe.c_str(), i, c, units, pixels, clock.get(), keeper.get()));
      raw.push_back(pes.back().get());
    }
    total_pixels_ = uint64_t(s.camera.width) * uint64_t(s.camera.height);
    host = std::make_unique<Host>("host", c, s, g, image, std::move(parts), raw, keeper.get());
    for (int i = 0; i < c.pes; ++i) host->links[size_t(i)]->bind(pes[size_t(i)]->memory.socket);
    // The clock, and units retrying writes into full FIFOs, keep a simulation alive even when
    // the loop has stalled: watch for it.
    if (progress_ || c.timing == Timing::Clocked || c.flow_control == FlowControl::None) SC_THREAD(monitor);
  }

 private:
  /// Every few thousand cycles: redraw the progress line (at most twice a second of wall time),
  /// and stop the simulation if nothing has moved for a long while (a deadlock the clock would
  /// otherwise hide).
  void monitor() {
    const auto start = std::chrono::steady_clock::now();
    auto last_draw = start;
    const sc_time step = sc_time(config_.clock_ns, sc_core::SC_NS) * 4096.0;
    uint64_t last_work = ~0ull;
    int idle = 0;
    while (!host->done) {
      sc_core::wait(step);
      uint64_t primaries = 0, rays = 0, work = 0;
      for (auto& pe : pes) {
        const PeCounters& k = pe->ctx.counters;
        primaries += k.counts.rays[0];
        rays += k.counts.total_rays();
        work += k.front.items + k.search.items + k.mac.items + k.root.items + k.shade.items;
      }
      const bool host_busy = sc_core::sc_time_stamp() < host->busy_until;
      idle = (work == last_work && !host_busy) ? idle + 1 : 0;
      last_work = work;
      if (idle >= 8) {
        stalled = true;
        sc_core::sc_stop();
        return;
      }
      if (!progress_) continue;
      const auto now = std::chrono::steady_clock::now();
      if (now - last_draw < std::chrono::milliseconds(500) || now - start < std::chrono::seconds(1)) continue;
      last_draw = now;
      std::fprintf(stderr, "\r%llu rays, %5.1f%% of primary rays issued, %.3g cycles   ", (unsigned long long)rays,
                   100.0 * double(primaries) / double(std::max<uint64_t>(1, total_pixels_)),
                   sc_core::sc_time_stamp() / sc_time(config_.clock_ns, sc_core::SC_NS));
      std::fflush(stderr);
      drew = true;
    }
  }

 public:
  bool stalled = false;  ///< the monitor stopped a simulation in which nothing moved
  bool drew = false;     ///< a progress line is on the terminal

 private:
  MachineConfig config_;
  bool progress_;
  uint64_t total_pixels_ = 0;
};

std::vector<FifoSummary> summarise_fifos(std::vector<std::unique_ptr<Pe>>& pes, sc_time end) {
  std::map<std::string, FifoSummary> by_kind;
  std::map<std::string, int> count;
  for (auto& pe : pes)
    for (auto& [name, st] : pe->fifo_stats()) {
      FifoSummary& f = by_kind[st->kind];
      f.kind = st->kind;
      f.depth = st->depth;
      f.peak = std::max(f.peak, st->peak);
      f.mean += end.to_seconds() > 0 ? st->occupancy_time / end.to_seconds() : 0;
      ++count[st->kind];
    }
  std::vector<FifoSummary> out;
  for (auto& [kind, f] : by_kind) {
    f.mean /= count[kind];
    out.push_back(f);
  }
  return out;
}

}  // namespace

MachineResult run_machine(const Scene& s, const Grid& g, const MachineConfig& c, const MachineOptions& opt) {
  c.validate();
  // The kernel's informational notes (the machine stopping itself when the frame is gathered,
  // the trace file's time unit) are not news to the user.
  sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  const auto t0 = std::chrono::steady_clock::now();
  Machine top("machine", s, g, c, opt.progress && isatty(2), !opt.vcd.empty());

  std::vector<EventLog> logs(opt.event_log.empty() ? 0 : size_t(c.pes));
  for (size_t pe = 0; pe < logs.size(); ++pe) top.pes[pe]->ctx.log = &logs[pe];

  sc_core::sc_trace_file* tf = nullptr;
  std::unique_ptr<Waveform> wave;
  if (!opt.vcd.empty()) {
    std::string base = opt.vcd;
    if (base.size() > 4 && base.substr(base.size() - 4) == ".vcd") base.resize(base.size() - 4);
    tf = sc_core::sc_create_vcd_trace_file(base.c_str());
    tf->set_time_unit(1, sc_core::SC_NS);
    wave = std::make_unique<Waveform>(tf);
    const sc_time period(c.clock_ns, sc_core::SC_NS);
    for (int pe : opt.vcd_pes) {
      if (pe < 0 || pe >= c.pes) continue;
      PeContext& ctx = top.pes[size_t(pe)]->ctx;
      ctx.window.enabled = true;
      ctx.window.from = period * double(opt.vcd_from_cycle);
      if (opt.vcd_to_cycle != UINT64_MAX) ctx.window.to = period * double(opt.vcd_to_cycle);
      top.pes[size_t(pe)]->trace(*wave);
    }
  }

  sc_core::sc_start();
  if (top.drew) std::fprintf(stderr, "\r%80s\r", "");

  MachineResult r;
  r.end = sc_core::sc_time_stamp();
  r.host = top.host->times;
  for (auto& pe : top.pes) {
    if (!pe->finished()) {
      r.deadlock = true;
      r.deadlock_report += pe->occupancy_report() + "\n";
    }
  }
  if (!top.host->done || top.stalled) r.deadlock = true;
  r.image = top.host->image;
  for (auto& pe : top.pes) {
    const PeCounters& k = pe->ctx.counters;
    r.counts.add(k.counts);
    r.mac_products += k.mac_products;
    r.mac_busy_cycles += k.mac.busy_cycles;
    r.spills += k.spills;
    r.per_pe.push_back(k);
  }
  r.fifos = summarise_fifos(top.pes, r.end);
  r.needs = top.needs;
  r.engine_unsupported = top.engine_unsupported;
  r.scene_bytes = top.scene_bytes;
  r.units = top.units;
  for (auto [kept, name] : {std::pair<bool, const char*>{top.units.spawn_path, "spawn_fifo"},
                            {top.units.shadow_rays, "shading.shadow_rays"},
                            {top.units.reflection, "shading.reflection"},
                            {top.units.refraction, "shading.refraction"}})
    if (!kept) r.left_out_units.push_back(name);
  for (auto& pe : top.pes) {
    r.mac_products_saved += pe->ctx.counters.mac_products_saved;
    r.mac_cycles_saved += pe->ctx.counters.mac_cycles_saved;
  }
  r.cycles = uint64_t(std::llround(r.end / sc_time(c.clock_ns, sc_core::SC_NS)));
  r.stats = frame_stats(r, c);
  if (tf) sc_core::sc_close_vcd_trace_file(tf);
  if (wave && !opt.gtkw.empty()) write_gtkw(opt.gtkw, opt.vcd, *wave);
  if (!logs.empty()) {
    std::ostringstream text;
    write_event_log(text, logs, top.pes[0]->ctx.cycle);
    write_text_atomically(opt.event_log, text.str());
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rtm
