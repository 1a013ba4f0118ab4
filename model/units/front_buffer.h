// The front buffer's policy (paper §4.2, and the flow control the paper does not give), apart
// from time: which ray goes next, when the loop is full, when the PE is done. Both schedulers
// drive it: they hand it what arrived on its inputs, ask what to do next, and do it.
//
// Arbitration: rays already in the loop (fed back or spawned) go first, in arrival order; a new
// primary ray is admitted only when none is waiting. Flow control: a ray past the front buffer
// holds one of `credits` credits until it comes back or ends, and every FIFO past the front
// buffer is at least `credits` deep, so no stage ever waits on a full FIFO downstream; the
// front buffer itself never refuses a ray (beyond its on-chip capacity rays spill to local
// memory), so the feedback paths always drain. Hence no cycle of waits can form: no deadlock.
//
// `Item` is how the scheduler holds a ray: a MachineRay (the modules) or a slot number (the
// engine).
#pragma once

#include <algorithm>
#include <cstdint>

#include "units/output.h"
#include "units/pe_state.h"
#include "units/ring_queue.h"

namespace rtm {

/// rays_expected while more primary rays may come (partition = dynamic: until the host says its
/// tiles are gone).
inline constexpr size_t kRaysUnknown = SIZE_MAX;

/// Where a ray handed out by the front buffer came from, for the event log.
enum FrontSource : uint8_t { kFromQueue = 0, kFromSpill = 1, kFromHost = 2 };

template <class Item>
class FrontBufferPolicy {
 public:
  enum class Next {
    Queued,   ///< hand out pop_queued()'s ray
    Primary,  ///< hand out the next primary ray (on a PE clock edge: host rays arrive between them)
    Finished,  ///< every ray of the PE's part of the frame has ended
    Wait,      ///< nothing to hand out until an input arrives
  };

  FrontBufferPolicy(PeState& pe, size_t rays_expected)
      : pe_(pe), credits_(pe.config.loop_credits_in_force()), rays_expected_(rays_expected) {
    for (FifoId id : inputs(UnitKind::FrontBuffer))
      if (const FifoSpec& f = fifo_spec(id); f.payload == Payload::Ray && pe.units.has(f))
        ray_inputs_.push_back(&f);
  }

  // What arrived on the inputs.
  void ended() { --in_flight_; }  ///< a ray left the loop: its credit comes back
  void returned(const Item& r) {  ///< fed back to walk on
    --in_flight_;
    queue_.push_back(r);
  }
  /// Spawned rays are new: their parent's credit came back with its end.
  void spawned(const Item& r) { queue_.push_back(r); }
  /// The first `n` primary rays are in local memory, of `expected` (kRaysUnknown: more may come).
  /// A new tile (or the host's answer that none is left) answers the PE's request for one.
  void primaries_arrived(size_t n) { primaries_arrived(n, rays_expected_); }
  void primaries_arrived(size_t n, size_t expected) {
    if (n > primaries_ || expected != rays_expected_) asked_ = false;
    primaries_ = n;
    rays_expected_ = expected;
  }

  Next next() const {
    if (in_flight_ < credits_) {
      if (!queue_.empty()) return Next::Queued;
      if (next_primary_ < primaries_ && room_for_primary() && !before_frame_end())
        return Next::Primary;
    }
    if (next_primary_ == rays_expected_ && queue_.empty() && in_flight_ == 0) return Next::Finished;
    return Next::Wait;
  }

