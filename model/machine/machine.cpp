#include "machine/machine.h"

#include "machine/engine_pe.h"
#include "frame/gtkw.h"
#include "machine/modular_pe.h"
#include "frame/partition.h"
#include "machine/sim_time.h"
#include "machine/watchdog.h"
#include "render/atomic_file.h"
#include "render/image_io.h"
#include "render/partial_files.h"
#include "render/progress.h"
#include "render/scene_needs.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
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
  std::unique_ptr<WorkerPool>
      own_pool;  ///< the PEs on the engine, when the caller started no threads
  std::unique_ptr<EngineDriver> driver;  ///< the PEs on the engine only
  std::vector<std::unique_ptr<Pe>> pes;
  std::unique_ptr<Host> host;
  SceneNeeds needs;
  PeUnits units;
  std::vector<MemoryLayout> memory;                   ///< per PE
  std::unique_ptr<ProgressDisplay> progress_display;  ///< null: none
  std::unique_ptr<Watchdog> watchdog;

  SC_HAS_PROCESS(Machine);
  std::string engine_unsupported;  ///< why the PEs run as modules; empty: on the engine

  Machine(sc_core::sc_module_name name, const Scene& s, const Grid& g, const MachineConfig& c,
          bool progress, bool tracing, uint64_t max_memory, uint64_t max_rays, WorkerPool* pool,
          int sim_threads)
      : sc_module(name), engine_unsupported(rtm::engine_unsupported(c, tracing)), config_(c) {
    const sc_time period(c.clock_ns, sc_core::SC_NS);
    if (c.timing == Timing::Clocked && !engine_unsupported.empty())  // the engine clocks its own
      clock = std::make_unique<sc_core::sc_clock>("clk", period, 0.5, period / 2, true);
    if (c.arbitration == MachineConfig::Arbitration::Ranked)
      keeper = std::make_unique<Timekeeper>("timekeeper");
    auto parts = partition_screen(s.camera.width, s.camera.height, c);
    const uint64_t screen_pixels = uint64_t(s.camera.width) * uint64_t(s.camera.height);
    auto image = std::make_shared<SceneImage>(s, g, c);
    needs = image->visit([&](const auto& mem) { return analyse_scene(s, mem.rams); });
    check_local_memory(*image, parts, c, screen_pixels);
    if (c.leave_out) {
      units.shadow_rays = needs.shadow_rays;
      units.reflection = needs.reflected_rays;
      units.refraction = needs.transmitted_rays;
      units.spawn_path = needs.spawns_rays();
    }
    if (engine_unsupported.empty()) {
      if (!pool) {
        own_pool = std::make_unique<WorkerPool>(engine_threads(sim_threads, c.pes));
        pool = own_pool.get();
      }
      driver = std::make_unique<EngineDriver>("engines", *pool);
    }
    std::vector<Pe*> raw;
    for (int i = 0; i < c.pes; ++i) {
      const std::string pe = "pe" + std::to_string(i);
      const size_t pixels = parts[size_t(i)].size();  // dynamic: none yet
      if (engine_unsupported.empty())
        pes.push_back(
            std::make_unique<EnginePe>(pe.c_str(), i, c, units, pixels, keeper.get(), *driver));
      else
        pes.push_back(std::make_unique<ModularPe>(pe.c_str(), i, c, units, pixels, clock.get(),
                                                  keeper.get()));
      raw.push_back(pes.back().get());
      PeState& st = pes.back()->ctx;
      st.spill_rays = memory[size_t(i)].spill_rays();
      st.memory = std::make_shared<PeMemory>(
          c, *image, c.partition == Partition::Dynamic ? screen_pixels : pixels);
      st.spawn_fanout =
          (units.shadow_rays ? s.lights.size() : 0) + units.reflection + units.refraction;
      if (c.frames > 1) {
        st.frame_rays = pixels;
        if (c.voxelisation == MachineConfig::Voxelisation::Pe)
          st.frame_switch = pe_voxelisation_ticks(c, g);
      }
    }
    host = std::make_unique<Host>("host", c, s, g, image, std::move(parts), raw, keeper.get());
    for (int i = 0; i < c.pes; ++i) {
      host->links[size_t(i)]->bind(pes[size_t(i)]->memory.socket);
      pes[size_t(i)]->memory.ask_for_tile = [this, i] { host->ask_for_tile(i); };
      pes[size_t(i)]->memory.tell_frame_end = [this, i] { host->pe_frame_ended(i); };
    }
    if (progress)
      progress_display =
          std::make_unique<ProgressDisplay>(uint64_t(s.camera.width) * uint64_t(s.camera.height));
    for (auto& pe : pes) watched_.push_back(pe.get());
    watchdog = std::make_unique<Watchdog>(s, g, c, watched_, *host, max_memory, max_rays,
                                          progress_display.get());
    // With arbitration = kernel a monitor process's wake-ups would take part in SystemC's
    // same-time order, and so in the figures: there the monitor looks from outside, between
    // slices of the simulation (run()).
    if (c.arbitration == MachineConfig::Arbitration::Ranked) SC_THREAD(monitor);
  }

  /// Simulates the frame to its end, or until the monitor stops it. With arbitration = kernel in
  /// slices of sc_start, the monitor looking after each: sc_start(T) adds no event to the
  /// kernel's schedule (it only stops at T, after triggering what falls due then, and the next
  /// slice carries on with exactly that), so the figures are those of one sc_start().
  void run() {
    if (config_.arbitration == MachineConfig::Arbitration::Ranked) {
      sc_core::sc_start();
      return;
    }
    sc_time step = watchdog->base_step();
    for (;;) {
      sc_core::sc_start(step);
      // The host stops the simulation when the frame is gathered; no activity left is a deadlock.
      if (host->done || !sc_core::sc_pending_activity()) return;
      if (!watchdog->look(step)) {
        sc_core::sc_stop();
        return;
      }
    }
  }

  /// Lays out each PE's local memory; a PE whose sections do not fit stops the render before it
  /// starts, naming them (the PE with the most pixels needs the most).
  void check_local_memory(const SceneImage& image, const std::vector<std::vector<uint32_t>>& parts,
                          const MachineConfig& c, uint64_t screen_pixels) {
    const bool dynamic = c.partition == Partition::Dynamic;
    // A dynamic partition's PE may get any of the tiles: its memory has room for the whole screen.
    for (const auto& px : parts)
      memory.push_back(memory_layout(image, dynamic ? screen_pixels : px.size(), c));
    for (size_t pe = 0; pe < memory.size(); ++pe) {
      const MemoryLayout& m = memory[pe];
      if (m.fits()) continue;
      throw std::runtime_error("local memory too small: PE " + std::to_string(pe) + " needs " +
                               std::to_string(m.used) + " bytes (" + m.describe() +
                               ") but local_memory_bytes is " + std::to_string(m.capacity) +
                               "; a larger local memory, more PEs or a smaller frame fits");
    }
  }

  /// How many SystemC threads the machine elaborated (each needs a stack when simulation starts).
  static size_t threads(const std::vector<sc_core::sc_object*>& objects) {
    size_t n = 0;
    for (const sc_core::sc_object* o : objects) {
      const std::string kind = o->kind();
      n += kind == "sc_thread_process" || kind == "sc_cthread_process";
      n += threads(o->get_child_objects());
    }
    return n;
  }

 private:
  /// Every few thousand cycles (ranked arbitration): a look, until the frame is done or a look
  /// says stop.
  void monitor() {
    sc_time step = watchdog->base_step();
    while (!host->done) {
      sc_core::wait(step);
      if (!watchdog->look(step)) {
        sc_core::sc_stop();
        return;
      }
    }
  }

  MachineConfig config_;
  std::vector<Pe*> watched_;  ///< the PEs, as the watchdog sees them
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

