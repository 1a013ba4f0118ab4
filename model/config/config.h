// The machine configuration: every timing parameter, FIFO depth and unit count in one place.
// Plain data, parsed once by the testbench and handed to the modules' constructors. What each
// member means and accepts is declared once, with its key, in config_keys() (config.cpp);
// `rtm config` and docs/machine.md list them. The defaults are the initialisers here; a preset
// (presets(), config.cpp) is a named set of keys applied on top of them.
#pragma once

#include <climits>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geom/numerics.h"
#include "scene/file_error.h"
#include "scene/grid_frame.h"

namespace rtm {

enum class Partition { Scanlines, Blocks, Strips, Pixels, Dynamic };
enum class Timing { Fast, Clocked };
enum class Precision { Fp32, Fp64 };
enum class FlowControl { Credits, None };
/// How a PE's local memory orders the requests issued in one cycle (memory/local_memory_timing.h).
enum class MemoryArbitration { RoundRobin, FixedPriority, Fcfs };

/// The most replicated units of one kind a PE may have (search_units' bound); the lane dispatcher
/// (units/lane_dispatcher.h) holds as many.
inline constexpr int kMaxUnitsOfAKind = 256;

/// The preset of MachineConfig{} itself: no key changed.
inline constexpr const char* kDefaultPreset = "default";

struct MachineConfig {
  /// The preset the keys started from (apply_preset); the statistics record it.
  std::string preset = kDefaultPreset;

  // Multiprocessor
  int pes = 1;
  Partition partition = Partition::Scanlines;
  int tile = 16;

  // Fidelity
  Timing timing = Timing::Fast;
  /// Every datapath unit's arithmetic, unless the unit's own key below says otherwise.
  Precision precision = Precision::Fp32;
  /// A unit's own arithmetic: as `precision` says (the default), or fp32 or fp64 whatever it says.
  enum class UnitPrecision { Precision, Fp32, Fp64 };
  UnitPrecision intersection_precision =
      UnitPrecision::Precision;                            ///< the MAC, root unit and clip tests
  UnitPrecision dda_precision = UnitPrecision::Precision;  ///< the search units' 3DDDA
  UnitPrecision shading_precision = UnitPrecision::Precision;  ///< the shading unit
  enum class MacSchedule { Full, Sparse };
  MacSchedule mac_schedule = MacSchedule::Sparse;
  bool leave_out = true;  ///< what is left out: render/scene_needs.h
  bool recentre = true;
  // The numerical options' defaults are MacNumerics', which the reference renderer uses, except
  // the origin latch: the reference tests each primitive once per ray (its mailbox), which the
  // advanced latch, formed per voxel, would not allow; in fp64 the two give the same image. In fp32
  // the advanced latch keeps every SPD scene's primary hits within 99.5 % of the reference's
  // (docs/numerics.md, case 13).
  Discriminant discriminant = MacNumerics{}.discriminant;
  CoefScaling coef_scaling = MacNumerics{}.coef_scaling;
  OriginLatch origin_latch = OriginLatch::Advance;
  HitRefine hit_refine = HitRefine::Newton;
  /// Triangles with vertex normals (NFF pp, mesh files) shaded smooth: what the files ask for;
  /// interpolate_cycles more shading latency on such a hit (docs/scene-format.md, "Vertex
  /// normals").
  NormalInterpolation normal_interpolation = kDefaultNormalInterpolation;
  /// The coordinates the PEs compute in (scene/grid_frame.h): the grid's own, so that fp32
  /// accuracy does not depend on where the scene is (docs/numerics.md, "Where the scene is").
  PeFrame pe_frame = PeFrame::Grid;

  // PE clock and units (cycles)
  double clock_ns = 10;
  int search_units = 4;
  enum class SearchWalk { PerVoxel, UntilOccupied };
  SearchWalk search_walk = SearchWalk::PerVoxel;
  int intersection_units = 1;
  int dda_step_cycles = 2;
  int mul_latency = 1;
  int add_latency = 1;
  int root_latency = 12;
  int fma_discriminant_cycles = 2;
  int advance_cycles = 1;
  int refine_cycles = 8;
  int interpolate_cycles = 12;
  int clip_cycles = 4;
  int sort_cycles = 1;
  int shade_cycles = 16;
  int spawn_cycles = 4;
  int accumulate_cycles = 2;
  int fb_dispatch_cycles = 1;

  // Pipelining (units/pipeline.h, paper §2 ③): cycles between items a unit accepts; 0: each
  // item's own latency, i.e. the unit holds one item at a time (unpipelined).
  int dispatch_interval = 1;
  int search_interval = 1;    ///< per 3DDDA pass
  bool mac_streaming = true;  ///< the next job's products issue while the previous ones drain
  int root_interval = 1;      ///< per primitive
  int shade_interval = 1;