  /// The waiting ray that goes next, handed out at `now`; `cycles` receives its dispatch time,
  /// `spilled` whether it came from the spill area (rays beyond the on-chip capacity live in local
  /// memory, and its record is read back: `wait`).
  Item pop_queued(uint64_t now, uint64_t& cycles, bool& spilled, MemoryWait& wait) {
    spilled = queue_.size() > size_t(pe_.config.front_buffer_capacity);
    cycles = dispatch_cycles(false);
    if (spilled) {
      ++pe_.counters.spills;
      if (PeMemory* m = pe_.memory.get()) {
        cycles += m->unloaded(kSpillRecordBytes);
        wait.latency = cycles;
        m->request(m->front(), m->addresses().spilled_ray(spill_place(spill_reads_++)),
                   kSpillRecordBytes, now / pe_.cycle, cycles, wait);
      }
    }
    wait.latency = cycles;
    Item r = queue_.front();
    queue_.pop_front();
    return r;
  }
  /// The number of the next primary ray in local memory, handed out at `now`; `cycles` as above.
  /// A ray the host made is read from local memory within the dispatch (`wait`).
  size_t pop_primary(uint64_t now, uint64_t& cycles, MemoryWait& wait) {
    if (next_primary_ == 0) pe_.counters.start = now;
    if (frame_wait_since_ != kNotWaiting) {
      pe_.counters.frame_wait += now - frame_wait_since_;
      frame_wait_since_ = kNotWaiting;
    }
    cycles = dispatch_cycles(true);
    wait.latency = cycles;
    PeMemory* m = pe_.memory.get();
    if (m && pe_.config.ray_generation == MachineConfig::RayGeneration::Host)
      m->request(m->front(), m->addresses().primary_ray(pe_.place_in_frame(next_primary_)),
                 kRayRecordBytes, now / pe_.cycle, std::max(cycles, m->unloaded(kRayRecordBytes)),
                 wait);
    ++next_primary_;
    // A dynamic partition asks for its next tile when it takes the last primary ray it holds: the
    // link's round trip overlaps the rays still in its loop, and no PE holds a tile another could
    // have started (asking a tile ahead was slower: docs/machine.md, "Screen partitioning").
    if (rays_expected_ == kRaysUnknown && !asked_ && next_primary_ == primaries_)
      asked_ = ask_ = true;
    return next_primary_ - 1;
  }
  /// A ray (`id`) goes past the front buffer: it takes a credit and `cycles` of the front buffer.
  void dispatched(uint64_t now, uint32_t id, uint64_t cycles, uint8_t from) {
    ++in_flight_;
    if (pe_.log) pe_.log->take(now, UnitKind::FrontBuffer, 0, id, cycles, from);
  }
  void finish(uint64_t now) {
    finished_ = true;
    pe_.counters.finish = now;
  }

  /// What the front buffer does when it may hand out a ray (units/unit_step.h's accept), the
  /// same under both schedulers, which then carry it out.
  struct Decision {
    enum Kind {
      Queued,   ///< hand out `queued`
      Primary,  ///< hand out primary ray number `primary`
      Align,    ///< a primary ray goes at the PE clock edge `at`: wake then
      None,     ///< nothing now (waiting for input, aligning, or finished)
    } kind = None;
    Item queued{};
    size_t primary = 0;
    uint64_t cycles = 0;  ///< Queued, Primary: its dispatch time
    uint8_t from = 0;     ///< Queued, Primary: where it came from (FrontSource)
    uint64_t at = 0;      ///< Align
    MemoryWait wait;      ///< Queued, Primary: what it reads from local memory
  };
  /// Decides at `now` (`cycle`: the PE clock period, in now's unit); `drain()` hands the policy
  /// what arrived on its inputs, and is called only when a decision needs them.
  template <class Drain>
  Decision decide(uint64_t now, uint64_t cycle, Drain&& drain) {
    Decision d;
    if (state_ == State::Aligning) {
      // The primary ray it decided on goes at the PE clock edge it asked to be woken at.
      if (now % cycle || now < align_at_) return d;
      state_ = State::Deciding;
      d.kind = Decision::Primary;
      d.primary = pop_primary(now, d.cycles, d.wait);
      d.from = kFromHost;
      return d;
    }
    if (finished_ || overflowed()) return d;
    const size_t before = queue_.size();
    drain();
    spill_arrivals(before, now);
    waiting_for_tile(now);
    frame_ending(now);
    if (queue_.size() > capacity()) {
      // The ray trees outgrew local memory: the machine stops the frame (machine/machine.cpp).
      pe_.counters.spill_overflow = queue_.size();
      pe_.counters.spill_overflow_at = now;
      return d;
    }
    switch (next()) {
      case Next::Queued: {
        bool spilled = false;
        d.kind = Decision::Queued;
        d.queued = pop_queued(now, d.cycles, spilled, d.wait);
        d.from = spilled ? kFromSpill : kFromQueue;
        return d;
      }
      case Next::Primary: {
        // Rays from the host arrive between PE clock edges; a frame's first waits for the PE's
        // switch from the frame before.
        state_ = State::Aligning;
        const bool first_of_frame = pe_.frame_rays && next_primary_ % pe_.frame_rays == 0;
        const uint64_t from = first_of_frame ? std::max(now, next_frame_at_) : now;
        align_at_ = from + (cycle - from % cycle) % cycle;
        if (align_at_ > now) {
          d.kind = Decision::Align;
          d.at = align_at_;
          return d;
        }
        return decide(now, cycle, drain);
      }
      case Next::Finished:
        finish(now);
        return d;
      case Next::Wait:
        return d;
    }
    return d;
  }