/// The SystemC threads a configuration elaborates, known before elaborating it: the host, the
/// monitor and the timekeeper; with the PEs on the engine, its driver and per PE one thread, else
/// (modular_pe.cpp) per PE the front buffer, the shading unit, each search unit, and per
/// intersection lane the MAC and root threads plus the clocked MAC. run_machine counts again once
/// elaborated.
size_t expected_threads(const MachineConfig& c, bool tracing) {
  if (engine_unsupported(c, tracing).empty()) return 4 + size_t(c.pes);
  const size_t per_pe = 2 + size_t(c.search_units) +
                        size_t(c.intersection_units) * (c.timing == Timing::Clocked ? 3 : 2);
  return 3 + size_t(c.pes) * per_pe;
}

/// Each SystemC thread's stack costs the process two memory maps (the stack and its guard page);
/// past the kernel's limit the simulation cannot start (SystemC's E518 "stack setup failed").
void check_threads_fit(size_t threads, const MachineConfig& c) {
  std::ifstream limit_file("/proc/sys/vm/max_map_count");
  long limit = 0;
  if (!(limit_file >> limit) || limit <= 0) return;  // not Linux, or not readable: let SystemC try
  std::ifstream maps("/proc/self/maps");
  long in_use = 0;
  for (std::string line; std::getline(maps, line);) ++in_use;
  // Room for what loads later (the image library, thread arenas) besides the stacks.
  const long spare = 1024;
  const long needed = 2 * long(threads);
  if (needed + in_use + spare <= limit) return;
  const long per_pe = std::max<long>(1, long(threads) / c.pes);
  const long fit = std::max<long>(0, (limit - in_use - spare) / 2 / per_pe);
  throw MachineLimitError("pes: " + std::to_string(c.pes) + " PEs need " + std::to_string(threads) +
                          " SystemC threads (" + std::to_string(per_pe) +
                          " a PE with pe_simulation = " + to_string(c.pe_simulation) +
                          ", timing = " + to_string(c.timing) +
                          "); each stack takes 2 memory maps and this host allows " +
                          std::to_string(limit) + " (vm.max_map_count), " + std::to_string(in_use) +
                          " in use: at most about " + std::to_string(fit) +
                          " PEs of this configuration fit");
}

