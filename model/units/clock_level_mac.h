// The MAC unit (paper §5.2, Fig. 2) at clock level: two multipliers and an adder chained as a
// pipeline of registers, advanced one rising edge at a time, accumulating 6 products for α, 12 for
// β and 10 for γ per primitive. The datapath of clocked timing, without a scheduler: the modules
// run it on the PE clock (machine/clocked_mac.h), the PE engine edge by edge up to each of the
// MAC's actions (engine/pe_engine.h).
//
// It must agree exactly with the fast model (units/mac_timing.h for cycles, form_abg for values):
// check_clocked compares them on every job, and the root unit takes the clocked sums.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "config/config.h"
#include "units/intersection.h"
#include "units/mac_timing.h"
#include "units/pe_state.h"

namespace rtm {

/// Rounds a double to the machine's precision. Computing a float operation in double and
/// rounding once gives exactly the IEEE float result for +, − and × (53 >= 2·24 + 2), so the
/// clock-level MAC can hold its registers as doubles.
inline double round_to(Precision p, double x) {
  return p == Precision::Fp32 ? double(float(x)) : x;
}

/// A MAC job in the clock-level unit's terms: latches and one RAM image per primitive, already
/// rounded to the machine precision.
struct MacJob {
  std::vector<Latches<double>> latches;  ///< per primitive (the origin is re-centred on each)
  std::vector<CoefRam<double>> rams;
  std::vector<MacOps> ops;  ///< per primitive; empty: the full schedule for all
  std::vector<uint64_t>
      loads;  ///< per primitive, cycles to load its coefficients (MacTiming::Job::loads)
  uint32_t ray_id = 0;
};

/// The job of ray r's examined voxel, from the PE's scene image.
MacJob mac_job(const SceneImage& image, const MachineRay& r, const MacTiming::Job& plan);

class ClockLevelMac {
 public:
  ClockLevelMac(const MacTiming& timing, Precision precision);

  /// A finished job: α, β, γ per primitive and its cycles from its first edge to its last.
  struct Done {
    std::vector<std::array<double, 3>> sums;
    uint64_t cycles = 0;
  };
  /// Posts a job between edges: its cycle 0 is the next edge.
  void start(MacJob job);
  /// The oldest job, if its last sums are out; false while it runs.
  bool finish(Done& done);
  /// Nothing posted is left to run and the registers hold no product: an edge would change
  /// nothing that matters (only the edge count, from which a job's cycles are measured).
  bool idle() const;

  /// The registers after an edge, for a waveform.
  struct Registers {
    bool m1_valid = false, m2_valid = false, add_valid = false;
    double m1_a = 0, m1_b = 0, m1_out = 0, m2_coef = 0, m2_out = 0;
    bool accumulated = false;  ///< the adder put out a product: the fields below changed
    double acc = 0;
    uint32_t abg_select = 0, product_counter = 0, ray_id = 0, prim = 0;
    bool sums_valid = false;  ///< a primitive's α, β, γ were handed on at this edge
    double alpha = 0, beta = 0, gamma = 0;
  };
  /// One rising edge: the schedule's next product enters multiplier 1 and every stage takes what
  /// the one before it held at the last edge. `regs`, when given, receives the registers.
  /// True when a job finished at this edge.
  bool edge(Registers* regs = nullptr);

 private:
  /// A product on its way down the pipeline.
  struct Stage {
    bool valid = false;
    uint64_t job = 0;  ///< its job's serial number
    int prim = 0;
    int k = 0;          ///< index into kMacSchedule
    bool last = false;  ///< the primitive's last product
    double value = 0;   ///< the product so far
  };
  /// A shift register of a fixed number of stages: a stage in at every edge, the oldest out.
  struct Delay {
    std::vector<Stage> stages;
    size_t at = 0;
    explicit Delay(int length) : stages(size_t(length)) {}
    Stage shift(const Stage& in) {
      Stage out = stages[at];
      stages[at] = in;
      at = at + 1 == stages.size() ? 0 : at + 1;
      return out;
    }
    bool empty() const;
  };
  struct Posted {
    MacJob job;
    MacTiming::Job plan;
    uint64_t start = 0;   ///< the edge of its cycle 0
    int prim = 0, j = 0;  ///< its next product to issue
    Done done;
    bool finished = false;
  };
  Posted& job(uint64_t serial) { return jobs_[size_t(serial - first_serial_)]; }

  /// The adder: the product leaving it into α, β or γ; true when a job finished.
  bool accumulate(const Stage& out, Registers* regs);
  /// Multiplier 2: the product from multiplier 1 times its coefficient.
  void multiply_by_coefficient(Stage& s);
  /// Multiplier 1: the product of two latches.
  void multiply_latches(Stage& s);
  /// The product the schedule issues at this edge (invalid: none), for multiplier 1.
  Stage issue();

  MacTiming timing_;
  Precision precision_;
  std::deque<Posted> jobs_;  ///< posted and not yet handed on, oldest first
  uint64_t first_serial_ = 0;
  uint64_t tick_ = 0;  ///< edges run so far
  Delay mul1_, mul2_, adder_;
  double sum_[3] = {0, 0, 0};
  uint32_t accumulated_ = 0;
};

/// The clocked MAC's finished job against the fast model's sums `fast` and cycles: "" when they
/// agree bit for bit and to the cycle, and then `fast` holds the clocked sums; else what differs
/// (a model bug). `ran`: the clocked job had finished.
std::string check_clocked(MacResult& fast, bool mem32, const ClockLevelMac::Done& clocked,
                          uint64_t fast_cycles, bool ran);

/// The clock-level MAC driven edge by edge from a scheduler's actions instead of a clock: edges
/// fall mid-cycle, so the edges before an action at a cycle boundary are run first, and none while
/// the unit has nothing inside or holds a result that cannot leave.
class EdgeByEdgeMac {
 public:
  EdgeByEdgeMac(const MacTiming& timing, Precision precision, uint64_t period)
      : mac_(timing, precision), period_(period), next_edge_(period / 2) {}

  /// A job taken at `now` whose fast model takes `fast_cycles`.
  void start(uint64_t now, MacJob job, uint64_t fast_cycles);
  /// At `now` the unit's oldest result is due: checks the clocked job against the fast one
  /// (once per job; see check_clocked) and returns the difference, "" when none.
  std::string check(uint64_t now, MacResult& fast, bool mem32);
  /// Whether the due result cannot leave at `now`; while it cannot, the whole pipeline holds.
  void stall(uint64_t now, bool on);
  /// The due result left: the next one is checked anew.
  void retired() { checked_ = false; }

 private:
  void run_before(uint64_t now);

  ClockLevelMac mac_;
  uint64_t period_;
  uint64_t next_edge_;
  bool stalled_ = false, checked_ = false;
  std::deque<uint64_t> fast_cycles_;  ///< of each job inside, oldest first
};

}  // namespace rtm
