#include "config/config.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "config/nearest_name.h"

namespace rtm {
namespace {

using M = MachineConfig;
using Range = ConfigKey::Range;

/// Each enum's value names, written once: to_string, parsing and the documentation read them.
template <class E>
struct EnumNames;
template <>
struct EnumNames<Partition> {
  static constexpr std::pair<Partition, const char*> all[] = {{Partition::Scanlines, "scanlines"},
                                                              {Partition::Blocks, "blocks"},
                                                              {Partition::Strips, "strips"},
                                                              {Partition::Pixels, "pixels"},
                                                              {Partition::Dynamic, "dynamic"}};
};
template <>
struct EnumNames<Timing> {
  static constexpr std::pair<Timing, const char*> all[] = {{Timing::Fast, "fast"},
                                                           {Timing::Clocked, "clocked"}};
};
template <>
struct EnumNames<Precision> {
  static constexpr std::pair<Precision, const char*> all[] = {{Precision::Fp32, "fp32"},
                                                              {Precision::Fp64, "fp64"}};
};
template <>
struct EnumNames<M::UnitPrecision> {
  static constexpr std::pair<M::UnitPrecision, const char*> all[] = {
      {M::UnitPrecision::Precision, "precision"},
      {M::UnitPrecision::Fp32, "fp32"},
      {M::UnitPrecision::Fp64, "fp64"}};
};
template <>
struct EnumNames<HitRefine> {
  static constexpr std::pair<HitRefine, const char*> all[] = {{HitRefine::None, "none"},
                                                              {HitRefine::Newton, "newton"}};
};
template <>
struct EnumNames<NormalInterpolation> {
  static constexpr std::pair<NormalInterpolation, const char*> all[] = {
      {NormalInterpolation::Flat, "flat"}, {NormalInterpolation::Barycentric, "barycentric"}};
};
template <>
struct EnumNames<FlowControl> {
  static constexpr std::pair<FlowControl, const char*> all[] = {{FlowControl::Credits, "credits"},
                                                                {FlowControl::None, "none"}};
};
template <>
struct EnumNames<MemoryArbitration> {
  static constexpr std::pair<MemoryArbitration, const char*> all[] = {
      {MemoryArbitration::RoundRobin, "round_robin"},
      {MemoryArbitration::FixedPriority, "fixed_priority"},
      {MemoryArbitration::Fcfs, "fcfs"}};
};
template <>
struct EnumNames<Discriminant> {
  static constexpr std::pair<Discriminant, const char*> all[] = {{Discriminant::Plain, "plain"},
                                                                 {Discriminant::Fma, "fma"}};
};
template <>
struct EnumNames<CoefScaling> {
  static constexpr std::pair<CoefScaling, const char*> all[] = {{CoefScaling::None, "none"},
                                                                {CoefScaling::Pow2, "pow2"}};
};
template <>
struct EnumNames<OriginLatch> {
  static constexpr std::pair<OriginLatch, const char*> all[] = {{OriginLatch::Machine, "machine"},
                                                                {OriginLatch::Wide, "wide"},
                                                                {OriginLatch::Advance, "advance"}};
};
template <>
struct EnumNames<PeFrame> {
  static constexpr std::pair<PeFrame, const char*> all[] = {{PeFrame::World, "world"},
                                                            {PeFrame::Grid, "grid"}};
};
template <>
struct EnumNames<M::MacSchedule> {
  static constexpr std::pair<M::MacSchedule, const char*> all[] = {
      {M::MacSchedule::Full, "full"}, {M::MacSchedule::Sparse, "sparse"}};
};
template <>
struct EnumNames<M::SearchWalk> {
  static constexpr std::pair<M::SearchWalk, const char*> all[] = {
      {M::SearchWalk::PerVoxel, "per_voxel"}, {M::SearchWalk::UntilOccupied, "until_occupied"}};
};
template <>
struct EnumNames<M::RayGeneration> {
  static constexpr std::pair<M::RayGeneration, const char*> all[] = {
      {M::RayGeneration::Host, "host"}, {M::RayGeneration::Pe, "pe"}};
};
template <>
struct EnumNames<M::Voxelisation> {
  static constexpr std::pair<M::Voxelisation, const char*> all[] = {{M::Voxelisation::Host, "host"},
                                                                    {M::Voxelisation::Pe, "pe"}};
};
template <>
struct EnumNames<M::LinkTopology> {
  static constexpr std::pair<M::LinkTopology, const char*> all[] = {
      {M::LinkTopology::Serial, "serial"},
      {M::LinkTopology::Bus, "bus"},
      {M::LinkTopology::Star, "star"},
      {M::LinkTopology::Tree, "tree"}};
};
template <>
struct EnumNames<M::TreeForwarding> {
  static constexpr std::pair<M::TreeForwarding, const char*> all[] = {
      {M::TreeForwarding::StoreAndForward, "store_and_forward"},
      {M::TreeForwarding::CutThrough, "cut_through"}};
};
template <>
struct EnumNames<M::Gather> {
  static constexpr std::pair<M::Gather, const char*> all[] = {
      {M::Gather::AfterAll, "after_all"},
      {M::Gather::AsFinished, "as_finished"},
      {M::Gather::Streamed, "streamed"}};
};
template <>
struct EnumNames<M::Arbitration> {
  static constexpr std::pair<M::Arbitration, const char*> all[] = {
      {M::Arbitration::Kernel, "kernel"}, {M::Arbitration::Ranked, "ranked"}};
};
template <>
struct EnumNames<M::PeSimulation> {
  static constexpr std::pair<M::PeSimulation, const char*> all[] = {
      {M::PeSimulation::Auto, "auto"}, {M::PeSimulation::Modules, "modules"}};
};

template <class E>
const char* name_of(E e) {
  for (const auto& [value, name] : EnumNames<E>::all)
    if (value == e) return name;
  return "?";
}

[[noreturn]] void bad(const std::string& key, const std::string& why) {
  throw std::invalid_argument(key + ": " + why);
}

/// The six digits the statistics have always shown, or as many more as reading it back needs.
std::string fmt(double x) {
  for (int digits = 6;; ++digits) {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    if (digits == 17 || std::strtod(s.str().c_str(), nullptr) == x) return s.str();
  }
}

/// A PE's local memory in bytes: the most whole MiB a 32-bit integer key holds (2047 MiB; a
/// 16384x16384 frame needs 11.8 GB of rays and frame buffer, so eight PEs or more).
constexpr double kMaxLocalMemoryBytes = 2047.0 * (1 << 20);
Range from(double min, double max = HUGE_VAL) { return {min, max, false, 0}; }
Range from(double min, double max, double step) { return {min, max, false, step}; }

bool whole_steps(const Range& r, double x) {
  if (!(r.step > 0)) return true;
  const double q = x / r.step;  // 0.3 / 0.001 is 299.99999999999994: a multiple within rounding
  return std::fabs(q - std::round(q)) <= 1e-9 * std::max(1.0, std::fabs(q));
}

bool in(const Range& r, double x) {
  return (r.above_min ? x > r.min : x >= r.min) && x <= r.max && whole_steps(r, x);
}

ConfigKey int_key(const char* name, const char* meaning, int M::*m, Range r) {
  ConfigKey k{name, ConfigKey::Type::Integer, meaning, r, {}, {}, {}, {}};
  auto check = [name, r, expected = k.accepted()](long x, const std::string& shown) {
    if (!in(r, double(x))) bad(name, "expected " + expected + ", got " + shown);
  };
  k.get = [m](const M& c) { return std::to_string(c.*m); };
  k.set = [m, name, check](M& c, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end) bad(name, "expected an integer, got '" + v + "'");
    // Past 32 bits is not the key's range but the type's, as non-finite is for a number.
    if (errno == ERANGE || x < INT_MIN || x > INT_MAX)
      bad(name, "expected a 32-bit integer, got '" + v + "'");
    check(x, v);
    c.*m = int(x);
  };
  k.check = [m, check](const M& c) { check(c.*m, std::to_string(c.*m)); };
  return k;
}

ConfigKey double_key(const char* name, const char* meaning, double M::*m, Range r) {
  ConfigKey k{name, ConfigKey::Type::Number, meaning, r, {}, {}, {}, {}};
  auto check = [name, r, expected = k.accepted()](double x, const std::string& shown) {
    if (!in(r, x)) bad(name, "expected " + expected + ", got " + shown);
  };
  k.get = [m](const M& c) { return fmt(c.*m); };
  k.set = [m, name, check](M& c, const std::string& v) {
    // strtod, not stod: a number too small for a normal double is still a number (and out of
    // every key's range), not a parse error.
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || end == v.c_str() || std::isspace(static_cast<unsigned char>(v[0])))
      bad(name, "expected a number, got '" + v + "'");
    if (*end || !std::isfinite(x)) bad(name, "expected a finite number, got '" + v + "'");
    check(x, v);
    c.*m = x;
  };
  k.check = [m, check](const M& c) { check(c.*m, fmt(c.*m)); };
  return k;
}

