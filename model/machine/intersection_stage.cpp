#include "machine/intersection_stage.h"

#include "machine/routing.h"

namespace rtm {

uint64_t back_end_cycles(const MachineConfig& c, const MacTiming::Job& mac, const std::vector<uint32_t>& clips) {
  uint64_t unit_free = 0;
  for (size_t p = 0; p < clips.size(); ++p) {
    const uint64_t ready = mac.done(int(p)) + 1 + uint64_t(c.root_cycles());
    unit_free = std::max(unit_free, ready) + clips[p] * uint64_t(c.clip_cycles) + uint64_t(c.sort_cycles);
  }
  return unit_free - mac.cycles();
}

IntersectionStage::IntersectionStage(sc_core::sc_module_name name, PeContext& ctx, sc_core::sc_clock* clock)
    : sc_module(name),
      ctx_(ctx),
      mac_sleep_(ctx.sleeper()),
      root_sleep_(ctx.sleeper()),
      timing_(ctx.config),
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
    m.r = rays_in->read();
    mac_probe_.begin(m.r.id);
    const SceneImage& img = *ctx_.image;
    const DdaState& s = m.r.examined;
    const int64_t v = img.grid->index(s.cell[0], s.cell[1], s.cell[2]);
    const int n = int(img.grid->count(v));
    const bool fp32 = ctx_.config.precision == Precision::Fp32;
    if (fp32)
      form_voxel_abg(img.mem32, m.r.ray, v, m.abg32, s.t_enter);
    else
      form_voxel_abg(img.mem64, m.r.ray, v, m.abg64, s.t_enter);
    std::vector<int> counts;
    int products = 0;
    for (const uint32_t *it = img.grid->begin(v), *end = it + n; it != end; ++it) {
      counts.push_back(fp32 ? img.mem32.products(*it) : img.mem64.products(*it));
      products += counts.back();
    }
    m.plan = timing_.job(counts);
    const uint64_t cycles = m.plan.cycles();
    if (clocked_) {
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
    ctx_.counters.mac_products += uint64_t(products);
    ctx_.counters.mac_products_saved += uint64_t(n) * kMacProducts - uint64_t(products);
    ctx_.counters.mac_cycles_saved += timing_.job_cycles(n) - cycles;
    ctx_.counters.mac.busy_cycles += cycles;
    ++ctx_.counters.mac.items;
    mac_probe_.end();
    to_root_.write(m);  // never blocks: see FrontBuffer
  }
}

void IntersectionStage::root_thread() {
  std::vector<uint32_t> clips;
  for (;;) {
    MacResult m = to_root_.read();
    MachineRay& r = m.r;
    root_probe_.begin(r.id);
    const SceneImage& img = *ctx_.image;
    const int64_t v = img.grid->index(r.examined.cell[0], r.examined.cell[1], r.examined.cell[2]);
    const VoxelHit h = ctx_.config.precision == Precision::Fp32
                           ? resolve_voxel(img.mem32, r.ray, r.examined, v, m.abg32.data(), &clips)
                           : resolve_voxel(img.mem64, r.ray, r.examined, v, m.abg64.data(), &clips);
    ctx_.counters.counts.intersection_tests += h.tests;
    ctx_.counters.counts.clip_tests += h.clip_tests;
    const uint64_t cycles = back_end_cycles(ctx_.config, m.plan, clips);
    ctx_.counters.root.busy_cycles += cycles;
    ++ctx_.counters.root.items;
    (*root_sleep_)(ctx_.cycles(cycles));

    switch (intersection_route(*img.scene, r, h)) {
      case Route::Shade: hits_out->write(r); break;
      case Route::Feedback: feedback_out->write(r); break;
      case Route::End: ends_out->write(RayEnd{r.id}); break;
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
