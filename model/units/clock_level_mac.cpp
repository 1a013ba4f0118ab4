#include "units/clock_level_mac.h"

#include <algorithm>
#include <stdexcept>

namespace rtm {

namespace {

template <class Real>
MacJob job_of(const SceneMemory<Real>& mem, const MachineRay& r, int64_t voxel) {
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

template <class Real>
bool same_sums(std::vector<Abg<Real>>& fast, const ClockLevelMac::Done& clocked) {
  if (fast.size() != clocked.sums.size()) return false;
  for (size_t i = 0; i < fast.size(); ++i)
    if (double(fast[i].a) != clocked.sums[i][0] || double(fast[i].b) != clocked.sums[i][1] ||
        double(fast[i].g) != clocked.sums[i][2])
      return false;
  for (size_t i = 0; i < fast.size(); ++i)
    fast[i] = {Real(clocked.sums[i][0]), Real(clocked.sums[i][1]), Real(clocked.sums[i][2])};
  return true;
}

}  // namespace

MacJob mac_job(const SceneImage& image, const MachineRay& r, const MacTiming::Job& plan) {
  const DdaState& s = r.examined;
  const int64_t v = image.grid->index(s.cell[0], s.cell[1], s.cell[2]);
  MacJob job = image.visit([&](const auto& mem) { return job_of(mem, r, v); });
  job.loads = plan.loads;
  return job;
}

std::string check_clocked(MacResult& fast, bool mem32, const ClockLevelMac::Done& clocked,
                          uint64_t fast_cycles, bool ran) {
  if (ran && fast_cycles == clocked.cycles &&
      (mem32 ? same_sums(fast.abg32, clocked) : same_sums(fast.abg64, clocked)))
    return "";
  return "the fast MAC model disagrees with the clocked MAC: " +
         (ran ? "clocked " + std::to_string(clocked.cycles) +
                    " cycles (or other sums) against fast " + std::to_string(fast_cycles)
              : "still running after the fast model's " + std::to_string(fast_cycles) + " cycles");
}

// ---- the clock-level MAC ----

ClockLevelMac::ClockLevelMac(const MacTiming& timing, Precision precision)
    : timing_(timing),
      precision_(precision),
      mul1_(timing.mul_latency),
      mul2_(timing.mul_latency),
      adder_(timing.add_latency) {}

bool ClockLevelMac::Delay::empty() const {
  return std::none_of(stages.begin(), stages.end(), [](const Stage& s) { return s.valid; });
}

void ClockLevelMac::start(MacJob job) {
  Posted p;
  std::vector<int> counts;
  for (size_t i = 0; i < job.rams.size(); ++i)
    counts.push_back(job.ops.empty() ? kMacProducts : int(job.ops[i].size()));
  p.plan = timing_.job(counts, job.loads);
  p.done.sums.assign(job.rams.size(), {0, 0, 0});
  p.job = std::move(job);
  p.start = tick_;  // the next edge runs cycle tick_
  jobs_.push_back(std::move(p));
}

bool ClockLevelMac::finish(Done& done) {
  if (jobs_.empty() || !jobs_.front().finished) return false;
  done = std::move(jobs_.front().done);
  jobs_.pop_front();
  ++first_serial_;
  return true;
}

bool ClockLevelMac::idle() const {
  if (!jobs_.empty() && !jobs_.back().finished) return false;
  return mul1_.empty() && mul2_.empty() && adder_.empty();
}

bool ClockLevelMac::edge(Registers* regs) {
  const Stage in = issue();
  if (regs && in.valid) {
    const MacOp& op = kMacSchedule[size_t(in.k)];
    const Latches<double>& l = job(in.job).job.latches[size_t(in.prim)];
    regs->m1_a = l[op.x];
    regs->m1_b = l[op.y];
  }
  Stage m1 = mul1_.shift(in);
  multiply_latches(m1);
  Stage m2 = mul2_.shift(m1);
  multiply_by_coefficient(m2);
  const Stage out = adder_.shift(m2);
  // The adder's output is the product that entered add_latency edges ago, so no job it belongs to
  // can have been handed on yet.
  const bool finished = accumulate(out, regs);
  ++tick_;
  if (regs) {
    regs->m1_valid = in.valid;
    if (m1.valid) {
      regs->m1_out = m1.value;
      regs->m2_coef = job(m1.job).job.rams[size_t(m1.prim)][kMacSchedule[size_t(m1.k)].w];
    }
    regs->m2_valid = m1.valid;
    if (m2.valid) regs->m2_out = m2.value;
    regs->add_valid = m2.valid;
  }
  return finished;
}

bool ClockLevelMac::accumulate(const Stage& out, Registers* regs) {
  if (regs) regs->accumulated = regs->sums_valid = false;
  if (!out.valid) return false;
  Posted& j = job(out.job);
  const MacOp& op = kMacSchedule[size_t(out.k)];
  sum_[op.sum] = round_to(precision_, sum_[op.sum] + out.value);
  ++accumulated_;
  if (regs) {
    regs->accumulated = true;
    regs->acc = sum_[op.sum];
    regs->abg_select = uint32_t(op.sum);
    regs->ray_id = j.job.ray_id;
    regs->prim = uint32_t(out.prim);
    regs->product_counter = accumulated_;
  }
  if (!out.last) return false;
  j.done.sums[size_t(out.prim)] = {sum_[0], sum_[1], sum_[2]};
  if (regs) {
    regs->sums_valid = true;
    regs->alpha = sum_[0], regs->beta = sum_[1], regs->gamma = sum_[2];
  }
  sum_[0] = sum_[1] = sum_[2] = 0;
  if (out.prim + 1 != int(j.done.sums.size())) return false;
  j.done.cycles = tick_ - j.start + 1;
  j.finished = true;
  accumulated_ = 0;
  return true;
}

void ClockLevelMac::multiply_by_coefficient(Stage& s) {
  if (s.valid)
    s.value = round_to(precision_,
                       s.value * job(s.job).job.rams[size_t(s.prim)][kMacSchedule[size_t(s.k)].w]);
}

void ClockLevelMac::multiply_latches(Stage& s) {
  if (!s.valid) return;
  const MacOp& op = kMacSchedule[size_t(s.k)];
  const Latches<double>& l = job(s.job).job.latches[size_t(s.prim)];
  s.value = round_to(precision_, l[op.x] * l[op.y]);
}

ClockLevelMac::Stage ClockLevelMac::issue() {
  // The next product when the schedule says so: the oldest job with products left.
  Stage in;
  for (size_t i = 0; i < jobs_.size(); ++i) {
    Posted& j = jobs_[i];
    const int prims = int(j.plan.counts.size());
    if (j.prim == prims) continue;
    if (tick_ == j.start + j.plan.issue(j.prim, j.j)) {
      in.valid = true;
      in.job = first_serial_ + i;
      in.prim = j.prim;
      in.k = j.job.ops.empty() ? j.j : j.job.ops[size_t(j.prim)][size_t(j.j)];
      in.last = j.j + 1 == j.plan.counts[size_t(j.prim)];
      if (in.last) {
        ++j.prim;
        j.j = 0;
      } else {
        ++j.j;
      }
    }
    break;
  }
  return in;
}

// ---- driven edge by edge ----

void EdgeByEdgeMac::run_before(uint64_t now) {
  // Units act at cycle boundaries (a primary ray waits for one, and every time after it is whole
  // cycles): between edges, so which comes first is never in doubt.
  if (now % period_)
    throw std::logic_error("the clocked MAC: an action at " + std::to_string(now) +
                           ", between cycle boundaries of " + std::to_string(period_));
  while (next_edge_ < now) {
    if (stalled_ || mac_.idle()) {
      // Nothing can change until the next action: on to the first edge after it.
      next_edge_ += (now - next_edge_ + period_ - 1) / period_ * period_;
      return;
    }
    mac_.edge();
    next_edge_ += period_;
  }
}

void EdgeByEdgeMac::start(uint64_t now, MacJob job, uint64_t fast_cycles) {
  run_before(now);
  mac_.start(std::move(job));
  fast_cycles_.push_back(fast_cycles);
}

std::string EdgeByEdgeMac::check(uint64_t now, MacResult& fast, bool mem32) {
  if (checked_) return "";
  run_before(now);
  ClockLevelMac::Done done;
  const bool ran = mac_.finish(done);
  checked_ = true;
  const uint64_t cycles = fast_cycles_.front();
  fast_cycles_.pop_front();
  return check_clocked(fast, mem32, done, cycles, ran);
}

void EdgeByEdgeMac::stall(uint64_t now, bool on) {
  run_before(now);
  stalled_ = on;
}

}  // namespace rtm
