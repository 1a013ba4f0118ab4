#include "machine/front_buffer_module.h"

namespace rtm {

FrontBufferModule::FrontBufferModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem,
                                     sc_core::sc_event& finished)
    : UnitModule(name, ctx, {UnitKind::FrontBuffer}),
      sleep_(ctx.sleeper(UnitKind::FrontBuffer)),
      mem_(mem),
      policy_(ctx, mem.rays_expected),
      finished_event_(finished),
      pipe_(ctx.period.value(), &ctx.counters.front) {
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

void FrontBufferModule::dispatch(const MachineRay& r, uint64_t cycles, uint8_t from, uint64_t now) {
  policy_.dispatched(now, r.id, cycles, from);
  probe_.begin(r.id);
  pipe_.accept(r, now, ctx_.period.value() * cycles, ctx_.period.value() * policy_.interval(cycles));
}

bool FrontBufferModule::decide(uint64_t now) {
  using Next = FrontBufferPolicy<MachineRay>::Next;
  if (state_ == State::Aligning) {
    // The primary ray it decided on goes at the PE clock edge it asked to be woken at.
    if (now % ctx_.period.value()) return false;
    state_ = State::Deciding;
    uint64_t cycles = 0;
    const size_t i = policy_.pop_primary(now, cycles);
    if (i == 0) ctx_.window.pe_started(ctx_.pe);  // a window counted from this PE's start opens
    dispatch(primary_ray(ctx_, mem_.rays, i), cycles, kFromHost, now);
    return true;
  }
  if (state_ == State::Finished) return false;
  drain();
  switch (policy_.next()) {
    case Next::Queued: {
      uint64_t cycles = 0;
      bool spilled = false;
      const MachineRay r = policy_.pop_queued(cycles, spilled);
      dispatch(r, cycles, spilled ? kFromSpill : kFromQueue, now);
      return true;
    }
    case Next::Primary: {
      // Rays from the host arrive between PE clock edges.
      state_ = State::Aligning;
      const uint64_t c = ctx_.period.value();
      if (const uint64_t off = now % c) {
        sleep_->want(now + c - off);
        return false;
      }
      return decide(now);
    }
    case Next::Finished:
      policy_.finish(now);
      state_ = State::Finished;
      finished_event_.notify(sc_core::SC_ZERO_TIME);
      return false;
    case Next::Wait: return false;
  }
  return false;
}

struct FrontBufferModule::Ops {
  FrontBufferModule& m;
  bool waiting = false;
  sc_core::sc_event_or_list either;

  void woke(uint64_t now) {
    if (m.state_ != State::Waiting) return;
    m.policy_.woke(now);
    m.state_ = State::Deciding;
  }
  bool write_head(uint64_t) {
    // With credits, never full: in_flight <= credits <= the FIFO's depth.
    return m.try_write({FifoId::Search, Output::What::Item}, m.pipe_.head().item, UnitKind::FrontBuffer, 0);
  }
  void retired(const MachineRay&) {
    if (m.pipe_.empty()) m.probe_.end();
  }
  bool accept(uint64_t now) { return m.decide(now); }
  void wait_for_input() {
    if (m.state_ != State::Deciding) return;
    m.policy_.wait(PeContext::now());
    m.state_ = State::Waiting;
    waiting = true;
  }
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
