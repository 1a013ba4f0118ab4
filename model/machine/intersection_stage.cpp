#include "machine/intersection_stage.h"


namespace rtm {

LaneDispatcher::LaneDispatcher(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int lanes)
    : sc_module(name), in_(in) {
  for (int i = 0; i < lanes; ++i) wake_.push_back(std::make_unique<sc_core::sc_event>());
  SC_METHOD(dispatch);
  sensitive << in_.data_written_event();
  dont_initialize();
}

void LaneDispatcher::wait_for_ray(int lane) {
  idle_.insert(lane);
  sc_core::wait(*wake_[size_t(lane)]);
}

void LaneDispatcher::dispatch() {
  // Immediate notifications: the units run next, in the order notified, and each takes one ray.
  for (int n = in_.num_available(); n > 0 && !idle_.empty(); --n) {
    const int lane = *idle_.begin();
    idle_.erase(idle_.begin());
    wake_[size_t(lane)]->notify();
  }
}

IntersectionStage::IntersectionStage(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock,
                                     LaneDispatcher* lanes, int lane)
    : sc_module(name),
      ctx_(ctx),
      mac_sleep_(ctx.sleeper(UnitRank::Mac)),
      root_sleep_(ctx.sleeper(UnitRank::Root, lane)),
      timing_(ctx.config),
      lanes_(lanes),
      lane_(lane),
      to_root_("to_root", ctx.config.root_fifo_depth, "root") {
  if (clock) {
    clocked_ = std::make_unique<ClockedMac>("mac_unit", timing_, ctx.config.precision, ctx.cycle);
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

void IntersectionStage::mac_thread() {
  std::vector<std::array<double, 3>> sums;
  for (;;) {
    MacResult m;
    if (lanes_)
      while (!rays_in->nb_read(m.r)) lanes_->wait_for_ray(lane_);
    else
      m.r = rays_in->read();
    mac_probe_.begin(m.r.id);
    const uint64_t cycles = mac_work(ctx_, timing_, m);
    if (clocked_) {
      const SceneImage& img = *ctx_.image;
      const DdaState& s = m.r.examined;
      const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
      const bool fp32 = ctx_.config.precision == Precision::Fp32;
      const MacJob job = fp32 ? make_job(img.mem32, m.r, v) : make_job(img.mem64, m.r, v);
      uint64_t ran;
      if (ctx_.keeper) {
        // Ranked order: the stage wakes exactly as in fast timing; the clocked unit has put
        // its last sums out half a cycle before.
        clocked_->start(job, sums);
        (*mac_sleep_)(ctx_.cycles(cycles));
        ran = clocked_->finish();
      } else {
        ran = clocked_->run(job, sums);
      }
      if (fp32)
        check_clocked(m.abg32, sums, cycles, ran);
      else
        check_clocked(m.abg64, sums, cycles, ran);
    } else {
      (*mac_sleep_)(ctx_.cycles(cycles));
    }
    mac_probe_.end();
    put(&to_root_, m, ctx_, *mac_sleep_);
  }
}

void IntersectionStage::root_thread() {
  std::vector<uint32_t> clips;
  for (;;) {
    MacResult m = to_root_.read();
    root_probe_.begin(m.r.id);
    const Routed w = root_work(ctx_, m, clips);
    (*root_sleep_)(ctx_.cycles(w.cycles));
    switch (w.route) {
      case Route::Shade: put(hits_out, m.r, ctx_, *root_sleep_); break;
      case Route::Feedback: put(feedback_out, m.r, ctx_, *root_sleep_); break;
      case Route::End: put(ends_out, RayEnd{m.r.id}, ctx_, *root_sleep_); break;
      case Route::Intersect: break;  // not a route out of this stage
    }
    root_probe_.end();
  }
}

void IntersectionStage::trace(sc_core::sc_trace_file* tf, const std::string& prefix) {
  mac_probe_.trace(tf, prefix + ".mac", &ctx_.window);
  root_probe_.trace(tf, prefix + ".root", &ctx_.window);
  to_root_.trace(tf, prefix + ".to_root.occupancy", &ctx_.window);
  if (clocked_) clocked_->trace(tf, prefix + ".mac_unit", &ctx_.window);
}

}  // namespace rtm
