#include "machine/front_buffer_module.h"

namespace rtm {

FrontBufferModule::FrontBufferModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem,
                                     sc_core::sc_event& finished)
    : UnitModule(name, ctx, {UnitKind::FrontBuffer}),
      sleep_(ctx.sleeper(UnitKind::FrontBuffer)),
      mem_(mem),
      policy_(ctx, mem.rays_expected),
      finished_event_(finished),
      pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::FrontBuffer, 0)) {
  SC_THREAD(run);
}

/// The front buffer's operations for FrontBufferPolicy::carry_out.
struct FrontBufferModule::FrontOps {
  FrontBufferModule& m;
  uint64_t now;

  bool read_end() {
    RayEnd e;
    return m.ends_in()->nb_read(e);
  }
  bool read(FifoId id, MachineRay& r) { return m.rays_in(id)->nb_read(r); }
  void drained() {
    m.policy_.primaries_arrived(m.mem_.rays.size(), m.mem_.rays_expected);
    if (m.ctx_.window.now()) m.traced_waiting_ = int(m.policy_.waiting());
  }
  MachineRay primary(size_t n) {
    if (n == 0) m.ctx_.window.pe_started(m.ctx_.pe);  // a window counted from this PE's start opens
    return primary_ray(m.ctx_, m.mem_.rays, n);
  }
  void dispatch(MachineRay&& r, uint64_t cycles, uint8_t from, MemoryWait&& wait) {
    m.policy_.dispatched(now, r.id, cycles, from);
    m.probe_.begin(r.id);
    m.pipe_.accept(r, now, cycles, m.policy_.interval(cycles), std::move(wait));
  }
  void want(uint64_t t) { m.sleep_->want(t); }
  void finished() { m.finished_event_.notify(sc_core::SC_ZERO_TIME); }
  void ask_for_tile() { m.mem_.ask_for_tile(); }
  void frame_ended() { m.mem_.frame_ended(); }
};

struct FrontBufferModule::Ops {
  FrontBufferModule& m;

  void woke(uint64_t now) { m.policy_.woke(now); }
  bool write_head(uint64_t) {
    // With credits, never full: in_flight <= credits <= the FIFO's depth.
    return m.try_write({FifoId::Search, Output::What::Item}, m.pipe_.head().item,
                       UnitKind::FrontBuffer, 0);
  }
  void retired(const MachineRay&) {
    if (m.pipe_.empty()) m.probe_.end();
  }
  bool accept(uint64_t now) {
    FrontOps ops{m, now};
    return m.policy_.carry_out(now, m.ctx_.period.value(), ops);
  }
  bool wait_for_input() { return m.policy_.wait(PeContext::now()); }
  void want(uint64_t t) { m.sleep_->want(t); }
};

void FrontBufferModule::run() {
  Ops ops{*this};
  // Built once: constructing an event list on every wait costs allocations on the hottest path.
  sc_core::sc_event_or_list either =
      ends_in()->data_written_event() | mem_.rays_arrived | sleep_->event();
  for (const FifoSpec& f : fifo_table())
    if (f.payload == Payload::Ray && has_input(f.id)) either |= rays_in(f.id)->data_written_event();
  run_unit(pipe_, ops, *sleep_, either);
}

void FrontBufferModule::trace(Waveform& wave) {
  const std::string scope = name();
  probe_.trace(wave, scope, &ctx_.window);
  wave.trace(traced_waiting_, scope + ".waiting");
}

}  // namespace rtm
