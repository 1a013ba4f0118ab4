// The machine configuration: every timing parameter, FIFO depth and unit count in one place.
// Plain data, parsed once by the testbench and handed to the modules' constructors.
#pragma once

#include <climits>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geom/numerics.h"

namespace rtm {

enum class Partition { Scanlines, Blocks, Strips, Pixels };
enum class Timing { Fast, Clocked };
enum class Precision { Fp32, Fp64 };
enum class FlowControl { Credits, None };

struct MachineConfig {
  // Multiprocessor
  int pes = 1;                            ///< processing elements
  Partition partition = Partition::Scanlines;
  int tile = 16;                          ///< block edge in pixels (partition = blocks)

  // Fidelity
  Timing timing = Timing::Fast;
  Precision precision = Precision::Fp32;  ///< MAC, root unit and clip arithmetic
  enum class MacSchedule { Full, Sparse };
  /// full: the paper's 6 + 12 + 10 products for every test; sparse: each primitive's products
  /// with a zero coefficient word are skipped (same sums, fewer cycles).
  MacSchedule mac_schedule = MacSchedule::Sparse;
  /// Units, FIFOs and paths the scene cannot use are not elaborated (render/scene_needs.h).
  bool leave_out = true;
  bool recentre = true;                   ///< coefficients relative to each primitive's centre (false: world coefficients, as in the paper)
  /// Root unit's discriminant: plain b·b − 4a·c, or fma (difference of products with fused
  /// multiply-adds, fma_discriminant_cycles more root latency). docs/numerics.md.
  Discriminant discriminant = MacNumerics{}.discriminant;
  /// Coefficient RAM image: none (the quadric's coefficients, the paper) or pow2 (scaled by a
  /// power of two so the largest is in [1, 2): same bits in range, no float32 overflow).
  CoefScaling coef_scaling = MacNumerics{}.coef_scaling;
  /// V latches: machine (V rounded, then minus the centre: the paper's latch), wide (V − centre in
  /// fp64, then rounded: the default) or advance (wide, from the voxel's entry point;
  /// advance_cycles more root latency).
  OriginLatch origin_latch = MacNumerics{}.origin;

  // PE clock and units (cycles)
  double clock_ns = 10;                   ///< PE clock period
  int search_units = 4;                   ///< replicated 3DDDA units (paper Fig. 1: four)
  /// per_voxel: a ray in an empty voxel goes back to the front buffer (the paper, §4.2);
  /// until_occupied: the search unit keeps stepping until an occupied voxel or the walk's end.
  enum class SearchWalk { PerVoxel, UntilOccupied };
  SearchWalk search_walk = SearchWalk::PerVoxel;
  int intersection_units = 1;             ///< MAC + root/sort lanes (the paper has one)
  int dda_step_cycles = 2;                ///< one 3DDDA step (compare and increment)
  int voxel_read_cycles = 2;              ///< read a voxel's occupancy/list header from local memory
  int mul_latency = 1;                    ///< each MAC multiplier's pipeline depth
  int add_latency = 1;                    ///< MAC adder latency; dependent accumulation issues one product per add_latency
  int coef_load_cycles = 4;               ///< load a primitive's 13 coefficient words into the MAC RAM (overlapped with the previous primitive)
  int root_latency = 12;                  ///< root unit: discriminant, square root, two divisions (pipelined)
  int fma_discriminant_cycles = 2;        ///< extra root-unit latency of discriminant = fma (the dependent FMA stage)
  int advance_cycles = 1;                 ///< extra root-unit latency of origin_latch = advance (adding t_enter to the roots)
  int clip_cycles = 4;                    ///< one clip half-space test (3 products and an add)
  int sort_cycles = 1;                    ///< per primitive result merged into the nearest-hit register
  int shade_cycles = 16;                  ///< normal, ambient term and frame-buffer update for one ray
  int spawn_cycles = 4;                   ///< generate one shadow or branch ray
  int accumulate_cycles = 2;              ///< add a shadow ray's or the background's brightness to the frame buffer
  int fb_dispatch_cycles = 1;             ///< front buffer hands out one ray

  // Buffers (rays)
  int front_buffer_capacity = 64;         ///< on-chip front buffer; overflow spills to local memory
  int spill_cycles = 8;                   ///< extra cycles to move a ray to or from the spill area
  int search_fifo_depth = 16;             ///< front buffer -> search units
  int intersect_fifo_depth = 16;          ///< search -> intersection
  int root_fifo_depth = 16;               ///< MAC -> root unit / sort
  int shade_fifo_depth = 16;              ///< search and intersection -> shading
  int feedback_fifo_depth = 8;            ///< each path back into the front buffer
  int loop_credits = 0;                   ///< rays allowed past the front buffer at once; 0 = the largest safe value
  /// credits: the deadlock-free flow control of FrontBuffer; none: the front buffer hands out
  /// rays whenever the search FIFO has room, as the paper describes, and the loop can deadlock
  /// (the simulator then reports it).
  FlowControl flow_control = FlowControl::Credits;