  // Buffers (rays)
  int front_buffer_capacity = 64;
  int local_memory_bytes = 1 << 30;
  int search_fifo_depth = 16;
  int intersect_fifo_depth = 16;
  int root_fifo_depth = 16;
  int shade_fifo_depth = 16;
  int feedback_fifo_depth = 8;
  int loop_credits = 0;
  FlowControl flow_control = FlowControl::Credits;

  // Local memory and the MAC's coefficient RAM: the timing models of model/memory/
  // (docs/memory.md).
  int memory_ports = 0;  ///< 0: as many as the requests need (no port contention)
  int memory_banks = 0;  ///< 0: no bank conflicts
  int memory_interleave_bytes = 16;
  int memory_latency = 2;
  int memory_bytes_per_cycle = 16;
  MemoryArbitration memory_arbitration = MemoryArbitration::RoundRobin;
  int mac_ram_primitives = 0;  ///< 0: every primitive's coefficients resident (paper §5.2)
  int voxel_cache_bytes = 0;   ///< 0: none

  // Host and interconnect
  enum class RayGeneration { Host, Pe };
  RayGeneration ray_generation = RayGeneration::Host;
  int pe_ray_cycles = 8;

  double host_clock_ns = 10;
  int host_voxel_cycles = 40;
  /// Who builds the voxel data: the host, sending it with the scene (the paper), or each PE its
  /// own.
  enum class Voxelisation { Host, Pe };
  Voxelisation voxelisation = Voxelisation::Host;
  int pe_voxel_cycles = 2;
  int host_ray_cycles = 20;
  int host_frame_cycles = 40;
  double link_bandwidth_mb_s = 400;
  double link_latency_ns = 1000;
  // The interconnect (model/net/interconnect.h, docs/machine.md "The host-PE interconnect").
  // Serial is the model's original link, so the default figures are what they always were.
  enum class LinkTopology { Serial, Bus, Star, Tree };
  LinkTopology link_topology = LinkTopology::Serial;
  int host_ports = 1;
  int tree_fanout = 2;
  /// How a tree's PE passes a transfer on: once it holds all of it, or once its header is in.
  enum class TreeForwarding { StoreAndForward, CutThrough };
  TreeForwarding tree_forwarding = TreeForwarding::StoreAndForward;
  bool broadcast = false;
  int ray_block = 0;
  int scene_block = 0;  ///< primitives per scene transfer, framed and sent in turn (0: at once)
  /// Frames in one run: the same frame again, the host preparing each while the PEs render the
  /// one before (machine/host.h).
  int frames = 1;
  enum class Gather { AfterAll, AsFinished, Streamed };
  Gather gather = Gather::AfterAll;
  int gather_block = 256;  ///< pixels per transfer of a streamed gather

  enum class Arbitration { Kernel, Ranked };
  Arbitration arbitration = Arbitration::Ranked;  ///< machine/timekeeper.h

  enum class PeSimulation { Auto, Modules };
  PeSimulation pe_simulation = PeSimulation::Auto;  ///< engine/pe_engine.h

  /// The technology the machine's cost is figured in: the built-in 45nm or a technology file
  /// (cost/technology.h, docs/cost.md).
  std::string tech = "45nm";

  /// Root-unit latency including the discriminant option's extra stage.
  int root_cycles() const {
    return root_latency + (discriminant == Discriminant::Fma ? fma_discriminant_cycles : 0) +
           (origin_latch == OriginLatch::Advance ? advance_cycles : 0);
  }
  /// Each unit's arithmetic: its own key, or `precision`.
  Precision intersection_precision_in_force() const { return in_force(intersection_precision); }
  Precision dda_precision_in_force() const { return in_force(dda_precision); }
  Precision shading_precision_in_force() const { return in_force(shading_precision); }
  /// Shading latency of a hit beyond shade_cycles: the hit refinement's.
  int refine_cycles_in_force() const { return hit_refine == HitRefine::Newton ? refine_cycles : 0; }
  /// Shading latency of a hit on primitive `p` beyond shade_cycles: the vertex normals' weighting.
  int interpolate_cycles_for(const Primitive& p) const {
    return normal_interpolation == NormalInterpolation::Barycentric && !p.normals.empty()
               ? interpolate_cycles
               : 0;
  }
  /// The MAC and root unit's numerical options, as SceneMemory takes them.
  MacNumerics numerics() const { return {discriminant, coef_scaling, origin_latch}; }
  /// The safe number of loop credits: no FIFO past the front buffer can then ever be full.
  int safe_credits() const;
  /// The front buffer's credits: loop_credits, its safe value, or unlimited without flow control.
  int loop_credits_in_force() const {
    return flow_control == FlowControl::None ? INT_MAX
           : loop_credits > 0                ? loop_credits
                                             : safe_credits();
  }
  /// Each key's range, then the rules across keys; throws std::invalid_argument naming the
  /// offending key and why.
  void validate() const;

