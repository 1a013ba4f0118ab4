#include "machine/search_unit.h"

#include "machine/unit_work.h"

namespace rtm {

SearchUnit::SearchUnit(sc_core::sc_module_name name, PeContext& ctx)
    : sc_module(name), ctx_(ctx), sleep_(ctx.sleeper(UnitRank::Search)) {
  SC_THREAD(run);
}

void SearchUnit::run() {
  for (;;) {
    MachineRay r = rays_in->read();
    probe_.begin(r.id);
    const Routed w = search_work(ctx_, r);
    (*sleep_)(ctx_.cycles(w.cycles));
    switch (w.route) {
      case Route::Intersect: put(occupied_out, r, ctx_, *sleep_); break;
      case Route::Feedback: put(feedback_out, r, ctx_, *sleep_); break;
      case Route::Shade: put(shade_out, r, ctx_, *sleep_); break;
      case Route::End: put(ends_out, RayEnd{r.id}, ctx_, *sleep_); break;
    }
    probe_.end();
  }
}

}  // namespace rtm