  // Host and interconnect
  enum class RayGeneration { Host, Pe };
  /// host: the host generates every primary ray and sends them (the paper); pe: each PE generates
  /// its own from the camera, pe_ray_cycles each, in its front buffer.
  RayGeneration ray_generation = RayGeneration::Host;
  int pe_ray_cycles = 8;

  double host_clock_ns = 10;
  int host_voxel_cycles = 40;             ///< per primitive reference registered in a voxel
  int host_ray_cycles = 20;               ///< per primary ray generated
  double link_bandwidth_mb_s = 400;       ///< host <-> PE link, MB/s
  double link_latency_ns = 1000;          ///< per transaction
  bool broadcast = false;                 ///< one transfer of the scene reaches every PE (else one per PE)
  int ray_block = 0;                      ///< primary rays per transfer; 0 = all of a PE's rays at once
  enum class Gather { AfterAll, AsFinished };
  /// after_all: the host reads the frame buffers once every PE is done (the paper's order);
  /// as_finished: it reads each PE's as soon as that PE is done, while the others still work.
  Gather gather = Gather::AfterAll;

  enum class Arbitration { Kernel, Ranked };
  /// Who goes first when units finish in the same cycle: kernel (SystemC's event queue decides)
  /// or ranked (a fixed order by unit: results independent of the kernel; machine/timekeeper.h).
  Arbitration arbitration = Arbitration::Ranked;

  enum class PeSimulation { Auto, Modules };
  /// auto: each PE's pipeline runs on the PE engine (machine/pe_engine.h) when the configuration
  /// allows it, with the same results as the modules; modules: always one SystemC process per unit.
  PeSimulation pe_simulation = PeSimulation::Auto;

  /// Root-unit latency including the discriminant option's extra stage.
  int root_cycles() const {
    return root_latency + (discriminant == Discriminant::Fma ? fma_discriminant_cycles : 0) +
           (origin_latch == OriginLatch::Advance ? advance_cycles : 0);
  }
  /// The MAC and root unit's numerical options, as SceneMemory takes them.
  MacNumerics numerics() const { return {discriminant, coef_scaling, origin_latch}; }
  /// The safe number of loop credits: no FIFO past the front buffer can then ever be full.
  int safe_credits() const;
  /// The front buffer's credits: loop_credits, its safe value, or unlimited without flow control.
  int loop_credits_in_force() const {
    return flow_control == FlowControl::None ? INT_MAX : loop_credits > 0 ? loop_credits : safe_credits();
  }
  /// Throws std::invalid_argument naming the offending key and why.
  void validate() const;
};

/// A configuration file problem: the message reads "file:line: key: what is wrong". Like a bad
/// command line, it is the user's input at fault (rtm exits 2), not the scene's.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what), file_(file), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

/// A named configuration key: how users set it from a file, --set key=value, or a sweep.
struct ConfigKey {
  std::string name;
  std::string doc;
  std::function<std::string(const MachineConfig&)> get;
  std::function<void(MachineConfig&, const std::string&)> set;  ///< throws std::invalid_argument
};
const std::vector<ConfigKey>& config_keys();

/// Sets one key from text; throws std::invalid_argument ("unknown key", "not a number", ...).
void set_config(MachineConfig& c, const std::string& key, const std::string& value);
/// Reads a YAML file holding one flat map of `key: value` pairs (the keys of config_keys()).
/// Throws ConfigError.
void load_config_file(MachineConfig& c, const std::string& path);
/// Every key with its value and documentation, one per line.
std::string describe_config(const MachineConfig& c);

const char* to_string(Partition p);
const char* to_string(Timing t);
const char* to_string(Precision p);
const char* to_string(FlowControl f);
const char* to_string(MachineConfig::RayGeneration g);
const char* to_string(MachineConfig::Gather g);
const char* to_string(MachineConfig::Arbitration a);
const char* to_string(MachineConfig::PeSimulation p);
const char* to_string(MachineConfig::SearchWalk w);
const char* to_string(MachineConfig::MacSchedule m);
const char* to_string(Discriminant d);
const char* to_string(CoefScaling s);
const char* to_string(OriginLatch o);

}  // namespace rtm
