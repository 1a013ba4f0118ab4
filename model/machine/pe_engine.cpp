#include "machine/pe_engine.h"

#include <algorithm>
#include <sstream>

namespace rtm {

std::string engine_unsupported(const MachineConfig& c, bool tracing) {
  if (c.pe_simulation == MachineConfig::PeSimulation::Modules) return "pe_simulation = modules";
  if (c.timing != Timing::Fast) return "clocked timing runs the MAC on a clock";
  if (c.arbitration != MachineConfig::Arbitration::Ranked)
    return "arbitration = kernel leaves the same-cycle order to SystemC";
  if (c.flow_control != FlowControl::Credits) return "flow_control = none can deadlock, which the modules report";
  if (c.dda_step_cycles == 0 || c.shade_cycles == 0 || c.accumulate_cycles == 0)
    return "a unit taking zero cycles acts within the instant it started";
  if (tracing) return "a waveform traces the modules' signals";
  return "";
}

PeEngine::Fifo::Fifo(std::string n, const char* kind, int depth, std::vector<Fifo*>* touched)
    : name(std::move(n)), ring(size_t(depth)), meter(kind, depth), touched_list(touched) {}

PeEngine::PeEngine(PeContext& ctx, std::vector<PixelSum>& frame, std::vector<int32_t>& ids,
                   const std::vector<Ray>& rays, size_t rays_expected)
    : ctx_(ctx),
      frame_(frame),
      ids_(ids),
      rays_(rays),
      rays_expected_(rays_expected),
      cycle_(ctx.cycle.value()),
      credits_(ctx.config.loop_credits_in_force()),
      timing_(ctx.config),
      search_fifo_("search_fifo", "search", ctx.config.search_fifo_depth, &touched_),
      intersect_fifo_("intersect_fifo", "intersect", ctx.config.intersect_fifo_depth, &touched_),
      shade_fifo_("shade_fifo", "shade", ctx.config.shade_fifo_depth, &touched_),
      feedback_search_("feedback_search", "feedback", ctx.config.feedback_fifo_depth, &touched_),
      feedback_intersect_("feedback_intersect", "feedback", ctx.config.feedback_fifo_depth, &touched_),
      spawn_fifo_("spawn_fifo", "spawn", ctx.config.feedback_fifo_depth, &touched_),
      ends_fifo_("ends_fifo", "ends", ctx.config.feedback_fifo_depth, &touched_),
      spawn_path_(ctx.units.spawn_path),
      lanes_(size_t(ctx.config.intersection_units)),
      mac0_(kSearch + size_t(ctx.config.search_units)),
      root0_(mac0_ + lanes_) {
  due_at_.assign(root0_ + lanes_, kNever);
  due_.resize(due_at_.size());
  for (size_t u = mac0_; u-- > kSearch;) idle_search_.push_back(u);
  for (size_t lane = 0; lane < lanes_; ++lane) {
    idle_macs_.insert(lane);
    to_root_.emplace_back("to_root", "root", ctx.config.root_fifo_depth, &touched_);
  }
  fifos_ = {&search_fifo_, &intersect_fifo_, &shade_fifo_, &feedback_search_, &feedback_intersect_};
  if (spawn_path_) fifos_.push_back(&spawn_fifo_);
  for (Fifo& f : to_root_) fifos_.push_back(&f);
  fifos_.push_back(&ends_fifo_);
  front_loop(0);
}

// ---- the event loop ----

uint64_t PeEngine::next_instant() {
  uint64_t next = pending_step_;
  due_now_.clear();
  for (size_t u = 0; u < due_at_.size(); ++u) {
    const uint64_t at = due_at_[u];
    if (at > next) continue;
    if (at < next) {
      next = at;
      due_now_.clear();
    }
    if (at != kNever) due_now_.push_back(u);
  }
  return next;
}

bool PeEngine::idle() const {
  return pending_step_ == kNever &&
         std::all_of(due_at_.begin(), due_at_.end(), [](uint64_t at) { return at == kNever; });
}

void PeEngine::run_before(uint64_t t) {
  for (uint64_t next; (next = next_instant()) < t;) step(next);
}

void PeEngine::rays_arrived(uint64_t t, size_t n) {
  rays_visible_ = n;
  front_poked_ = true;
  pending_step_ = t;
}

void PeEngine::schedule(size_t unit, uint64_t at, uint32_t item, Route route) {
  // Root units go by their lane: each takes only its own MAC's results, and the modules rank
  // them so (pe_context.h).
  const Unit kind = unit_at(unit);
  const uint64_t rank = uint64_t(kind) + (kind == Unit::Root ? unit - root0_ : 0);
  due_at_[unit] = at;
  due_[unit] = {rank << 48 | seq_++, item, route};
}

void PeEngine::step(uint64_t now) {
  if (pending_step_ == now) pending_step_ = kNever;
  // The units whose work ends now (found by next_instant), in rank order; their next work ends later.
  for (size_t i = 1; i < due_now_.size(); ++i)  // a few at most: insertion sort
    for (size_t j = i; j > 0 && due_[due_now_[j]].order < due_[due_now_[j - 1]].order; --j)
      std::swap(due_now_[j], due_now_[j - 1]);
  for (size_t u : due_now_) {
    const Due d = due_[u];
    due_at_[u] = kNever;
    wake(u, d, now);
  }
  // What they wrote becomes visible.
  const bool poked = front_poked_ || feedback_search_.written || feedback_intersect_.written || spawn_fifo_.written ||
                     ends_fifo_.written;
  front_poked_ = false;
  for (Fifo* f : touched_) {
    f->visible = f->count;
    f->written = false;
    f->reads_now = 0;
  }
  // Idle units take it, and the front buffer drains its inputs if it was waiting.
  take_inputs(now);
  if (front_ == Front::Waiting && poked) {
    if (stalled_) ctx_.counters.credit_stall += sc_core::sc_time::from_value(now - waiting_since_);
    front_loop(now);
  }
  // Places freed by reads are there for the next instant's writers.
  for (Fifo* f : touched_) {
    f->reads_now = 0;
    f->touched = false;
  }
  touched_.clear();
}

void PeEngine::take_inputs(uint64_t now) {
  while (!idle_search_.empty() && search_fifo_.visible > 0) {
    const size_t u = idle_search_.back();
    idle_search_.pop_back();
    search_start(u, search_fifo_.read(now), now);
  }
  while (!idle_macs_.empty() && intersect_fifo_.visible > 0) {
    const size_t lane = *idle_macs_.begin();
    idle_macs_.erase(idle_macs_.begin());
    mac_start(lane, intersect_fifo_.read(now), now);
  }
  // A unit with nothing due is idle.
  for (size_t lane = 0; lane < lanes_; ++lane)
    if (due_at_[root0_ + lane] == kNever && to_root_[lane].visible > 0)
      root_start(lane, to_root_[lane].read(now), now);
  if (due_at_[kShading] == kNever && shade_fifo_.visible > 0) shade_start(shade_fifo_.read(now), now);
}

// ---- rays ----

uint32_t PeEngine::new_ray(const MachineRay& r) {
  if (free_slots_.empty()) {
    slots_.push_back(r);
    return uint32_t(slots_.size() - 1);
  }
  const uint32_t s = free_slots_.back();
  free_slots_.pop_back();
  slots_[s] = r;
  return s;
}

void PeEngine::end_ray(uint32_t slot, uint64_t now) {
  ends_fifo_.write(slots_[slot].id, now);
  free_slots_.push_back(slot);
}

// ---- the units: each writes its result when its work ends (one cycle later again while the
// FIFO is full, as the modules' put() does), then takes its next item ----

void PeEngine::wake(size_t unit, const Due& d, uint64_t now) {
  const uint64_t retry = now + cycle_;
  switch (unit_at(unit)) {
    case Unit::FrontBuffer:
      if (front_ == Front::Aligning) {
        primary(now);
        return;
      }
      if (search_fifo_.full()) return schedule(kFront, retry);
      search_fifo_.write(front_ray_, now);
      front_loop(now);
      return;

    case Unit::Search: {
      Fifo& out = d.route == Route::Intersect ? intersect_fifo_
                  : d.route == Route::Feedback ? feedback_search_
                  : d.route == Route::Shade    ? shade_fifo_
                                               : ends_fifo_;
      if (out.full()) return schedule(unit, retry, d.item, d.route);
      if (d.route == Route::End)
        end_ray(d.item, now);
      else
        out.write(d.item, now);
      if (search_fifo_.visible > 0)
        search_start(unit, search_fifo_.read(now), now);
      else
        idle_search_.push_back(unit);
      return;
    }

    case Unit::Mac: {
      const size_t lane = unit - mac0_;
      Fifo& out = to_root_[lane];
      if (out.full()) return schedule(unit, retry, d.item);
      out.write(d.item, now);
      if (intersect_fifo_.visible > 0)
        mac_start(lane, intersect_fifo_.read(now), now);
      else
        idle_macs_.insert(lane);
      return;
    }

    case Unit::Root: {
      const size_t lane = unit - root0_;
      Fifo& out = d.route == Route::Shade ? shade_fifo_ : d.route == Route::Feedback ? feedback_intersect_ : ends_fifo_;
      if (out.full()) return schedule(unit, retry, d.item, d.route);
      const MachineRay& r = results_[d.item].r;
      if (d.route == Route::End)
        ends_fifo_.write(r.id, now);
      else
        out.write(new_ray(r), now);
      free_results_.push_back(d.item);
      if (to_root_[lane].visible > 0) root_start(lane, to_root_[lane].read(now), now);
      return;
    }

    case Unit::Shading:
      // The ray's end first, then the spawned rays in order; each is made (numbered) before
      // it waits for room, as in the module.
      for (; shade_next_ <= shade_out_.rays.size(); ++shade_next_) {
        if (shade_next_ == 0) {
          if (ends_fifo_.full()) return schedule(kShading, retry);
          ends_fifo_.write(slots_[shade_ray_].id, now);
          continue;
        }
        if (!shade_child_made_) {
          shade_child_ = new_ray(spawned_ray(ctx_, slots_[shade_ray_], shade_out_.rays[shade_next_ - 1]));
          shade_child_made_ = true;
        }
        if (spawn_fifo_.full()) return schedule(kShading, retry);
        spawn_fifo_.write(shade_child_, now);
        shade_child_made_ = false;
      }
      free_slots_.push_back(shade_ray_);
      if (shade_fifo_.visible > 0) shade_start(shade_fifo_.read(now), now);
      return;
  }
}

void PeEngine::front_loop(uint64_t now) {
  while (ends_fifo_.visible > 0) {
    ends_fifo_.read(now);
    --in_flight_;
  }
  for (Fifo* f : {&feedback_search_, &feedback_intersect_}) {
    while (f->visible > 0) {
      queue_.push_back(f->read(now));
      --in_flight_;
    }
  }
  // Spawned rays are new: their parent's credit came back through the ends FIFO.
  if (spawn_path_)
    while (spawn_fifo_.visible > 0) queue_.push_back(spawn_fifo_.read(now));

  if (in_flight_ < credits_) {
    if (!queue_.empty()) {
      const bool spilled = queue_.size() > size_t(ctx_.config.front_buffer_capacity);
      if (spilled) ++ctx_.counters.spills;
      const uint32_t slot = queue_.front();
      queue_.pop_front();
      return dispatch(slot, dispatch_cycles(ctx_.config, spilled, false), now);
    }
    if (next_primary_ < rays_visible_) {
      // Rays from the host arrive between PE clock edges.
      if (const uint64_t off = now % cycle_) {
        front_ = Front::Aligning;
        return schedule(kFront, now + cycle_ - off);
      }
      return primary(now);
    }
  }
  if (next_primary_ == rays_expected_ && queue_.empty() && in_flight_ == 0) {
    front_ = Front::Done;
    finish_ = now;
    ctx_.counters.finish = sc_core::sc_time::from_value(now);
    return;
  }
  stalled_ = !queue_.empty() || next_primary_ < rays_visible_;  // only credits hold them back
  waiting_since_ = now;
  front_ = Front::Waiting;
}

void PeEngine::primary(uint64_t now) {
  if (next_primary_ == 0) ctx_.counters.start = sc_core::sc_time::from_value(now);
  const uint32_t slot = new_ray(primary_ray(ctx_, rays_, next_primary_++));
  dispatch(slot, dispatch_cycles(ctx_.config, false, true), now);
}

void PeEngine::dispatch(uint32_t slot, uint64_t cycles, uint64_t now) {
  ++in_flight_;
  ctx_.counters.front.busy_cycles += cycles;
  ++ctx_.counters.front.items;
  front_ray_ = slot;
  front_ = Front::Dispatching;
  schedule(kFront, now + cycles * cycle_);
}

void PeEngine::search_start(size_t unit, uint32_t slot, uint64_t now) {
  const Routed w = search_work(ctx_, slots_[slot]);
  schedule(unit, now + w.cycles * cycle_, slot, w.route);
}

void PeEngine::mac_start(size_t lane, uint32_t slot, uint64_t now) {
  if (free_results_.empty()) {
    results_.emplace_back();
    free_results_.push_back(uint32_t(results_.size() - 1));
  }
  const uint32_t result = free_results_.back();
  free_results_.pop_back();
  MacResult& m = results_[result];
  m.r = slots_[slot];
  free_slots_.push_back(slot);  // the ray travels with its MAC result now
  schedule(mac0_ + lane, now + mac_work(ctx_, timing_, m) * cycle_, result);
}

void PeEngine::root_start(size_t lane, uint32_t result, uint64_t now) {
  const Routed w = root_work(ctx_, results_[result], clips_);
  schedule(root0_ + lane, now + w.cycles * cycle_, result, w.route);
}

void PeEngine::shade_start(uint32_t slot, uint64_t now) {
  shade_ray_ = slot;
  const MachineRay& r = slots_[slot];
  const uint64_t cycles = shade_work(ctx_, r, frame_[r.slot], ids_[r.slot], shade_out_);
  for (const Ray& child : shade_out_.rays)
    if (!ctx_.units.generates(child.kind))
      SC_REPORT_FATAL("rtm/pe/shading", "a left-out ray generator was needed: the scene analysis is wrong");
  shade_next_ = 0;
  schedule(kShading, now + cycles * cycle_);
}

// ---- statistics ----

std::vector<std::pair<std::string, const FifoStats*>> PeEngine::fifo_stats(uint64_t now) {
  std::vector<std::pair<std::string, const FifoStats*>> out;
  for (Fifo* f : fifos_) {
    out.emplace_back(f->name, &f->meter.close(now));
  }
  return out;
}

std::string PeEngine::occupancy_report() const {
  std::ostringstream s;
  s << queue_.size() << " rays waiting in the front buffer, " << in_flight_ << " past it;";
  for (const Fifo* f : fifos_) s << " " << f->name << " " << f->meter.occupancy << "/" << f->meter.stats.depth;
  return s.str();
}

}  // namespace rtm