ConfigKey bool_key(const char* name, const char* meaning, bool M::*m) {
  ConfigKey k{name, ConfigKey::Type::Flag, meaning, {}, {"true", "false"}, {}, {}, {}};
  k.get = [m](const M& c) { return std::string(c.*m ? "true" : "false"); };
  k.set = [m, name](M& c, const std::string& v) {
    if (v == "true" || v == "1" || v == "yes" || v == "on")
      c.*m = true;
    else if (v == "false" || v == "0" || v == "no" || v == "off")
      c.*m = false;
    else
      bad(name, "expected true or false, got '" + v + "'");
  };
  k.check = [](const M&) {};
  return k;
}

template <class E>
ConfigKey enum_key(const char* name, const char* meaning, E M::*m) {
  ConfigKey k{name, ConfigKey::Type::Choice, meaning, {}, {}, {}, {}, {}};
  for (const auto& [value, text] : EnumNames<E>::all) k.values.push_back(text);
  k.get = [m](const M& c) { return std::string(name_of(c.*m)); };
  k.set = [m, name, expected = k.accepted()](M& c, const std::string& v) {
    for (const auto& [value, text] : EnumNames<E>::all)
      if (v == text) {
        c.*m = value;
        return;
      }
    bad(name, "expected " + expected + ", got '" + v + "'");
  };
  k.check = [](const M&) {};
  return k;
}

/// A name or a file's path, as a plain YAML scalar reads it back: no spaces, quotes or '#'.
ConfigKey text_key(const char* name, const char* meaning, std::string M::*m) {
  ConfigKey k{name, ConfigKey::Type::Text, meaning, {}, {}, {}, {}, {}};
  auto check = [name](const std::string& v) {
    const bool plain = !v.empty() && v[0] != '-' && std::all_of(v.begin(), v.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) ||
             std::string("._-/+").find(ch) != std::string::npos;
    });
    if (!plain)
      bad(name,
          "expected a name or a path of letters, digits and . _ - / + (not starting with -), got "
          "'" +
              v + "'");
  };
  k.get = [m](const M& c) { return c.*m; };
  k.set = [m, check](M& c, const std::string& v) {
    check(v);
    c.*m = v;
  };
  k.check = [m, check](const M& c) { check(c.*m); };
  return k;
}

/// One cell of a Markdown table: a '|' would end it.
std::string cell(const std::string& text) {
  std::string s;
  for (char ch : text) s += ch == '|' ? std::string("\\|") : std::string(1, ch);
  return s;
}

}  // namespace

const char* to_string(Partition p) { return name_of(p); }
const char* to_string(Timing t) { return name_of(t); }
const char* to_string(Precision p) { return name_of(p); }
const char* to_string(FlowControl f) { return name_of(f); }
const char* to_string(MemoryArbitration a) { return name_of(a); }
const char* to_string(Discriminant d) { return name_of(d); }
const char* to_string(CoefScaling s) { return name_of(s); }
const char* to_string(OriginLatch o) { return name_of(o); }
const char* to_string(MachineConfig::MacSchedule m) { return name_of(m); }
const char* to_string(MachineConfig::UnitPrecision p) { return name_of(p); }
const char* to_string(HitRefine r) { return name_of(r); }
const char* to_string(NormalInterpolation n) { return name_of(n); }
const char* to_string(MachineConfig::SearchWalk w) { return name_of(w); }
const char* to_string(MachineConfig::RayGeneration g) { return name_of(g); }
const char* to_string(MachineConfig::Gather g) { return name_of(g); }
const char* to_string(MachineConfig::LinkTopology t) { return name_of(t); }
const char* to_string(MachineConfig::Voxelisation v) { return name_of(v); }
const char* to_string(MachineConfig::TreeForwarding f) { return name_of(f); }
const char* to_string(MachineConfig::Arbitration a) { return name_of(a); }
const char* to_string(MachineConfig::PeSimulation p) { return name_of(p); }

