#include "machine/intersection_module.h"

namespace rtm {

IntersectionModule::IntersectionModule(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock,
                                       Dispatcher& dispatcher, int lane)
    : UnitModule(name, ctx, {UnitKind::Mac, UnitKind::Root}),
      mac_(ctx, lane),
      root_(ctx, lane),
      mac_sleep_(ctx.sleeper(UnitKind::Mac)),
      root_sleep_(ctx.sleeper(UnitKind::Root, lane)),
      dispatcher_(dispatcher),
      root_fifo_(fifo_spec(FifoId::Root).name, ctx.config.*fifo_spec(FifoId::Root).depth, fifo_spec(FifoId::Root).kind),
      mac_pipe_(ctx.period.value()),
      root_pipe_(ctx.period.value()) {
  if (clock) {
    clocked_ = std::make_unique<ClockedMac>("mac_unit", mac_.timing(), ctx.config.precision, ctx.period);
    clocked_->clk(*clock);
  }
  SC_THREAD(mac_thread);
  SC_THREAD(root_thread);
}

namespace {

/// The clocked MAC's job: latches and RAM words in the machine's precision, held as doubles.
template <class Real>
MacJob make_job(const SceneMemory<Real>& mem, const MachineRay& r, int64_t voxel) {
  MacJob job;
  const Grid& g = *mem.grid;
  for (const uint32_t *it = g.begin(voxel), *end = it + g.count(voxel); it != end; ++it) {
    const Latches<Real> l = mem.latches(r.ray, *it, r.examined.t_enter);
    Latches<double> ld{};
    for (int i = 0; i < 7; ++i) ld[size_t(i)] = double(l[size_t(i)]);
    job.latches.push_back(ld);
    CoefRam<double> ram{};
    for (int w = 0; w < kRamWords; ++w) ram[size_t(w)] = double(mem.rams[*it][size_t(w)]);
    job.rams.push_back(ram);
    if (!mem.ops.empty()) job.ops.push_back(mem.ops[*it]);
  }
  job.ray_id = r.id;
  return job;
}

/// The clocked MAC must reproduce the schedule's sums bit for bit; anything else is a model bug.
template <class Real>
void check_clocked(const std::vector<Abg<Real>>& fast, const std::vector<std::array<double, 3>>& clocked,
                   uint64_t fast_cycles, uint64_t clocked_cycles) {
  bool same = fast.size() == clocked.size() && fast_cycles == clocked_cycles;
  for (size_t i = 0; same && i < fast.size(); ++i)
    same = double(fast[i].a) == clocked[i][0] && double(fast[i].b) == clocked[i][1] && double(fast[i].g) == clocked[i][2];
  if (!same)
    SC_REPORT_FATAL("rtm/pe/mac", ("clocked MAC disagrees with the fast MAC model: " + std::to_string(clocked_cycles) +
                                   " cycles against " + std::to_string(fast_cycles))
                                      .c_str());
}

}  // namespace

struct IntersectionModule::MacOps {
  IntersectionModule& x;
  bool waiting = false;
  sc_core::sc_event_or_list either;
  bool checked = false;  ///< the head job's clocked sums were checked

  void woke(uint64_t) { x.dispatcher_.woke(x.mac_.lane()); }
  bool write_head(uint64_t) {
    Held& h = x.mac_pipe_.head().item;
    if (x.clocked_ && !checked) {
      // The clocked unit has put its last sums out half a cycle before the stage takes them.
      const uint64_t ran = x.clocked_->finish();
      if (x.ctx_.image->mem32)
        check_clocked(h.m.abg32, x.sums_, x.job_cycles_, ran);
      else
        check_clocked(h.m.abg64, x.sums_, x.job_cycles_, ran);
      checked = true;
    }
    if (x.root_fifo_.num_free() == 0) return false;
    x.root_fifo_.write(h.m);
    record_put(x.ctx_, x.ctx_.log_time(), UnitKind::Mac, x.mac_.lane(), h.m.r.id, h.out);
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
    const Work w = x.mac_.take(h.m, x.ctx_.log_time());
    h.out = w.out;
    if (x.clocked_) {
      const SceneImage& img = *x.ctx_.image;
      const DdaState& s = h.m.r.examined;
      const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
      x.job_ = img.visit([&](const auto& mem) { return make_job(mem, h.m.r, v); });
      x.clocked_->start(x.job_, x.sums_);
      x.job_cycles_ = w.cycles;
    }
    x.mac_pipe_.accept(h, now, x.ctx_.period.value() * w.cycles, x.ctx_.period.value() * w.interval);
    return true;
  }
  void wait_for_input() {
    waiting = true;
    x.dispatcher_.wait(x.mac_.lane());
  }
  void want(uint64_t t) { x.mac_sleep_->want(t); }
};

void IntersectionModule::mac_thread() {
  MacOps ops{*this, false, {}, false};
  ops.either = dispatcher_.event(mac_.lane()) | mac_sleep_->event();
  run_unit(mac_pipe_, ops, *mac_sleep_);
}

struct IntersectionModule::RootOps {
  IntersectionModule& x;
  bool waiting = false;
  sc_core::sc_event_or_list either;

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
    const Work w = x.root_.take(h.m, x.ctx_.log_time());
    h.out = w.out;
    x.root_pipe_.accept(h, now, x.ctx_.period.value() * w.cycles, x.ctx_.period.value() * w.interval);
    return true;
  }
  void wait_for_input() { waiting = true; }
  void want(uint64_t t) { x.root_sleep_->want(t); }
};

void IntersectionModule::root_thread() {
  RootOps ops{*this, false, {}};
  ops.either = root_fifo_.data_written_event() | root_sleep_->event();
  run_unit(root_pipe_, ops, *root_sleep_);
}

void IntersectionModule::trace(Waveform& wave) {
  const std::string scope = name();
  mac_probe_.trace(wave, scope + ".mac", &ctx_.window);
  root_probe_.trace(wave, scope + ".root", &ctx_.window);
  root_fifo_.trace(wave, std::string(root_fifo_.name()) + ".occupancy", &ctx_.window);
  if (clocked_) clocked_->trace(wave, clocked_->name(), &ctx_.window);
}

}  // namespace rtm