 private:
  Precision in_force(UnitPrecision u) const {
    return u == UnitPrecision::Precision ? precision
           : u == UnitPrecision::Fp32    ? Precision::Fp32
                                         : Precision::Fp64;
  }
};

/// A configuration file problem: the message reads "file:line: key: what is wrong". Like a bad
/// command line, it is the user's input at fault (rtm exits 2), not the scene's.
struct ConfigError : FileError {
  using FileError::FileError;
};

/// A named configuration key: how users set it from a file, --set key=value, or a sweep. Each key
/// is declared once, in config_keys(); parsing, validate()'s range checks, `rtm config` and
/// docs/machine.md's key table all read that declaration. Its default is MachineConfig{}'s.
struct ConfigKey {
  enum class Type { Integer, Number, Flag, Choice, Text };
  /// What a number may be: min..max, or above min when min itself is refused.
  struct Range {
    double min = 0;
    double max = HUGE_VAL;  ///< HUGE_VAL: no bound but the type's (32-bit integers, finite numbers)
    bool above_min = false;
    double step = 0;  ///< > 0: the number must be a whole multiple of it
  };

  std::string name;
  Type type;
  std::string meaning;              ///< one line
  Range range;                      ///< Integer and Number
  std::vector<std::string> values;  ///< Flag and Choice: the names it takes
  std::function<std::string(const MachineConfig&)> get;
  std::function<void(MachineConfig&, const std::string&)>
      set;  ///< parses and checks the range; throws std::invalid_argument
  std::function<void(const MachineConfig&)>
      check;  ///< throws std::invalid_argument if out of range

  /// "an integer in 1..65536", "a number > 0", "true or false", "one of fast, clocked", "a name or
  /// a path".
  std::string accepted() const;
};
const std::vector<ConfigKey>& config_keys();

/// A named machine: keys set, in order, on top of MachineConfig{}. Each preset is declared once,
/// in presets(); `rtm render --preset`, a configuration file's `preset:`, a sweep's `preset:` and
/// docs/machine.md's table of how a preset differs from the defaults all read that declaration.
struct Preset {
  struct Override {
    std::string key, value;  ///< as set_config takes them, the value as the key prints it
    std::string why;         ///< one line: what in the paper (or which reading of it) says so
  };
  std::string name;
  std::string meaning;  ///< one line
  std::vector<Override> overrides;
};
const std::vector<Preset>& presets();

/// Sets one key from text; throws std::invalid_argument ("unknown key", "not a number", ...).
void set_config(MachineConfig& c, const std::string& key, const std::string& value);
/// Sets one key from `KEY=VALUE`, as `--set` gives it; throws std::invalid_argument.
void set_config_assignment(MachineConfig& c, const std::string& assignment);
/// Sets the keys of preset `name` and records it in c.preset. c must not have started from another
/// preset: one configuration has one starting point. Throws std::invalid_argument naming the
/// known presets.
void apply_preset(MachineConfig& c, const std::string& name);
/// Reads a YAML file holding one flat map of `key: value` pairs (the keys of config_keys()), and
/// optionally `preset: NAME`, which is applied first, wherever the file has it. Throws ConfigError.
void load_config_file(MachineConfig& c, const std::string& path);
/// The same from the file's text; `file_name` is for messages.
void parse_config(MachineConfig& c, const std::string& text, const std::string& file_name);
/// A YAML file load_config_file reads back as c: its preset, then one
/// `key: value  # meaning (accepted)` a line.
std::string describe_config(const MachineConfig& c);
/// Each key on which c differs from the preset it started from (c.preset on MachineConfig{}), as
/// `key=value`, in config_keys()' order: with the preset, what names c.
std::vector<std::string> keys_apart_from_preset(const MachineConfig& c);
/// docs/machine.md's table of every key: name, default, what it accepts, meaning.
std::string config_keys_markdown();
/// docs/machine.md's table of every key on which preset `name` differs from the defaults: both
/// values and why. Throws std::invalid_argument for an unknown preset.
std::string preset_markdown(const std::string& name);

const char* to_string(Partition p);
const char* to_string(Timing t);
const char* to_string(Precision p);
const char* to_string(FlowControl f);
const char* to_string(MemoryArbitration a);
const char* to_string(MachineConfig::RayGeneration g);
const char* to_string(MachineConfig::Voxelisation v);
const char* to_string(MachineConfig::Gather g);
const char* to_string(MachineConfig::LinkTopology t);
const char* to_string(MachineConfig::TreeForwarding f);
const char* to_string(MachineConfig::Arbitration a);
const char* to_string(MachineConfig::PeSimulation p);
const char* to_string(MachineConfig::SearchWalk w);
const char* to_string(MachineConfig::MacSchedule m);
const char* to_string(MachineConfig::UnitPrecision p);
const char* to_string(HitRefine r);
const char* to_string(NormalInterpolation n);
const char* to_string(Discriminant d);
const char* to_string(CoefScaling s);
const char* to_string(OriginLatch o);

}  // namespace rtm
