#include "machine/intersection_module.h"

namespace rtm {

IntersectionModule::IntersectionModule(sc_core::sc_module_name name, PeContext& ctx,
                                       sc_core::sc_clock* clock, Dispatcher& dispatcher, int lane)
    : UnitModule(name, ctx, {UnitKind::Mac, UnitKind::Root}),
      mac_(ctx, lane),
      root_(ctx, lane),
      mac_sleep_(ctx.sleeper(UnitKind::Mac)),
      root_sleep_(ctx.sleeper(UnitKind::Root, lane)),
      dispatcher_(dispatcher),
      root_fifo_(fifo_spec(FifoId::Root).name, ctx.config.*fifo_spec(FifoId::Root).depth,
                 fifo_spec(FifoId::Root).kind),
      mac_pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::Mac, lane)),
      root_pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::Root, lane)) {
  if (clock) {
    clocked_ = std::make_unique<ClockedMac>(
        "mac", mac_.timing(), ctx.config.intersection_precision_in_force(), ctx.period);
    clocked_->clk(*clock);
  }
  SC_THREAD(mac_thread);
  SC_THREAD(root_thread);
}

struct IntersectionModule::MacOps {
  IntersectionModule& x;
  bool checked = false;  ///< the head job's clocked sums were checked

  void woke(uint64_t) { x.dispatcher_.woke(x.mac_.lane()); }
  bool write_head(uint64_t) {
    Held& h = x.mac_pipe_.head().item;
    if (x.clocked_ && !checked) {
      // The clocked unit has put the job's last sums out half a cycle before the stage takes them.
      // The fast model must predict the clocked MAC's sums bit for bit and its cycles exactly;
      // anything else is a model bug. The clocked sums are then the ones the root unit takes.
      ClockedMac::Done done;
      const bool ran = x.clocked_->finish(done);
      const std::string differs =
          check_clocked(h.m, x.ctx_.image->mem32.has_value(), done, x.job_cycles_.front(), ran);
      if (!differs.empty()) SC_REPORT_FATAL("rtm/pe/mac", differs.c_str());
      x.job_cycles_.pop_front();
      checked = true;
    }
    const bool full = x.root_fifo_.num_free() == 0;
    if (x.clocked_) x.clocked_->stall(full);  // a result that cannot leave holds the whole MAC
    if (full) return false;
    x.root_fifo_.write(h.m);
    record_put(x.ctx_, x.ctx_.put_time(), UnitKind::Mac, x.mac_.lane(), h.m.r, h.out);
    return true;
  }
  void retired(const Held&) {
    checked = false;
    if (x.mac_pipe_.empty()) x.mac_probe_.end();
  }
  bool accept(uint64_t now) {
    Held h;
    if (!x.rays_in(FifoId::Intersect)->nb_read(h.m.r)) return false;
    x.mac_probe_.begin(h.m.r.id);
    Work w = x.mac_.take(h.m, now);
    h.out = w.out;
    if (x.clocked_) {
      x.clocked_->start(mac_job(*x.ctx_.image, h.m.r, h.m.plan));
      x.job_cycles_.push_back(w.cycles);
    }
    x.mac_pipe_.accept(h, now, w.cycles, w.interval, std::move(w.wait));
    return true;
  }
  bool wait_for_input() {
    x.dispatcher_.wait(x.mac_.lane());
    return true;
  }
  void want(uint64_t t) { x.mac_sleep_->want(t); }
};

void IntersectionModule::mac_thread() {
  MacOps ops{*this, false};
  const sc_core::sc_event_or_list either = dispatcher_.event(mac_.lane()) | mac_sleep_->event();
  run_unit(mac_pipe_, ops, *mac_sleep_, either);
}

struct IntersectionModule::RootOps {
  IntersectionModule& x;

  void woke(uint64_t) {}
  bool write_head(uint64_t) {
    const Held& h = x.root_pipe_.head().item;
    return x.try_write(h.out, h.m.r, UnitKind::Root, x.root_.lane());
  }
  void retired(const Held&) {
    if (x.root_pipe_.empty()) x.root_probe_.end();
  }
  bool accept(uint64_t now) {
    Held h;
    if (!x.root_fifo_.nb_read(h.m)) return false;
    x.root_probe_.begin(h.m.r.id);
    Work w = x.root_.take(h.m, now);
    h.out = w.out;
    x.root_pipe_.accept(h, now, w.cycles, w.interval, std::move(w.wait));
    return true;
  }
  bool wait_for_input() { return true; }
  void want(uint64_t t) { x.root_sleep_->want(t); }
};

void IntersectionModule::root_thread() {
  RootOps ops{*this};
  const sc_core::sc_event_or_list either = root_fifo_.data_written_event() | root_sleep_->event();
  run_unit(root_pipe_, ops, *root_sleep_, either);
}

void IntersectionModule::trace(Waveform& wave) {
  const std::string scope = name();
  // The MAC's busy flag and ray are the unit's; in clocked timing its pipeline's registers join
  // them in the same scope (the clocked MAC is the module scope.mac).
  mac_probe_.trace(wave, scope + ".mac", &ctx_.window);
  root_probe_.trace(wave, scope + ".root", &ctx_.window);
  root_fifo_.trace(wave, std::string(root_fifo_.name()) + ".occupancy", &ctx_.window);
  if (clocked_) clocked_->trace(wave, clocked_->name(), &ctx_.window);
}

}  // namespace rtm
