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

void FrontBufferModule::drain() {
  RayEnd e;
  while (ends_in()->nb_read(e)) policy_.ended();
  MachineRay r;
  for (const FifoSpec& f : fifo_table()) {
    if (f.payload != Payload::Ray || !has_input(f.id)) continue;
    while (rays_in(f.id)->nb_read(r)) f.returns_credit ? policy_.returned(r) : policy_.spawned(r);
  }
  policy_.primaries_arrived(mem_.rays.size());
  if (ctx_.window.now()) traced_waiting_ = int(policy_.waiting());
}

void FrontBufferModule::dispatch(const MachineRay& r, uint64_t cycles, uint8_t from, uint64_t now, MemoryWait&& wait) {
  policy_.dispatched(now, r.id, cycles, from);
  probe_.begin(r.id);
  pipe_.accept(r, now, cycles, policy_.interval(cycles), std::move(wait));
}

bool FrontBufferModule::decide(uint64_t now) {
  auto d = policy_.decide(now, ctx_.period.value(), [&] { drain(); });
  using D = FrontBufferPolicy<MachineRay>::Decision;
  switch (d.kind) {
    case D::Queued: dispatch(d.queued, d.cycles, d.from, now, std::move(d.wait)); return true;
    case D::Primary:
      if (d.primary == 0) ctx_.window.pe_started(ctx_.pe);  // a window counted from this PE's start opens
      dispatch(primary_ray(ctx_, mem_.rays, d.primary), d.cycles, d.from, now, std::move(d.wait));
      return true;
    case D::Align: sleep_->want(d.at); return false;
    case D::None:
      if (policy_.finished() && !finish_told_) {
        finish_told_ = true;
        finished_event_.notify(sc_core::SC_ZERO_TIME);
      }
      return false;
  }
  return false;
}

struct FrontBufferModule::Ops {
  FrontBufferModule& m;
  bool waiting = false;
  sc_core::sc_event_or_list either;

  void woke(uint64_t now) { m.policy_.woke(now); }
  bool write_head(uint64_t) {
    // With credits, never full: in_flight <= credits <= the FIFO's depth.
    return m.try_write({FifoId::Search, Output::What::Item}, m.pipe_.head().item, UnitKind::FrontBuffer, 0);
  }
  void retired(const MachineRay&) {
    if (m.pipe_.empty()) m.probe_.end();
  }
  bool accept(uint64_t now) { return m.decide(now); }
  void wait_for_input() { waiting = m.policy_.wait(PeContext::now()); }
  void want(uint64_t t) { m.sleep_->want(t); }
};

void FrontBufferModule::run() {
  Ops ops{*this, false, {}};
  // Built once: constructing an event list on every wait costs allocations on the hottest path.
  ops.either = ends_in()->data_written_event() | mem_.rays_arrived | sleep_->event();
  for (const FifoSpec& f : fifo_table())
    if (f.payload == Payload::Ray && has_input(f.id)) ops.either |= rays_in(f.id)->data_written_event();
  run_unit(pipe_, ops, *sleep_);
}

void FrontBufferModule::trace(Waveform& wave) {
  const std::string scope = name();
  probe_.trace(wave, scope, &ctx_.window);
  wave.trace(traced_waiting_, scope + ".waiting");
}

}  // namespace rtm
