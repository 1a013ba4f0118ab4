#include "machine/search_module.h"

namespace rtm {

SearchModule::SearchModule(sc_core::sc_module_name name, PeContext& ctx, int index)
    : UnitModule(name, ctx, {UnitKind::Search}), unit_(ctx, index), sleep_(ctx.sleeper(UnitKind::Search)) {
  SC_THREAD(run);
}

void SearchModule::run() {
  for (;;) {
    MachineRay r = rays_in(FifoId::Search)->read();
    probe_.begin(r.id);
    const Work w = unit_.take(r, ctx_.log_time());
    (*sleep_)(ctx_.cycles(w.cycles));
    write(w.out, r, UnitKind::Search, unit_.index(), *sleep_);
    probe_.end();
  }
}

}  // namespace rtm