std::string ConfigKey::accepted() const {
  switch (type) {
    case Type::Integer:
    case Type::Number: {
      const std::string what = type == Type::Integer ? "an integer" : "a number";
      const std::string steps = range.step > 0 ? ", a multiple of " + fmt(range.step) : "";
      if (range.max != HUGE_VAL)
        return what + " in " + fmt(range.min) + ".." + fmt(range.max) + steps;
      return what + (range.above_min ? " > " : " >= ") + fmt(range.min);
    }
    case Type::Flag:
      return "true or false";
    case Type::Text:
      return "a name or a path";
    case Type::Choice: {
      std::string s = "one of ";
      for (const std::string& v : values) s += (&v == &values.front() ? "" : ", ") + v;
      return s;
    }
  }
  return "?";
}

// The machine's keys, each declared once. Their defaults are MachineConfig's initialisers; the
// ranges are what the model can represent and finish (docs/reliability.md, "Limits"):
//
// - Time. SystemC holds simulated time as a 64-bit count of picoseconds (its default resolution,
//   which rtm keeps): 2^64 ps is 213 days. A clock period is a whole number of ticks, at least two
//   (clocked timing's clock is high for half the period and low for the other half) and at most
//   1 µs (a 1 MHz machine; the paper's runs at tens of MHz), so even the slowest clock leaves room
//   for 4.6e12 cycles below the 2^62 ps horizon the machine's monitor enforces (machine.cpp),
//   whatever the frame adds up to. A link latency of at most 1 ms and a bandwidth of at least
//   1 kB/s put one transfer of 1 GB at 1e6 s (1e18 ps), inside the horizon; 1 PB/s is where a
//   transfer of any scene takes less than a tick. A frame whose times add up past the horizon
//   anyway (the slowest link carrying a huge frame's rays) is stopped with an error, never wrapped.
// - Cycles of one operation: at most 65536 (2^16). The longest the machine has is the root unit's
//   12; 65536 keeps every sum along a ray's path far inside 64 bits and keeps the PE engine, which
//   wakes every 8192 cycles, from spending more than a few wake-ups on one operation.
// - MAC latencies: at most 1024 pipeline stages (no multiplier or adder has more). The clocked MAC
//   steps every cycle of a test (28 add_latency + 2 mul_latency), so its wall time grows with them.
// - FIFO depths, the front buffer and loop credits: at most 65536 rays. Every FIFO is allocated
//   whole (the PE engine 4 bytes a place, a module one ray record a place) in every PE; the memory
//   budget (rtm render --max-memory) checks their total over all PEs before simulating.
// - PEs: at most 16384. Each PE is a SystemC thread (more with pe_simulation = modules), and each
//   thread's stack costs the process two memory maps; Linux's default limit of 65530 maps
//   (vm.max_map_count) holds about 32000 threads. rtm render refuses, before simulating, a
//   configuration whose threads the host's limit cannot hold.
// - tile and ray_block need not exceed the largest image (16384 a side); host_ports and
//   tree_fanout need not exceed the most PEs; scene_block need not exceed the most primitives
//   (2^24, the MAC's coefficient RAM's bound below).
// - Local memory timing (model/memory/, docs/memory.md): ports and banks at most 1024, each a
//   table of booked cycles (a PE has at most 323 requesters: 256 search units, 64 lanes, the front
//   buffer, shading, the host). The granule and the port width: at most 64 KiB. The latency, like
//   any operation, at most 65536 cycles, and at least 1: a request is then complete a cycle after
//   it is issued at the earliest, and its grant is known by then (the requests of its cycle are
//   resolved together).
// - The MAC's coefficient RAM: at most 2^24 primitives. It holds at most the primitives it has
//   seen, so a capacity above the scene's primitive count acts as that count: compulsory misses
//   only. The voxel cache: at most 1 GiB, more than the voxel data of the largest grid (2^24
//   voxels) with its lists; its tags are allocated whole (8 bytes a line).
// - frames: at most 1024. The simulator keeps every frame's pixels (the machine holds two frames'),
//   so a run's memory grows with them, and a steady state shows within a few frames.
constexpr int kMaxPes = 16384;
constexpr int kMaxFrames = 1024;
constexpr int kMaxImageSide = 16384;
constexpr int kMaxPixels = kMaxImageSide * kMaxImageSide;
constexpr double kTickNs = 0.001;
constexpr double kMinClockNs = 2 * kTickNs;
constexpr double kMaxClockNs = 1000;
constexpr int kMaxOpCycles = 65536;
constexpr int kMaxMacLatency = 1024;
constexpr int kMaxBufferRays = 65536;
constexpr double kMinBandwidthMbS = 0.001;
constexpr double kMaxBandwidthMbS = 1e9;
constexpr double kMaxLinkLatencyNs = 1e6;
constexpr int kMaxMemoryUnits = 1024;
constexpr int kMaxMemoryWidth = 65536;
constexpr int kMaxMacRamPrimitives = 1 << 24;
constexpr int kMaxVoxelCacheBytes = 1 << 30;

