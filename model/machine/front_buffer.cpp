#include "machine/front_buffer.h"

#include "machine/unit_work.h"

namespace rtm {

FrontBuffer::FrontBuffer(sc_core::sc_module_name name, PeContext& ctx, LocalMemory& mem, sc_core::sc_event& finished)
    : sc_module(name),
      ctx_(ctx),
      sleep_(ctx.sleeper(UnitRank::FrontBuffer)),
      mem_(mem),
      credits_(ctx.config.loop_credits_in_force()),
      finished_event_(finished) {
  SC_THREAD(run);
}

void FrontBuffer::drain() {
  MachineRay r;
  RayEnd e;
  while (ends_in->nb_read(e)) --in_flight_;
  for (sc_core::sc_fifo_in<MachineRay>* in : {&from_search, &from_intersect}) {
    while ((*in)->nb_read(r)) {
      --in_flight_;
      queue_.push_back(r);
    }
  }
  // Spawned rays are new: their parent's credit came back through ends_in.
  if (from_shade.size())
    while (from_shade->nb_read(r)) queue_.push_back(r);
  if (ctx_.window.now()) traced_waiting_ = int(queue_.size());
}

void FrontBuffer::dispatch(MachineRay r, uint64_t cycles) {
  ++in_flight_;
  probe_.begin(r.id);
  ctx_.counters.front.busy_cycles += cycles;
  ++ctx_.counters.front.items;
  (*sleep_)(ctx_.cycles(cycles));
  put(rays_out, r, ctx_, *sleep_);  // with credits, never waits: in_flight <= credits <= the FIFO's depth
  probe_.end();
}

void FrontBuffer::run() {
  // Built once: constructing an event list on every wait costs allocations on the hottest path.
  inputs_ = from_search->data_written_event() | from_intersect->data_written_event() |
            ends_in->data_written_event() | mem_.rays_arrived;
  if (from_shade.size()) inputs_ |= from_shade->data_written_event();
  for (;;) {
    drain();
    if (in_flight_ < credits_) {
      if (!queue_.empty()) {
        // Rays beyond the on-chip capacity live in the spill area in local memory.
        const bool spilled = queue_.size() > size_t(ctx_.config.front_buffer_capacity);
        if (spilled) ++ctx_.counters.spills;
        MachineRay r = queue_.front();
        queue_.pop_front();
        dispatch(r, dispatch_cycles(ctx_.config, spilled, false));
        continue;
      }
      if (next_primary_ < mem_.rays.size()) {
        ctx_.align(*sleep_);
        if (next_primary_ == 0) ctx_.counters.start = sc_core::sc_time_stamp();
        dispatch(primary_ray(ctx_, mem_.rays, next_primary_++), dispatch_cycles(ctx_.config, false, true));
        continue;
      }
    }
    if (next_primary_ == mem_.rays_expected && queue_.empty() && in_flight_ == 0) {
      finished_ = true;
      ctx_.counters.finish = sc_core::sc_time_stamp();
      finished_event_.notify(sc_core::SC_ZERO_TIME);
      return;
    }
    const bool stalled = !queue_.empty() || next_primary_ < mem_.rays.size();  // only credits hold them back
    const sc_core::sc_time since = sc_core::sc_time_stamp();
    sc_core::wait(inputs_);
    if (stalled) ctx_.counters.credit_stall += sc_core::sc_time_stamp() - since;
  }
}

void FrontBuffer::trace(sc_core::sc_trace_file* tf, const std::string& prefix) {
  probe_.trace(tf, prefix, &ctx_.window);
  sc_core::sc_trace(tf, traced_waiting_, prefix + ".waiting");
}

}  // namespace rtm