/// Creates the file (and its folder) as every output is, or says in one line why it cannot.
void open_for_writing(const std::string& path, const std::string& final_path) {
  std::error_code ec;
  if (const auto dir = std::filesystem::path(path).parent_path(); !dir.empty())
    std::filesystem::create_directories(dir, ec);
  errno = 0;
  if (!std::ofstream(path, std::ios::binary))
    throw std::runtime_error(final_path + ": cannot write: " +
                             (ec ? ec.message() : std::strerror(errno ? errno : EACCES)));
}

/// A time in whole PE cycles, as the stats give it.
uint64_t cycles_of(sc_time t, const MachineConfig& c) {
  return uint64_t(std::llround(t / sc_time(c.clock_ns, sc_core::SC_NS)));
}

/// What the save file shows of a waveform: its window, narrowed to the time the traced PEs
/// worked (before, during the host's phases, nothing of theirs changes). A window that holds
/// none of that recorded nothing: that is a warning.
GtkwView recorded_view(const std::vector<std::unique_ptr<Pe>>& pes, const std::vector<int>& traced,
                       sc_time end, const MachineConfig& c, std::vector<std::string>& warnings) {
  const TraceWindow& w = pes[size_t(traced.front())]->ctx.window;
  auto ns = [](sc_time t) { return uint64_t(std::llround(t.to_seconds() * 1e9)); };
  GtkwView view{0, ns(end), c.clock_ns};
  if (!w.placed()) {
    warnings.push_back("--vcd-window: PE " + std::to_string(w.anchor->pe) +
                       " never started (it has no pixels), so the waveform recorded nothing");
    return view;
  }
  const auto [from, to] = w.span(end);
  sc_time first = sc_core::sc_max_time(), last = sc_core::SC_ZERO_TIME;
  std::string worked;
  for (int pe : traced) {
    const PeCounters& k = pes[size_t(pe)]->ctx.counters;
    if (k.counts.rays[0] == 0) continue;  // no pixels: it never worked
    const sc_time start = sc_time::from_value(k.start), finish = sc_time::from_value(k.finish);
    worked += std::string(worked.empty() ? "" : ", ") + "PE " + std::to_string(pe) + " cycles " +
              std::to_string(cycles_of(start, c)) + ".." + std::to_string(cycles_of(finish, c));
    if (start > to || finish < from) continue;
    first = std::min(first, std::max(from, start));
    last = std::max(last, std::min(to, finish));
  }
  if (first > last) {
    warnings.push_back("--vcd-window: cycles " + std::to_string(cycles_of(from, c)) + ".." +
                       std::to_string(cycles_of(to, c)) + " hold none of the traced PEs' work (" +
                       (worked.empty() ? std::string("they have no pixels") : worked) +
                       "), so the waveform recorded nothing; e.g. --vcd-window pe" +
                       std::to_string(traced.front()) +
                       "+0:2000 records the first 2000 cycles of PE " +
                       std::to_string(traced.front()) + "'s work");
    first = from;
    last = to;
  }
  view.from_ns = ns(first);
  view.to_ns = ns(last);
  return view;
}