const std::vector<ConfigKey>& config_keys() {
  static const std::vector<ConfigKey> keys = {
      int_key("pes", "processing elements", &M::pes, from(1, kMaxPes)),
      enum_key(
          "partition",
          "screen partitioning: scanlines (row y to PE y mod N), blocks (tile x tile tiles "
          "dealt round robin), strips (contiguous bands), pixels (every N-th pixel of each "
          "row, rows sheared), dynamic (tile x tile tiles handed out on demand: a PE out of work "
          "asks the host for the next over the link)",
          &M::partition),
      int_key("tile", "tile edge in pixels (partition = blocks or dynamic)", &M::tile,
              from(1, kMaxImageSide)),
      enum_key("timing",
               "MAC model: fast (cycle-exact by formula) or clocked (a process on a clock)",
               &M::timing),
      enum_key("precision",
               "arithmetic of every datapath unit of a PE (the 3DDDA, the MAC, root unit and "
               "clips, shading), unless the unit's own key says otherwise; the host computes in "
               "fp64 (docs/numerics.md)",
               &M::precision),
      enum_key(
          "intersection_precision",
          "MAC, root unit and clip arithmetic: precision (as the precision key says), fp32 or fp64",
          &M::intersection_precision),
      enum_key("dda_precision",
               "search units' 3DDDA arithmetic (voxel planes, crossing times, window ends): "
               "precision (as the precision key says), fp32 or fp64",
               &M::dda_precision),
      enum_key(
          "shading_precision",
          "shading arithmetic (hit point, normal, light, reflection and refraction directions, "
          "spawned origins, contributions): precision (as the precision key says), fp32 or fp64",
          &M::shading_precision),
      enum_key("mac_schedule",
               "full (the paper's 6 + 12 + 10 products for every test) or sparse (each primitive's "
               "products with a zero coefficient word skipped: same sums, fewer cycles)",
               &M::mac_schedule),
      bool_key(
          "leave_out",
          "leave out the units, FIFOs and paths the scene cannot use (they are not elaborated)",
          &M::leave_out),
      bool_key("recentre",
               "coefficients relative to each primitive's centre, ray origin re-centred per test "
               "(false: world coefficients, as in the paper)",
               &M::recentre),
      enum_key("discriminant",
               "root unit's b^2 - 4ac: plain (two rounded products) or fma (difference of products "
               "with fused multiply-adds; fma_discriminant_cycles more latency; docs/numerics.md)",
               &M::discriminant),
      enum_key(
          "coef_scaling",
          "coefficient RAM image: none (the quadric's own coefficients, the paper) or pow2 (scaled "
          "by a power of two so the largest is in [1, 2): exact, keeps float32 in range)",
          &M::coef_scaling),
      enum_key("origin_latch",
               "ray origin into the V latches: machine (rounded to the MAC precision, then "
               "re-centred: the paper's latch), wide (re-centred in fp64, then rounded) or advance "
               "(wide, from the voxel's entry point; advance_cycles more latency)",
               &M::origin_latch),
      enum_key("hit_refine",
               "shading's hit point: none (at the root unit's t, as in the paper) or newton (one "
               "Newton step on the primitive's quadric in fp64 first; refine_cycles more shading "
               "latency per hit; docs/numerics.md)",
               &M::hit_refine),
      enum_key(
          "normal_interpolation",
          "the normal a triangle with vertex normals (NFF pp, a mesh file's) is lit with: flat "
          "(its plane's, as in the paper) or barycentric (the vertex normals weighted by the hit's "
          "barycentric coordinates, from the clip tests' edge values; interpolate_cycles more "
          "shading latency per such hit, 12 more words a triangle in the scene copy)",
          &M::normal_interpolation),
      enum_key("pe_frame",
               "the coordinates the PEs compute in: world (the scene's own, as in the paper) or "
               "grid (translated to the grid's corner and scaled by its longest edge, formed by "
               "the host in fp64: fp32 accuracy independent of where the scene is; "
               "host_frame_cycles per primitive, light and camera)",
               &M::pe_frame),
      double_key("clock_ns", "PE clock period, ns", &M::clock_ns,
                 from(kMinClockNs, kMaxClockNs, kTickNs)),
      int_key("search_units", "replicated 3DDDA units per PE (paper Fig. 1: four)",
              &M::search_units, from(1, kMaxUnitsOfAKind)),
      enum_key(
          "search_walk",
          "per_voxel (a ray in an empty voxel goes back to the front buffer, as in the paper) or "
          "until_occupied (the search unit steps on until an occupied voxel or the walk's end)",
          &M::search_walk),
      int_key("intersection_units", "MAC + root/sort lanes per PE (the paper has one)",
              &M::intersection_units, from(1, 64)),
      int_key("dda_step_cycles", "cycles for one 3DDDA step (compare and increment)",
              &M::dda_step_cycles, from(0, kMaxOpCycles)),
      int_key("mul_latency", "pipeline depth of each MAC multiplier", &M::mul_latency,
              from(1, kMaxMacLatency)),
      int_key("add_latency",
              "MAC adder latency (dependent accumulation issues one product per add_latency)",
              &M::add_latency, from(1, kMaxMacLatency)),
      int_key("root_latency",
              "root unit latency: discriminant, square root, two divisions (pipelined)",
              &M::root_latency, from(1, kMaxOpCycles)),
      int_key("fma_discriminant_cycles",
              "extra root unit latency with discriminant = fma (the dependent FMA stage)",
              &M::fma_discriminant_cycles, from(0, kMaxOpCycles)),
      int_key("advance_cycles",
              "extra root unit latency with origin_latch = advance (adding t_enter to the roots)",
              &M::advance_cycles, from(0, kMaxOpCycles)),
      int_key("refine_cycles",
              "extra shading latency per hit with hit_refine = newton (the hit point, Q and its "
              "gradient there, the slope and a division, in fp64)",
              &M::refine_cycles, from(0, kMaxOpCycles)),
      int_key("interpolate_cycles",
              "extra shading latency per hit on a triangle with vertex normals with "
              "normal_interpolation = barycentric (3 weights, 9 products and 6 adds for the "
              "weighted normal, its normalisation)",
              &M::interpolate_cycles, from(0, kMaxOpCycles)),
      int_key("clip_cycles", "cycles per clip half-space test (3 products and an add)",
              &M::clip_cycles, from(0, kMaxOpCycles)),
      int_key("sort_cycles", "cycles per primitive result merged into the nearest-hit register",
              &M::sort_cycles, from(0, kMaxOpCycles)),
      int_key("shade_cycles",
              "shading cycles per ray: normal, ambient term and frame-buffer update",
              &M::shade_cycles, from(0, kMaxOpCycles)),
      int_key("spawn_cycles", "cycles to generate one shadow or branch ray", &M::spawn_cycles,
              from(0, kMaxOpCycles)),
      int_key("accumulate_cycles",
              "cycles to add a shadow ray's or the background's brightness to the frame buffer",
              &M::accumulate_cycles, from(0, kMaxOpCycles)),
      int_key("fb_dispatch_cycles", "cycles for the front buffer to hand out one ray",
              &M::fb_dispatch_cycles, from(1, kMaxOpCycles)),
      int_key("dispatch_interval",
              "front buffer: cycles between rays handed out (0: unpipelined, each ray's own "
              "dispatch time)",
              &M::dispatch_interval, from(0, kMaxOpCycles)),
      int_key("search_interval",
              "search unit: cycles between rays accepted, per 3DDDA pass (0: unpipelined, each "
              "ray's own step and read time)",
              &M::search_interval, from(0, kMaxOpCycles)),
      bool_key("mac_streaming",
               "MAC: the next voxel job's products issue while the previous job's drain (false: "
               "the MAC empties between jobs)",
               &M::mac_streaming),
      int_key("root_interval",
              "root unit: cycles between primitives accepted (0: unpipelined, one voxel's results "
              "at a time)",
              &M::root_interval, from(0, kMaxOpCycles)),
      int_key("shade_interval",
              "shading unit: cycles between rays accepted (0: unpipelined, each ray's own shading "
              "time)",
              &M::shade_interval, from(0, kMaxOpCycles)),
      int_key("front_buffer_capacity",
              "on-chip front buffer size in rays (overflow spills to local memory)",
              &M::front_buffer_capacity, from(1, kMaxBufferRays)),
      int_key("local_memory_bytes",
              "each PE's local memory: the scene copy, its primary rays and frame buffer must fit "
              "(else the render is refused); the rest is the front buffer's spill area",
              &M::local_memory_bytes, from(1024, kMaxLocalMemoryBytes)),
      int_key("search_fifo_depth", "FIFO depth, front buffer -> search units",
              &M::search_fifo_depth, from(1, kMaxBufferRays)),
      int_key("intersect_fifo_depth", "FIFO depth, search -> intersection",
              &M::intersect_fifo_depth, from(1, kMaxBufferRays)),
      int_key("root_fifo_depth", "FIFO depth, MAC -> root unit / sort", &M::root_fifo_depth,
              from(1, kMaxBufferRays)),
      int_key("shade_fifo_depth", "FIFO depth, search/intersection -> shading",
              &M::shade_fifo_depth, from(1, kMaxBufferRays)),
      int_key("feedback_fifo_depth", "FIFO depth of each path back into the front buffer",
              &M::feedback_fifo_depth, from(1, kMaxBufferRays)),
      enum_key(
          "flow_control",
          "credits (deadlock-free) or none (the front buffer hands out rays whenever the search "
          "FIFO has room, as in the paper; the loop can deadlock, and the simulator reports it)",
          &M::flow_control),
      int_key("loop_credits",
              "rays allowed past the front buffer at once (0: the largest safe value); at most the "
              "smallest FIFO depth past the front buffer",
              &M::loop_credits, from(0, kMaxBufferRays)),
      int_key("memory_ports",
              "local memory ports, each moving memory_bytes_per_cycle a cycle (0: as many as the "
              "requests need, no port contention)",
              &M::memory_ports, from(0, kMaxMemoryUnits)),
      int_key("memory_banks",
              "local memory banks, interleaved every memory_interleave_bytes; a bank serves one "
              "beat a cycle (0: no bank conflicts)",
              &M::memory_banks, from(0, kMaxMemoryUnits)),
      int_key("memory_interleave_bytes",
              "local memory interleave granule: consecutive granules lie in consecutive banks",
              &M::memory_interleave_bytes, from(1, kMaxMemoryWidth)),
      int_key("memory_latency",
              "local memory access latency: cycles from a request's start to its first beat's data",
              &M::memory_latency, from(1, kMaxOpCycles)),
      int_key("memory_bytes_per_cycle",
              "bytes a local memory port moves a cycle: a request of B bytes takes ceil(B / this) "
              "beats, one a cycle",
              &M::memory_bytes_per_cycle, from(1, kMaxMemoryWidth)),
      enum_key("memory_arbitration",
               "order of the local memory requests issued in one cycle: round_robin (rotating by "
               "requester), fixed_priority (lower requester first) or fcfs (in the order made); "
               "older requests always go first",
               &M::memory_arbitration),
      int_key("mac_ram_primitives",
              "primitives whose coefficients each MAC's coefficient RAM holds, least recently used "
              "replaced, a miss loading them from local memory (0: every primitive's, loaded "
              "before rendering)",
              &M::mac_ram_primitives, from(0, kMaxMacRamPrimitives)),
      int_key("voxel_cache_bytes",
              "bytes of a direct-mapped cache of voxel data (entries and primitive lists) in front "
              "of local memory, lines of memory_bytes_per_cycle (0: none)",
              &M::voxel_cache_bytes, from(0, kMaxVoxelCacheBytes)),
      enum_key("ray_generation",
               "who generates primary rays: host (the paper: generated and sent by the host) or pe "
               "(each PE from the camera, pe_ray_cycles each, in its front buffer)",
               &M::ray_generation),
      int_key("pe_ray_cycles", "PE cycles to generate one primary ray (ray_generation = pe)",
              &M::pe_ray_cycles, from(0, kMaxOpCycles)),
      double_key("host_clock_ns", "host clock period, ns", &M::host_clock_ns,
                 from(kMinClockNs, kMaxClockNs, kTickNs)),
      int_key("host_voxel_cycles", "host cycles per primitive reference registered in a voxel",
              &M::host_voxel_cycles, from(0, kMaxOpCycles)),
      enum_key(
          "voxelisation",
          "who builds the voxel data: host (the paper: the host builds it, host_voxel_cycles a "
          "reference, and sends it with the scene) or pe (the scene goes without it and each "
          "PE builds its own copy once the scene is in, pe_voxel_cycles a reference and the "
          "voxel offsets written at memory_bytes_per_cycle, before its first ray)",
          &M::voxelisation),
      int_key("pe_voxel_cycles",
              "PE cycles per primitive reference registered in a voxel (voxelisation = pe)",
              &M::pe_voxel_cycles, from(0, kMaxOpCycles)),
      int_key("host_ray_cycles", "host cycles per primary ray generated", &M::host_ray_cycles,
              from(0, kMaxOpCycles)),
      int_key("host_frame_cycles",
              "host cycles per primitive, light and camera moved into the grid's frame (pe_frame = "
              "grid)",
              &M::host_frame_cycles, from(0, kMaxOpCycles)),
      double_key("link_bandwidth_mb_s", "host <-> PE link bandwidth, MB/s", &M::link_bandwidth_mb_s,
                 from(kMinBandwidthMbS, kMaxBandwidthMbS)),
      double_key("link_latency_ns",
                 "host <-> PE link latency per transaction, ns (per hop on a tree)",
                 &M::link_latency_ns, from(0, kMaxLinkLatencyNs)),
      enum_key("link_topology",
               "host <-> PE interconnect: serial (one link, one transfer at a time: the model's "
               "original link), bus (one shared medium: one transfer at a time, a broadcast "
               "reaches every PE), star (a link per PE, the host drives host_ports of them at "
               "once) or tree (a link from each PE to its parent: the host drives host_ports "
               "children, each PE forwards to tree_fanout children as tree_forwarding says)",
               &M::link_topology),
      int_key("host_ports",
              "links the host drives at once: on a star its ports onto the PEs' links, on a tree "
              "its children (serial and bus: one medium, so one)",
              &M::host_ports, from(1, kMaxPes)),
      int_key("tree_fanout", "children of each PE on a tree (link_topology = tree; 1: a chain)",
              &M::tree_fanout, from(1, kMaxPes)),
      enum_key("tree_forwarding",
               "how a tree's PE passes a transfer on (link_topology = tree): store_and_forward "
               "(once it holds all of it) or cut_through (once the header is in: each further hop "
               "starts link_latency_ns after the one before)",
               &M::tree_forwarding),
      bool_key("broadcast",
               "one scene transfer reaches every PE (else one transfer per PE): on serial and bus "
               "one transfer on the medium, on a tree forwarded from parent to children, on a star "
               "only with host_ports >= pes (every link driven at once)",
               &M::broadcast),
      int_key("ray_block", "primary rays per host -> PE transfer (0: all of a PE's rays at once)",
              &M::ray_block, from(0, kMaxPixels)),
      int_key("scene_block",
              "primitives per host -> PE scene transfer (0: the whole scene in one transfer once "
              "it is prepared): the host frames a block (pe_frame = grid) and sends it while it "
              "frames the next, and a PE voxelising (voxelisation = pe) registers each block's "
              "references as the block arrives; lights and materials go with the first block, the "
              "host's voxel data after the last",
              &M::scene_block, from(0, kMaxMacRamPrimitives)),
      int_key("frames",
              "frames rendered in one run, the same frame each time, its scene prepared and sent "
              "anew as an animation's would be: the host prepares frame k+1 (and sends it, into "
              "a second scene copy in each local memory) while the PEs render frame k, and a PE "
              "starts a frame once it has finished the one before; the statistics give each "
              "frame's time and the steady state's (partition static, ray_block 0)",
              &M::frames, from(1, kMaxFrames)),
      enum_key("arbitration",
               "same-cycle order: ranked (a fixed order by unit, independent of the kernel: "
               "clocked and fast timing give the same cycles on any frame) or kernel (SystemC's "
               "event queue decides)",
               &M::arbitration),
      enum_key("pe_simulation",
               "auto (each PE's pipeline on the PE engine where the configuration allows: the same "
               "cycles, several times faster) or modules (one SystemC process per unit)",
               &M::pe_simulation),
      enum_key("gather",
               "after_all (the host reads the frame buffers once every PE is done, as in the "
               "paper), as_finished (each PE's as soon as it is done) or streamed (each PE sends "
               "its frame buffer while it renders, gather_block pixels a transfer, each block once "
               "its pixels are finished)",
               &M::gather),
      int_key("gather_block",
              "pixel slots per transfer of a streamed gather (gather = streamed), with a 4-byte "
              "header naming the block",
              &M::gather_block, from(1, kMaxPixels)),
      text_key("tech",
               "the technology the cost is figured in: 45nm (built in) or a technology file "
               "(docs/cost.md)",
               &M::tech),
  };
  return keys;
}

