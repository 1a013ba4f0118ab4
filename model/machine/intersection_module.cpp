#include "machine/intersection_module.h"

namespace rtm {

LaneDispatchModule::LaneDispatchModule(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int lanes)
    : sc_module(name), in_(in), lanes_(0) {
  for (int i = 0; i < lanes; ++i) wake_.push_back(std::make_unique<sc_core::sc_event>());
  SC_METHOD(dispatch);
  sensitive << in_.data_written_event();
  dont_initialize();
}

void LaneDispatchModule::wait_for_ray(int lane) {
  lanes_.idle(lane);
  sc_core::wait(*wake_[size_t(lane)]);
}

void LaneDispatchModule::dispatch() {
  // Immediate notifications: the units run next, in the order notified, and each takes one ray.
  for (int n = in_.num_available(); n > 0 && lanes_.any_idle(); --n) wake_[size_t(lanes_.take())]->notify();
}

IntersectionModule::IntersectionModule(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock,
                                       LaneDispatchModule* lanes, int lane)
    : UnitModule(name, ctx, {UnitKind::Mac, UnitKind::Root}),
      mac_(ctx, lane),
      root_(ctx, lane),
      mac_sleep_(ctx.sleeper(UnitKind::Mac)),
      root_sleep_(ctx.sleeper(UnitKind::Root, lane)),
      lanes_(lanes),
      root_fifo_(fifo_spec(FifoId::Root).name, ctx.config.*fifo_spec(FifoId::Root).depth, fifo_spec(FifoId::Root).kind) {
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

void IntersectionModule::mac_thread() {
  std::vector<std::array<double, 3>> sums;
  for (;;) {
    MacResult m;
    if (lanes_)
      while (!rays_in(FifoId::Intersect)->nb_read(m.r)) lanes_->wait_for_ray(mac_.lane());
    else
      m.r = rays_in(FifoId::Intersect)->read();
    mac_probe_.begin(m.r.id);
    const Work w = mac_.take(m, ctx_.log_time());
    if (clocked_) {
      const SceneImage& img = *ctx_.image;
      const DdaState& s = m.r.examined;
      const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
      const MacJob job = img.visit([&](const auto& mem) { return make_job(mem, m.r, v); });
      uint64_t ran;
      if (ctx_.keeper) {
        // Ranked order: the stage wakes exactly as in fast timing; the clocked unit has put
        // its last sums out half a cycle before.
        clocked_->start(job, sums);
        (*mac_sleep_)(ctx_.cycles(w.cycles));
        ran = clocked_->finish();
      } else {
        ran = clocked_->run(job, sums);
      }
      if (img.mem32)
        check_clocked(m.abg32, sums, w.cycles, ran);
      else
        check_clocked(m.abg64, sums, w.cycles, ran);
    } else {
      (*mac_sleep_)(ctx_.cycles(w.cycles));
    }
    mac_probe_.end();
    put(&root_fifo_, m, ctx_, *mac_sleep_);
    record_put(ctx_, ctx_.log_time(), UnitKind::Mac, mac_.lane(), m.r.id, w.out);
  }
}

void IntersectionModule::root_thread() {
  for (;;) {
    MacResult m = root_fifo_.read();
    root_probe_.begin(m.r.id);
    const Work w = root_.take(m, ctx_.log_time());
    (*root_sleep_)(ctx_.cycles(w.cycles));
    write(w.out, m.r, UnitKind::Root, root_.lane(), *root_sleep_);
    root_probe_.end();
  }
}

void IntersectionModule::trace(Waveform& wave) {
  const std::string scope = name();
  mac_probe_.trace(wave, scope + ".mac", &ctx_.window);
  root_probe_.trace(wave, scope + ".root", &ctx_.window);
  root_fifo_.trace(wave, std::string(root_fifo_.name()) + ".occupancy", &ctx_.window);
  if (clocked_) clocked_->trace(wave, clocked_->name(), &ctx_.window);
}

}  // namespace rtm