/// A waveform being recorded: the trace file, the VCD under its temporary name (renamed once
/// closed), the signals traced into it and the PEs whose signals they are. Empty: no waveform.
struct Recording {
  sc_core::sc_trace_file* tf = nullptr;
  std::unique_ptr<PartialFile> vcd;
  std::unique_ptr<Waveform> wave;
  std::vector<int> traced;
};

/// Opens the waveform the options ask for and traces the PEs they name, each within its window.
Recording start_waveform(Machine& top, const MachineConfig& c, const MachineOptions& opt) {
  Recording rec;
  if (opt.vcd.empty()) return rec;
  const std::string tmp = temporary_beside(vcd_file(opt.vcd));
  rec.vcd = std::make_unique<PartialFile>(tmp);
  open_for_writing(tmp,
                   vcd_file(opt.vcd));  // SystemC would report a failure twice, in its own words
  rec.tf = sc_core::sc_create_vcd_trace_file(
      tmp.substr(0, tmp.size() - 4).c_str());  // SystemC adds ".vcd"
  rec.tf->set_time_unit(1, sc_core::SC_NS);
  rec.wave = std::make_unique<Waveform>(rec.tf);
  const sc_time period(c.clock_ns, sc_core::SC_NS);
  auto time_of = [&](uint64_t cycles) {  // past the horizon: never
    return double(cycles) * double(period.value()) >= double(kTimeHorizonTicks)
               ? sc_core::sc_max_time()
               : period * double(cycles);
  };
  // Every PE's window shares the anchor: the PE it names sets it, traced or not.
  std::shared_ptr<WindowAnchor> anchor;
  if (opt.vcd_anchor_pe >= 0)
    anchor = std::make_shared<WindowAnchor>(WindowAnchor{opt.vcd_anchor_pe});
  for (auto& pe : top.pes) {
    pe->ctx.window.anchor = anchor;
    pe->ctx.window.from = time_of(opt.vcd_from_cycle);
    if (opt.vcd_to_cycle != UINT64_MAX) pe->ctx.window.to = time_of(opt.vcd_to_cycle);
  }
  for (int pe : opt.vcd_pes) {
    if (pe < 0 || pe >= c.pes) continue;
    top.pes[size_t(pe)]->ctx.window.enabled = true;
    top.pes[size_t(pe)]->trace(*rec.wave);
    rec.traced.push_back(pe);
  }
  return rec;
}

/// Why the watchdog stopped the simulation over its memory or work budget; empty if it did not.
std::string budget_stop(const Machine& top, const Scene& s, const MachineConfig& c,
                        const MachineOptions& opt) {
  if (!top.watchdog->over_budget && !top.watchdog->over_rays) return {};
  uint64_t rays = 0;
  for (auto& pe : top.pes) rays += pe->ctx.counters.counts.total_rays();
  std::ostringstream why;
  why << "the simulation stopped ";
  if (top.watchdog->over_budget)
    why << "holding " << bytes_text(top.watchdog->over_budget)
        << ", more than its memory budget of " << bytes_text(opt.max_memory) << " (--max-memory)";
  else
    why << "at its work budget of " << opt.max_rays << " rays (--max-rays)";
  why << ", at cycle " << uint64_t(sc_core::sc_time_stamp() / sc_time(c.clock_ns, sc_core::SC_NS))
      << " with " << rays << " rays traced: ";
  if (top.watchdog->over_budget)
    why << "the rays waiting in the front buffers grow with the ray tree (max_depth " << s.max_depth
        << ", threshold " << s.threshold << ")";
  else
    why << "the ray trees grow with max_depth " << s.max_depth << " and threshold " << s.threshold;
  return why.str();
}