  /// Decides at `now` and carries the decision out with the scheduler's operations, the same
  /// under both schedulers (units/unit_step.h's accept); true when it handed out a ray:
  ///   bool read_end()                  takes a ray's end from its input; false when there is none
  ///   bool read(FifoId, Item&)         takes a ray from that input; false when there is none
  ///   void drained()                   the inputs are drained
  ///   Item primary(size_t n)           primary ray n, made (numbered) now
  ///   void dispatch(Item&&, cycles, from, MemoryWait&&)  the ray goes into the front buffer's
  ///   pipeline void want(t)                     wake me at t void finished() every ray has ended
  ///   (called once)
  ///   void ask_for_tile()              the PE asks the host for its next tile (partition =
  ///   dynamic)
  ///   void frame_ended()               the PE has ended a frame, more to come (frames > 1)
  template <class Ops>
  bool carry_out(uint64_t now, uint64_t cycle, Ops& ops) {
    Decision d = decide(now, cycle, [&] { drain(ops); });
    if (tell_frame_end_) {
      tell_frame_end_ = false;
      ops.frame_ended();
    }
    switch (d.kind) {
      case Decision::Queued:
        ops.dispatch(std::move(d.queued), d.cycles, d.from, std::move(d.wait));
        return true;
      case Decision::Primary:
        ops.dispatch(ops.primary(d.primary), d.cycles, d.from, std::move(d.wait));
        if (ask_) {
          ask_ = false;
          ops.ask_for_tile();
        }
        return true;
      case Decision::Align:
        ops.want(d.at);
        return false;
      case Decision::None:
        if (finished_ && !finish_told_) {
          finish_told_ = true;
          ops.finished();
        }
        return false;
    }
    return false;
  }
  /// What arrived on the inputs, handed to the policy: rays' ends first, then the rays in the FIFO
  /// table's order.
  template <class Ops>
  void drain(Ops& ops) {
    while (ops.read_end()) ended();
    Item r;
    for (const FifoSpec* f : ray_inputs_)
      while (ops.read(f->id, r)) f->returns_credit ? returned(r) : spawned(r);
    ops.drained();
  }

  /// After a decision of None: whether the front buffer now waits for input (not when it is
  /// aligning or finished), starting its stall accounting (only credits hold back rays it has).
  bool wait(uint64_t now) {
    if (state_ != State::Deciding || finished_) return false;
    state_ = State::Waiting;
    stalled_ = !queue_.empty() || (next_primary_ < primaries_ && !before_frame_end());
    waiting_since_ = now;
    return true;
  }
  /// Woken at `now`, for whatever reason: a wait for input is over.
  void woke(uint64_t now) {
    if (state_ != State::Waiting) return;
    state_ = State::Deciding;
    if (stalled_) pe_.counters.credit_stall += now - waiting_since_;
  }
  bool waiting_for_input() const { return state_ == State::Waiting; }

  /// Cycles until the next ray may be handed out after one that takes `cycles` (units/pipeline.h).
  uint64_t interval(uint64_t cycles) const {
    return pipeline_interval(pe_.config.dispatch_interval, cycles);
  }

  bool finished() const { return finished_; }
  bool overflowed() const { return pe_.counters.spill_overflow > 0; }
  /// Rays it can hold: on chip, then in the spill area.
  uint64_t capacity() const {
    const uint64_t on_chip = uint64_t(pe_.config.front_buffer_capacity);
    return pe_.spill_rays > UINT64_MAX - on_chip ? UINT64_MAX : on_chip + pe_.spill_rays;
  }
  /// Flow control for a bounded spill area: a new primary ray goes only if every ray in the loop
  /// and it can each come back or spawn its most children without the waiting rays outgrowing
  /// what the front buffer holds, or if the loop is empty. Rays already in the loop always go on
  /// (they may spawn more, and a tree too wide for the memory stops the frame with an error), so
  /// a primary ray waits only for rays that will leave: no wait can close a cycle.
  bool room_for_primary() const {
    if (pe_.spill_rays == UINT64_MAX || (in_flight_ == 0 && queue_.empty())) return true;
    const uint64_t per_ray = std::max<uint64_t>(1, pe_.spawn_fanout);
    const uint64_t rays = uint64_t(in_flight_) + 1;
    return queue_.size() <= capacity() && rays <= (capacity() - queue_.size()) / per_ray;
  }
  int in_flight() const { return in_flight_; }
  size_t waiting() const { return queue_.size(); }
  size_t primaries_known() const { return primaries_; }