// The presets, each declared once: a name, what it means, and the keys it sets on top of
// MachineConfig{}, each with why. `paper` also sets keys whose default is the paper's today, so
// that it stays the paper's machine when a default changes; docs/machine.md's table shows only
// the keys where it differs, and its "Presets" section says which readings are the model's.
const std::vector<Preset>& presets() {
  static const std::vector<Preset> all = {
      {kDefaultPreset,
       "the model's defaults: the paper's structure, with the arithmetic and the MAC schedule the "
       "measurements chose",
       {}},
      {"paper",
       "the paper's machine: what Gwun, Murakami and Tomita describe and, where they are silent, "
       "the most literal reading",
       {
           {"partition", "scanlines",
            "silent (§2: pixel-parallel screen partitioning, no scheme named): rows dealt to the "
            "PEs in turn"},
           {"precision", "fp32",
            "silent (§5.2: floating-point multipliers and adder, no width given): single "
            "precision"},
           {"intersection_precision", "precision",
            "silent: one floating-point width for the whole PE"},
           {"dda_precision", "precision",
            "silent (§4: the 3DDDA's arithmetic is not described): the PE's one floating-point "
            "width"},
           {"shading_precision", "precision",
            "silent (§6: the shading arithmetic is not described): the PE's one floating-point "
            "width"},
           {"hit_refine", "none",
            "§6 shades the point the intersection stage found; no refinement is described"},
           {"normal_interpolation", "flat",
            "§6: the shading stage computes one normal per primitive, the surface's; vertex "
            "normals are not described"},
           {"pe_frame", "world",
            "§3.2, §5.2: the host sends the primitives, the voxel data and the rays as the scene "
            "gives them, and the RAM and latches hold world coordinates; no change of coordinates "
            "is described"},
           {"mac_schedule", "full",
            "§5.2: the adder accumulates 6 products for α, 12 for β and 10 for γ, for every "
            "primitive"},
           {"leave_out", "false",
            "§3.1, §6: one machine for every scene: each PE has its shadow and branch-ray units "
            "whether the scene uses them or not"},
           {"recentre", "false",
            "§5.2: the RAM holds the quadric's coefficients and the latches the ray's V, both in "
            "world space"},
           {"discriminant", "plain",
            "silent (the root unit is not described): b^2 - 4ac as written, two rounded products"},
           {"coef_scaling", "none",
            "§5.2: the RAM holds the quadric's own coefficients A ... J, unscaled"},
           {"origin_latch", "machine",
            "§5.2: the latches hold V in the MAC's own floating point (wide forms V - c in fp64 "
            "first; with world coefficients c = 0 and the two give the same bits)"},
           {"search_units", "4", "§4.1, Fig. 1: four search units"},
           {"search_walk", "per_voxel",
            "§4.2: a ray in an empty voxel goes back to the front buffer"},
           {"intersection_units", "1", "§5, Fig. 1: one intersection stage with one MAC"},
           {"mul_latency", "1",
            "§5.2: two multipliers and an adder chained as a 3-stage pipeline: a cycle a stage"},
           {"add_latency", "1",
            "§5.2: two multipliers and an adder chained as a 3-stage pipeline: a cycle a stage"},
           {"flow_control", "credits",
            "silent (what keeps the feedback loop from deadlocking is left open): credits, which "
            "change no ray's work; without them gears-1 at 64x64 deadlocks"},
           {"ray_generation", "host", "§3.2: the host generates one primary ray per pixel"},
           {"voxelisation", "host",
            "§3.2: the host generates the voxel data and transfers it to the PEs"},
           {"link_topology", "serial",
            "silent (§3.1: the PEs are the host's back-end; §3.2: the host transfers the results "
            "to each PE): one link, PE after PE"},
           {"host_ports", "1",
            "silent (no interconnect is described): the host drives one transfer at a time"},
           {"tree_forwarding", "store_and_forward",
            "silent (no interconnect is described): a PE passes on what its local memory holds, "
            "as a processor or DMA engine would"},
           {"broadcast", "false",
            "§3.1-3.2: the host transfers the data to every PE, each into its own local memory"},
           {"ray_block", "0",
            "§3.2: pre-processing first, then the transfer: every ray is generated before any is "
            "sent"},
           {"scene_block", "0",
            "§3.2: pre-processing first, then the transfer: the whole scene is prepared before any "
            "of it is sent"},
           {"gather", "after_all",
            "silent (frame-buffer gathering is left open): the host reads the frame buffers once "
            "every PE is done"},
           {"dispatch_interval", "1",
            "§2 ③, §4.2: every stage is pipelined inside: the front buffer hands out a ray a "
            "cycle"},
           {"search_interval", "1",
            "§2 ③, §4.2: the search units are pipelined (「これらはパイプライン化される」): a new "
            "ray every cycle"},
           {"mac_streaming", "true",
            "§5.2: the MAC is a pipeline of two multipliers and an adder: it does not drain "
            "between voxels"},
           {"root_interval", "1",
            "§2 ③, §5.1: the root unit and sort are pipelined: a primitive a cycle"},
           {"shade_interval", "1", "§2 ③, §6: the shading stage is pipelined: a ray a cycle"},
           {"memory_ports", "1",
            "silent (§3.1: each PE has its own local memory, its timing not given): one memory, "
            "one port every unit shares"},
           {"memory_banks", "1", "silent: one memory, not interleaved"},
           {"memory_interleave_bytes", "4",
            "silent: a 32-bit word (with one bank it changes nothing)"},
           {"memory_latency", "1",
            "silent: a word in the cycle after its address, so a voxel entry (two words) takes 2 "
            "cycles, as under the default"},
           {"memory_bytes_per_cycle", "4",
            "silent: one 32-bit word a cycle, the word of the machine's single precision"},
           {"memory_arbitration", "round_robin",
            "silent (how the units share the memory is not described): round robin, the plain fair "
            "arbiter"},
           {"mac_ram_primitives", "0",
            "§5.2: the RAM holds the primitives' quadric coefficients: every primitive's, loaded "
            "before rendering"},
           {"voxel_cache_bytes", "0",
            "§3.1: the voxel data is in the local memory; no cache is described"},
       }},
  };
  return all;
}