/// Throws if the frame could not be finished: a front buffer beyond its spill area, or the
/// simulated time past its horizon.
void check_finished(const Machine& top, const MachineConfig& c) {
  for (size_t pe = 0; pe < top.pes.size(); ++pe)
    if (const PeCounters& k = top.pes[pe]->ctx.counters; k.spill_overflow)
      throw std::runtime_error(
          "local memory too small for the ray trees: PE " + std::to_string(pe) +
          "'s front buffer had " + std::to_string(k.spill_overflow) + " rays waiting at cycle " +
          std::to_string(top.pes[pe]->ctx.cycles(k.spill_overflow_at)) + ", more than its " +
          std::to_string(c.front_buffer_capacity) + " on chip and the " +
          std::to_string(top.memory[pe].spill_rays()) + " its spill area holds (" +
          std::to_string(top.memory[pe].spill_bytes()) + " bytes of local_memory_bytes " +
          std::to_string(c.local_memory_bytes) +
          "); a larger local memory, a higher threshold or a lower max_depth fits");
  if (top.watchdog->overran)
    throw std::runtime_error(
        "the simulated time passed " + describe_ticks(double(kTimeHorizonTicks)) + " at cycle " +
        std::to_string(uint64_t(sc_core::sc_time_stamp() / sc_time(c.clock_ns, sc_core::SC_NS))) +
        ", the most a frame may take (SystemC counts time in 64-bit picoseconds); a shorter "
        "clock_ns or a smaller frame fits");
}

/// Every PE's counters, its local memory's use and its FIFOs' writes, into `r`.
void add_pe_counters(Machine& top, MachineResult& r) {
  for (auto& pe : top.pes) {
    const PeCounters& k = pe->ctx.counters;
    r.counts.add(k.counts);
    r.mac_products += k.mac_products;
    const UnitStats mac = k.total(UnitKind::Mac);
    r.mac_busy_cycles += mac.busy_cycles;
    r.mac_issue_cycles += mac.issue_cycles;
    r.spills += k.spills;
    r.per_pe.push_back(k);
    pe->ctx.memory->end_of_frame();
    r.memory_use.push_back(pe->ctx.memory->use());
  }
  for (auto& pe : top.pes)
    for (auto& [name, st] : pe->fifo_stats())
      for (const FifoSpec& f : fifo_table())
        if (name == f.name) r.fifo_writes[size_t(f.id)] += st->writes;
  for (auto& pe : top.pes) {
    r.mac_products_saved += pe->ctx.counters.mac_products_saved;
    r.mac_cycles_saved += pe->ctx.counters.mac_cycles_saved;
  }
}

/// What the frame did, from the host and every PE once the simulation ended, and the figures
/// derived from it.
MachineResult collect_result(Machine& top, const MachineConfig& c) {
  MachineResult r;
  const sc_time end = sc_core::sc_time_stamp();
  const sc_time period(c.clock_ns, sc_core::SC_NS);
  r.end = end.value();
  r.clock_ticks = period.value();
  r.host = top.host->times;
  r.links = top.host->link_use();
  if (c.partition == Partition::Dynamic) r.tiles = top.host->tiles_per_pe();
  for (auto& pe : top.pes) {
    if (!pe->finished()) {
      r.deadlock = true;
      r.deadlock_report += pe->occupancy_report() + "\n";
    }
  }
  if (!top.host->done || top.watchdog->stalled) r.deadlock = true;
  r.image = top.host->image;
  add_pe_counters(top, r);
  r.fifos = summarise_fifos(top.pes, end);
  r.needs = top.needs;
  r.engine_unsupported = top.engine_unsupported;
  r.scene_bytes = top.host->scene_link_bytes();
  r.memory = top.memory;
  r.units = top.units;
  for (auto [kept, name] :
       {std::pair<bool, const char*>{top.units.spawn_path, fifo_spec(FifoId::Spawn).name},
        {top.units.shadow_rays, "shading.shadow_rays"},
        {top.units.reflection, "shading.reflection"},
        {top.units.refraction, "shading.refraction"}})
    if (!kept) r.left_out_units.push_back(name);
  r.cycles = uint64_t(std::llround(end / period));
  for (uint64_t t : top.host->times.frame_done)
    r.frame_done.push_back(cycles_of(sc_time::from_value(t), c));
  r.stats = frame_stats(r, c);
  return r;
}

