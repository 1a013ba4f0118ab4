#include "machine/search_module.h"

namespace rtm {

SearchModule::SearchModule(sc_core::sc_module_name name, PeContext& ctx, int index,
                           Dispatcher& dispatcher)
    : UnitModule(name, ctx, {UnitKind::Search}),
      unit_(ctx, index),
      sleep_(ctx.sleeper(UnitKind::Search)),
      dispatcher_(dispatcher),
      pipe_(ctx.period.value(), &ctx.counters.unit(UnitKind::Search, index)) {
  SC_THREAD(run);
}

struct SearchModule::Ops {
  SearchModule& m;

  void woke(uint64_t) { m.dispatcher_.woke(m.unit_.index()); }
  bool write_head(uint64_t) {
    const Held& h = m.pipe_.head().item;
    return m.try_write(h.out, h.r, UnitKind::Search, m.unit_.index());
  }
  void retired(const Held&) {
    if (m.pipe_.empty()) m.probe_.end();
  }
  bool accept(uint64_t now) {
    Held h;
    if (!m.rays_in(FifoId::Search)->nb_read(h.r)) return false;
    m.probe_.begin(h.r.id);
    Work w = m.unit_.take(h.r, now);
    h.out = w.out;
    m.pipe_.accept(h, now, w.cycles, w.interval, std::move(w.wait));
    return true;
  }
  bool wait_for_input() {
    m.dispatcher_.wait(m.unit_.index());
    return true;
  }
  void want(uint64_t t) { m.sleep_->want(t); }
};

void SearchModule::run() {
  Ops ops{*this};
  const sc_core::sc_event_or_list either = dispatcher_.event(unit_.index()) | sleep_->event();
  run_unit(pipe_, ops, *sleep_, either);
}

}  // namespace rtm