namespace {

/// "one of default, paper"
std::string preset_names() {
  std::string s;
  for (const Preset& p : presets()) s += (s.empty() ? "one of " : ", ") + p.name;
  return s;
}

const Preset& find_preset(const std::string& name) {
  for (const Preset& p : presets())
    if (p.name == name) return p;
  bad("preset", "expected " + preset_names() + ", got '" + name + "'");
}

}  // namespace

namespace {

/// Keys that were constants the local memory's timing now models, and what sets that time now.
struct RemovedKey {
  const char* name;
  const char* replacement;
};
constexpr RemovedKey kRemovedKeys[] = {
    {"voxel_read_cycles",
     "a voxel entry's 8 bytes take the local memory's time: memory_latency, "
     "memory_bytes_per_cycle"},
    {"coef_load_cycles",
     "a coefficient RAM miss loads the record in the local memory's time (mac_ram_primitives: 0 "
     "holds every primitive, no loads)"},
    {"spill_cycles",
     "a spilled ray's 60 bytes take the local memory's time: memory_latency, "
     "memory_bytes_per_cycle"},
};

}  // namespace

void set_config(MachineConfig& c, const std::string& key, const std::string& value) {
  for (const ConfigKey& k : config_keys())
    if (k.name == key) return k.set(c, value);
  if (key == "preset")
    bad(key,
        "not a key but where the keys start: --preset NAME, or preset: NAME in a --config file");
  for (const RemovedKey& r : kRemovedKeys)
    if (key == r.name)
      bad(key, std::string("no longer a key: ") + r.replacement +
                   " (docs/memory.md; rtm config lists the keys)");
  std::vector<std::string> names;
  for (const ConfigKey& k : config_keys()) names.push_back(k.name);
  const std::string near = nearest_name(key, names);
  bad(key, "unknown machine configuration key" +
               (near.empty() ? "" : "; did you mean " + near + "?") + " (rtm config lists them)");
}