/// Closes the waveform and writes its save file (a window that recorded nothing is a warning in
/// `r`), and writes the event log.
void write_recordings(Machine& top, Recording& rec, std::vector<EventLog>& logs, MachineResult& r,
                      const MachineConfig& c, const MachineOptions& opt) {
  if (rec.tf) {
    sc_core::sc_close_vcd_trace_file(rec.tf);
    rec.vcd->commit(vcd_file(opt.vcd));
  }
  if (rec.wave && !rec.traced.empty()) {
    const GtkwView view =
        recorded_view(top.pes, rec.traced, sc_time::from_value(r.end), c, r.warnings);
    if (!opt.gtkw.empty()) write_gtkw(opt.gtkw, vcd_file(opt.vcd), rec.wave->signals(), view);
  }
  if (!logs.empty()) {
    std::ostringstream text;
    write_event_log(text, logs, top.pes[0]->ctx.cycle);
    write_text_atomically(opt.event_log, text.str());
  }
}

}  // namespace

std::string vcd_file(const std::string& vcd) {
  return vcd.size() > 4 && vcd.substr(vcd.size() - 4) == ".vcd" ? vcd : vcd + ".vcd";
}

MachineResult run_machine(const Scene& s, const Grid& g, const MachineConfig& c,
                          const MachineOptions& opt) {
  c.validate();
  // The kernel's informational notes (the machine stopping itself when the frame is gathered,
  // the trace file's time unit) are not news to the user.
  sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  const auto t0 = std::chrono::steady_clock::now();
  check_threads_fit(expected_threads(c, !opt.vcd.empty()),
                    c);  // before the seconds elaboration takes
  // What the host hands the PEs, in the frame they compute in (its cost is the host's: host.cpp).
  const FramedScene pe_view = framed(s, g, c.pe_frame);
  Machine top("machine", pe_view.scene, pe_view.grid, c, opt.progress && isatty(2),
              !opt.vcd.empty(), opt.max_memory, opt.max_rays, opt.pool, opt.sim_threads);

  check_threads_fit(Machine::threads(sc_core::sc_get_top_level_objects()), c);

  std::vector<EventLog> logs(opt.event_log.empty() ? 0 : size_t(c.pes));
  for (size_t pe = 0; pe < logs.size(); ++pe) top.pes[pe]->ctx.log = &logs[pe];
  Recording rec = start_waveform(top, c, opt);

  top.run();
  if ((top.progress_display && top.progress_display->drew())) std::fprintf(stderr, "\r%80s\r", "");

  // The budget stop is thrown here, in run_machine's own frame: thrown from a helper, the
  // address-sanitized build reported a stack-buffer-overflow inside AddressSanitizer's own
  // sigaltstack interceptor while unwinding (the Reliability budget tests), not in rtm's code.
  if (const std::string why = budget_stop(top, s, c, opt); !why.empty()) throw BudgetExceeded(why);
  check_finished(top, c);
  MachineResult r = collect_result(top, c);
  if (c.voxelisation == MachineConfig::Voxelisation::Pe) {
    r.voxel_primitives = uint64_t(pe_view.scene.primitives.size()) * uint64_t(c.pes);
    r.voxel_references = uint64_t(pe_view.grid.items.size()) * uint64_t(c.pes);
  }
  write_recordings(top, rec, logs, r, c, opt);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rtm
