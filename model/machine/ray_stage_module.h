// A ray stage's unit as a module (units/ray_stage.h: the object-search units of paper §4, and any
// kind a build adds as one): takes rays from its kind's one input FIFO (the dispatcher wakes the
// lowest-numbered waiting unit of the kind) and runs its unit on each, several in flight when
// pipelined.
#pragma once

#include <string>

#include <systemc>

#include "machine/unit_module.h"
#include "units/ray_stage.h"

namespace rtm {

template <UnitKind K>
class RayStageModule : public UnitModule {
 public:
  SC_HAS_PROCESS(RayStageModule);
  RayStageModule(sc_core::sc_module_name name, PeContext& ctx, int index, Dispatcher& dispatcher)
      : UnitModule(name, ctx, {K}),
        unit_(ctx, index),
        index_(index),
        input_(inputs(K).front()),
        sleep_(ctx.sleeper(K)),
        dispatcher_(dispatcher),
        pipe_(ctx.period.value(), &ctx.counters.unit(K, index)) {
    SC_THREAD(run);
  }
  void trace(Waveform& wave) override { probe_.trace(wave, name(), &ctx_.window); }

 private:
  struct Held {
    MachineRay r;
    Output out;
  };

  struct Ops {
    RayStageModule& m;

    void woke(uint64_t) { m.dispatcher_.woke(m.index_); }
    bool write_head(uint64_t) {
      const Held& h = m.pipe_.head().item;
      return m.try_write(h.out, h.r, K, m.index_);
    }
    void retired(const Held&) {
      if (m.pipe_.empty()) m.probe_.end();
    }
    bool accept(uint64_t now) {
      Held h;
      if (!m.rays_in(m.input_)->nb_read(h.r)) return false;
      m.probe_.begin(h.r.id);
      Work w = m.unit_.take(h.r, now);
      h.out = w.out;
      m.pipe_.accept(h, now, w.cycles, w.interval, std::move(w.wait));
      return true;
    }
    bool wait_for_input() {
      m.dispatcher_.wait(m.index_);
      return true;
    }
    void want(uint64_t t) { m.sleep_->want(t); }
  };

  void run() {
    Ops ops{*this};
    const sc_core::sc_event_or_list either = dispatcher_.event(index_) | sleep_->event();
    run_unit(pipe_, ops, *sleep_, either);
  }

  typename RayStage<K>::Unit unit_;
  int index_;
  FifoId input_;
  std::unique_ptr<Sleeper> sleep_;
  Dispatcher& dispatcher_;
  Pipeline<Held> pipe_;
  UnitProbe probe_;
};

}  // namespace rtm