void set_config_assignment(MachineConfig& c, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("expected KEY=VALUE, got '" + assignment + "'");
  set_config(c, assignment.substr(0, eq), assignment.substr(eq + 1));
}

void apply_preset(MachineConfig& c, const std::string& name) {
  const Preset& p = find_preset(name);
  if (c.preset != kDefaultPreset && c.preset != name)
    bad("preset",
        "'" + name + "' after '" + c.preset + "': a configuration starts from one preset");
  for (const Preset::Override& o : p.overrides) set_config(c, o.key, o.value);
  c.preset = name;
}

void load_config_file(MachineConfig& c, const std::string& path) {
  std::ifstream f(path);
  if (!f) throw ConfigError(path, 0, "cannot read the configuration file");
  std::stringstream text;
  text << f.rdbuf();
  parse_config(c, text.str(), path);
}

void parse_config(MachineConfig& c, const std::string& text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line + 1, e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw ConfigError(path, root.Mark().line + 1, "expected a map of key: value");
  // The preset is what the other keys change, so it goes first, wherever the file has it.
  for (const bool preset_pass : {true, false})
    for (const auto& kv : root) {
      const std::string& key = kv.first.Scalar();
      if ((key == "preset") != preset_pass) continue;
      const int line = kv.first.Mark().line + 1;
      if (!kv.second.IsScalar()) throw ConfigError(path, line, key + ": expected a single value");
      try {
        if (preset_pass)
          apply_preset(c, kv.second.Scalar());
        else
          set_config(c, key, kv.second.Scalar());
      } catch (const std::invalid_argument& e) {
        throw ConfigError(path, line, e.what());
      }
    }
}