 private:
  uint64_t dispatch_cycles(bool primary) const {
    const MachineConfig& c = pe_.config;
    const bool generate = primary && c.ray_generation == MachineConfig::RayGeneration::Pe;
    return uint64_t(c.fb_dispatch_cycles) + (generate ? uint64_t(c.pe_ray_cycles) : 0);
  }
  /// The spill area as a ring of kSpillRecordBytes places: the k-th ray written or read.
  uint64_t spill_place(uint64_t k) const {
    return pe_.spill_rays == 0 || pe_.spill_rays == UINT64_MAX ? k : k % pe_.spill_rays;
  }
  /// Rays that arrived beyond the on-chip capacity (the queue held `before`) are written to the
  /// spill area at `now`; nothing waits for a write.
  void spill_arrivals(size_t before, uint64_t now) {
    PeMemory* m = pe_.memory.get();
    const size_t on_chip = size_t(pe_.config.front_buffer_capacity);
    if (!m || queue_.size() <= std::max(before, on_chip)) return;
    for (size_t n = queue_.size() - std::max(before, on_chip); n > 0; --n)
      m->post(m->front(), m->addresses().spilled_ray(spill_place(spill_writes_++)),
              kSpillRecordBytes, now / pe_.cycle);
  }

  /// The PE's loop is empty and every primary ray it holds taken while more may come: it waits for
  /// a tile from then (counted in tile_wait, from its first ray on) until one, or the host's
  /// answer that none is left, arrives.
  void waiting_for_tile(uint64_t now) {
    const bool idle = rays_expected_ == kRaysUnknown && next_primary_ == primaries_ &&
                      next_primary_ > 0 && queue_.empty() && in_flight_ == 0;
    if (idle && tile_wait_since_ == kNotWaiting) tile_wait_since_ = now;
    if (!idle && tile_wait_since_ != kNotWaiting) {
      pe_.counters.tile_wait += now - tile_wait_since_;
      tile_wait_since_ = kNotWaiting;
    }
  }

  /// frames > 1: the next primary ray starts a frame, and the frame before has rays in the loop.
  bool before_frame_end() const {
    const uint64_t n = pe_.frame_rays;
    return n > 0 && next_primary_ > 0 && next_primary_ % n == 0 &&
           frames_ended_ < next_primary_ / n;
  }
  /// frames > 1: a frame whose rays have all ended ends at `now`; the next may start once the PE
  /// has switched to it (PeState::frame_switch), and the PE tells the host (carry_out).
  void frame_ending(uint64_t now) {
    if (!before_frame_end() || !queue_.empty() || in_flight_ > 0) return;
    ++frames_ended_;
    pe_.counters.frame_ends.push_back(now);
    if (next_primary_ == rays_expected_) return;  // the last: the PE is finished
    next_frame_at_ = now + pe_.frame_switch;
    frame_wait_since_ = now;
    tell_frame_end_ = true;
  }

  static constexpr uint64_t kNotWaiting = UINT64_MAX;
  PeState& pe_;
  const int credits_;
  size_t rays_expected_;
  bool asked_ = false;  ///< a request for a tile is out, not yet answered
  bool ask_ = false;    ///< a request to send (carry_out sends it)
  uint64_t tile_wait_since_ = kNotWaiting;
  // frames > 1.
  size_t frames_ended_ = 0;
  uint64_t next_frame_at_ = 0;  ///< the next frame's first primary ray goes no earlier
  uint64_t frame_wait_since_ = kNotWaiting;
  bool tell_frame_end_ = false;  ///< a frame's end to tell (carry_out tells it)
  uint64_t align_at_ = 0;        ///< Aligning: the primary ray goes at this PE clock edge
  RingQueue<Item> queue_;
  size_t next_primary_ = 0, primaries_ = 0;
  int in_flight_ = 0;
  bool finished_ = false, finish_told_ = false;
  std::vector<const FifoSpec*>
      ray_inputs_;  ///< the rays' inputs the PE has, in the FIFO table's order
  enum class State { Deciding, Waiting, Aligning } state_ = State::Deciding;
  bool stalled_ = false;
  uint64_t waiting_since_ = 0;
  uint64_t spill_writes_ = 0, spill_reads_ = 0;
};

}  // namespace rtm
