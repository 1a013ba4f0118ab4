#include "machine/front_buffer_module.h"

namespace rtm {

FrontBufferModule::FrontBufferModule(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem,
                                     sc_core::sc_event& finished)
    : UnitModule(name, ctx, {UnitKind::FrontBuffer}),
      sleep_(ctx.sleeper(UnitKind::FrontBuffer)),
      mem_(mem),
      policy_(ctx, mem.rays_expected),
      finished_event_(finished) {
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

void FrontBufferModule::send(const MachineRay& r, uint64_t cycles, uint8_t from) {
  policy_.dispatched(PeContext::now(), r.id, cycles, from);
  probe_.begin(r.id);
  (*sleep_)(ctx_.cycles(cycles));
  // With credits, never waits: in_flight <= credits <= the FIFO's depth.
  write({FifoId::Search, Output::What::Item}, r, UnitKind::FrontBuffer, 0, *sleep_);
  probe_.end();
}

void FrontBufferModule::run() {
  // Built once: constructing an event list on every wait costs allocations on the hottest path.
  inputs_ = ends_in()->data_written_event() | mem_.rays_arrived;
  for (const FifoSpec& f : fifo_table())
    if (f.payload == Payload::Ray && has_input(f.id)) inputs_ |= rays_in(f.id)->data_written_event();
  using Next = FrontBufferPolicy<MachineRay>::Next;
  for (;;) {
    drain();
    switch (policy_.next()) {
      case Next::Queued: {
        uint64_t cycles = 0;
        bool spilled = false;
        const MachineRay r = policy_.pop_queued(cycles, spilled);
        send(r, cycles, spilled ? kFromSpill : kFromQueue);
        break;
      }
      case Next::Primary: {
        ctx_.align(*sleep_);
        uint64_t cycles = 0;
        const size_t i = policy_.pop_primary(PeContext::now(), cycles);
        if (i == 0) ctx_.window.pe_started(ctx_.pe);  // a window counted from this PE's start opens
        send(primary_ray(ctx_, mem_.rays, i), cycles, kFromHost);
        break;
      }
      case Next::Finished:
        policy_.finish(PeContext::now());
        finished_event_.notify(sc_core::SC_ZERO_TIME);
        return;
      case Next::Wait:
        policy_.wait(PeContext::now());
        sc_core::wait(inputs_);
        policy_.woke(PeContext::now());
        break;
    }
  }
}

void FrontBufferModule::trace(Waveform& wave) {
  const std::string scope = name();
  probe_.trace(wave, scope, &ctx_.window);
  wave.trace(traced_waiting_, scope + ".waiting");
}

}  // namespace rtm