std::string describe_config(const MachineConfig& c) {
  std::vector<std::array<std::string, 3>> lines = {
      {"preset: " + c.preset, "the preset the keys below start from, applied first",
       preset_names()}};
  for (const ConfigKey& k : config_keys())
    lines.push_back({k.name + ": " + k.get(c), k.meaning, k.accepted()});
  size_t width = 0;
  for (const auto& l : lines) width = std::max(width, l[0].size());
  std::ostringstream s;
  s << "# rtm machine configuration (docs/machine.md): key: value  # meaning (what it accepts)\n"
       "# rtm render --config FILE reads it back.\n";
  // A YAML comment runs to the end of the line, so any one-line meaning can follow the value.
  for (const auto& [kv, meaning, accepted] : lines)
    s << kv << std::string(width - kv.size() + 2, ' ') << "# " << meaning << " (" << accepted
      << ")\n";
  return s.str();
}

std::string config_keys_markdown() {
  const MachineConfig defaults;
  std::ostringstream s;
  s << "| key | default | accepts | meaning |\n|---|---|---|---|\n";
  for (const ConfigKey& k : config_keys())
    s << "| `" << k.name << "` | " << cell(k.get(defaults)) << " | " << cell(k.accepted()) << " | "
      << cell(k.meaning) << " |\n";
  return s.str();
}

std::vector<std::string> keys_apart_from_preset(const MachineConfig& c) {
  MachineConfig start;
  apply_preset(start, c.preset);
  std::vector<std::string> apart;
  for (const ConfigKey& k : config_keys())
    if (k.get(c) != k.get(start)) apart.push_back(k.name + "=" + k.get(c));
  return apart;
}

std::string preset_markdown(const std::string& name) {
  const Preset& p = find_preset(name);
  const MachineConfig defaults;
  MachineConfig preset;
  apply_preset(preset, name);
  auto why = [&](const std::string& key) {
    for (const Preset::Override& o : p.overrides)
      if (o.key == key) return o.why;
    return std::string();
  };
  std::ostringstream s;
  s << "| key | " << kDefaultPreset << " | " << name << " | why |\n|---|---|---|---|\n";
  for (const ConfigKey& k : config_keys())
    if (k.get(preset) != k.get(defaults))
      s << "| `" << k.name << "` | " << cell(k.get(defaults)) << " | " << cell(k.get(preset))
        << " | " << cell(why(k.name)) << " |\n";
  return s.str();
}

int MachineConfig::safe_credits() const {
  return std::min({search_fifo_depth, intersect_fifo_depth, root_fifo_depth, shade_fifo_depth});
}

void MachineConfig::validate() const {
  for (const ConfigKey& k : config_keys()) k.check(*this);
  if (broadcast && link_topology == LinkTopology::Star && host_ports < pes)
    bad("broadcast", "true with link_topology = star needs host_ports >= pes (" +
                         std::to_string(host_ports) + " < " + std::to_string(pes) +
                         "): a star's link reaches one PE, so one transfer reaches every PE only "
                         "when the host drives every link at once; broadcast = false sends a copy "
                         "down each link, "
                         "host_ports at a time");
  if (partition == Partition::Dynamic && ray_block > 0)
    bad("ray_block", std::to_string(ray_block) +
                         " with partition = dynamic: a dynamic partition sends a tile's rays as "
                         "the PE asks for it, so ray_block must be 0");
  if (frames > 1 && partition == Partition::Dynamic)
    bad("frames", std::to_string(frames) +
                      " with partition = dynamic: a run of several frames deals each PE the same "
                      "pixels every frame, so the partition must be static");
  if (frames > 1 && ray_block > 0)
    bad("frames", std::to_string(frames) + " with ray_block = " + std::to_string(ray_block) +
                      ": a run of several frames sends each frame's rays at once, so ray_block "
                      "must be 0");
  if (loop_credits > safe_credits())
    bad("loop_credits", "must not exceed the smallest FIFO depth past the front buffer (" +
                            std::to_string(safe_credits()) +
                            "), or a full FIFO could deadlock the loop");
}

}  // namespace rtm
