#include "machine/config.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace rtm {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) { throw std::invalid_argument(key + ": " + why); }

long parse_int(const std::string& key, const std::string& v) {
  size_t used = 0;
  long x = 0;
  try {
    x = std::stol(v, &used);
  } catch (const std::exception&) {
    bad(key, "expected an integer, got '" + v + "'");
  }
  if (used != v.size()) bad(key, "expected an integer, got '" + v + "'");
  return x;
}

double parse_double(const std::string& key, const std::string& v) {
  size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    bad(key, "expected a number, got '" + v + "'");
  }
  if (used != v.size() || !std::isfinite(x)) bad(key, "expected a finite number, got '" + v + "'");
  return x;
}

bool parse_bool(const std::string& key, const std::string& v) {
  if (v == "true" || v == "1" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return false;
  bad(key, "expected true or false, got '" + v + "'");
}

template <class T>
std::string fmt(T x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

ConfigKey int_key(const char* name, const char* doc, int MachineConfig::*m) {
  return {name, doc, [m](const MachineConfig& c) { return fmt(c.*m); },
          [m, name](MachineConfig& c, const std::string& v) {
            const long x = parse_int(name, v);
            if (x < INT32_MIN || x > INT32_MAX) bad(name, "out of range");
            c.*m = int(x);
          }};
}

ConfigKey double_key(const char* name, const char* doc, double MachineConfig::*m) {
  return {name, doc, [m](const MachineConfig& c) { return fmt(c.*m); },
          [m, name](MachineConfig& c, const std::string& v) { c.*m = parse_double(name, v); }};
}

ConfigKey bool_key(const char* name, const char* doc, bool MachineConfig::*m) {
  return {name, doc, [m](const MachineConfig& c) { return std::string(c.*m ? "true" : "false"); },
          [m, name](MachineConfig& c, const std::string& v) { c.*m = parse_bool(name, v); }};
}

template <class E>
ConfigKey enum_key(const char* name, const char* doc, E MachineConfig::*m, std::vector<E> values) {
  return {name, doc, [m](const MachineConfig& c) { return std::string(to_string(c.*m)); },
          [m, name, values](MachineConfig& c, const std::string& v) {
            std::string names;
            for (E e : values) {
              if (v == to_string(e)) {
                c.*m = e;
                return;
              }
              names += std::string(names.empty() ? "" : ", ") + to_string(e);
            }
            bad(name, "expected one of " + names + ", got '" + v + "'");
          }};
}

}  // namespace

const char* to_string(Partition p) {
  switch (p) {
    case Partition::Scanlines: return "scanlines";
    case Partition::Blocks: return "blocks";
    case Partition::Strips: return "strips";
    case Partition::Pixels: return "pixels";
  }
  return "?";
}
const char* to_string(Timing t) { return t == Timing::Fast ? "fast" : "clocked"; }
const char* to_string(Precision p) { return p == Precision::Fp32 ? "fp32" : "fp64"; }
const char* to_string(FlowControl f) { return f == FlowControl::Credits ? "credits" : "none"; }
const char* to_string(Discriminant d) { return d == Discriminant::Plain ? "plain" : "fma"; }
const char* to_string(CoefScaling s) { return s == CoefScaling::None ? "none" : "pow2"; }
const char* to_string(OriginLatch o) {
  return o == OriginLatch::Machine ? "machine" : o == OriginLatch::Wide ? "wide" : "advance";
}
const char* to_string(MachineConfig::MacSchedule m) { return m == MachineConfig::MacSchedule::Full ? "full" : "sparse"; }
const char* to_string(MachineConfig::SearchWalk w) {
  return w == MachineConfig::SearchWalk::PerVoxel ? "per_voxel" : "until_occupied";
}
const char* to_string(MachineConfig::RayGeneration g) { return g == MachineConfig::RayGeneration::Host ? "host" : "pe"; }
const char* to_string(MachineConfig::Gather g) { return g == MachineConfig::Gather::AfterAll ? "after_all" : "as_finished"; }
const char* to_string(MachineConfig::Arbitration a) { return a == MachineConfig::Arbitration::Kernel ? "kernel" : "ranked"; }
const char* to_string(MachineConfig::PeSimulation p) { return p == MachineConfig::PeSimulation::Auto ? "auto" : "modules"; }

const std::vector<ConfigKey>& config_keys() {
  using M = MachineConfig;
  static const std::vector<ConfigKey> keys = {
      int_key("pes", "processing elements", &M::pes),
      enum_key("partition", "screen partitioning: scanlines (interleaved rows), blocks (tiles dealt round robin), strips (contiguous bands)",
               &M::partition, {Partition::Scanlines, Partition::Blocks, Partition::Strips, Partition::Pixels}),
      int_key("tile", "block edge in pixels (partition = blocks)", &M::tile),
      enum_key("timing", "MAC model: fast (cycle-exact by formula) or clocked (a process on a clock)", &M::timing,
               {Timing::Fast, Timing::Clocked}),
      enum_key("precision", "MAC, root unit and clip arithmetic", &M::precision, {Precision::Fp32, Precision::Fp64}),
      enum_key("mac_schedule", "full (the paper's 6 + 12 + 10 products per test) or sparse (skip products whose coefficient is zero; same sums)",
               &M::mac_schedule, {M::MacSchedule::Full, M::MacSchedule::Sparse}),
      bool_key("leave_out", "leave out units, FIFOs and paths the scene cannot use (they are not elaborated)", &M::leave_out),
      bool_key("recentre", "coefficients relative to each primitive's centre, ray origin re-centred per test (false: world coefficients, as in the paper)",
               &M::recentre),
      enum_key("discriminant", "root unit's b^2 - 4ac: plain (two rounded products) or fma (difference of products with FMAs; fma_discriminant_cycles more latency)",
               &M::discriminant, {Discriminant::Plain, Discriminant::Fma}),
      enum_key("coef_scaling", "coefficient RAM image: none (the quadric's own coefficients) or pow2 (scaled by a power of two so the largest is in [1, 2): exact, keeps float32 in range)",
               &M::coef_scaling, {CoefScaling::None, CoefScaling::Pow2}),
      enum_key("origin_latch", "ray origin into the V latches: machine (rounded to the MAC precision, then re-centred), wide (re-centred in fp64, then rounded) or advance (wide, from the voxel's entry point)",
               &M::origin_latch, {OriginLatch::Machine, OriginLatch::Wide, OriginLatch::Advance}),
      double_key("clock_ns", "PE clock period, ns", &M::clock_ns),
      int_key("search_units", "replicated 3DDDA units per PE", &M::search_units),
      enum_key("search_walk", "per_voxel (an empty voxel sends the ray back to the front buffer, as in the paper) or until_occupied (the search unit steps on by itself)",
               &M::search_walk, {M::SearchWalk::PerVoxel, M::SearchWalk::UntilOccupied}),
      int_key("intersection_units", "MAC + root/sort lanes per PE (the paper has one)", &M::intersection_units),
      int_key("dda_step_cycles", "cycles for one 3DDDA step", &M::dda_step_cycles),
      int_key("voxel_read_cycles", "cycles to read a voxel's entry from local memory", &M::voxel_read_cycles),
      int_key("mul_latency", "pipeline depth of each MAC multiplier", &M::mul_latency),
      int_key("add_latency", "MAC adder latency (dependent accumulation issues one product per add_latency)", &M::add_latency),
      int_key("coef_load_cycles", "cycles to load a primitive's coefficients into the MAC RAM", &M::coef_load_cycles),
      int_key("root_latency", "root unit latency (pipelined)", &M::root_latency),
      int_key("fma_discriminant_cycles", "extra root unit latency with discriminant = fma", &M::fma_discriminant_cycles),
      int_key("advance_cycles", "extra root unit latency with origin_latch = advance", &M::advance_cycles),
      int_key("clip_cycles", "cycles per clip half-space test", &M::clip_cycles),
      int_key("sort_cycles", "cycles per primitive result merged by the sort unit", &M::sort_cycles),
      int_key("shade_cycles", "shading cycles per ray", &M::shade_cycles),
      int_key("spawn_cycles", "cycles to generate one shadow or branch ray", &M::spawn_cycles),
      int_key("accumulate_cycles", "cycles to add a shadow ray's or the background's brightness to the frame buffer",
              &M::accumulate_cycles),
      int_key("fb_dispatch_cycles", "cycles for the front buffer to hand out one ray", &M::fb_dispatch_cycles),
      int_key("front_buffer_capacity", "on-chip front buffer size in rays (overflow spills to local memory)",
              &M::front_buffer_capacity),
      int_key("spill_cycles", "extra cycles per ray moved to or from the spill area", &M::spill_cycles),
      int_key("search_fifo_depth", "FIFO depth, front buffer -> search units", &M::search_fifo_depth),
      int_key("intersect_fifo_depth", "FIFO depth, search -> intersection", &M::intersect_fifo_depth),
      int_key("root_fifo_depth", "FIFO depth, MAC -> root unit", &M::root_fifo_depth),
      int_key("shade_fifo_depth", "FIFO depth, search/intersection -> shading", &M::shade_fifo_depth),
      int_key("feedback_fifo_depth", "FIFO depth of each path back into the front buffer", &M::feedback_fifo_depth),
      enum_key("flow_control", "credits (deadlock-free) or none (the paper's unregulated loop, which can deadlock)",
               &M::flow_control, {FlowControl::Credits, FlowControl::None}),
      int_key("loop_credits", "rays allowed past the front buffer at once (0: largest safe value)", &M::loop_credits),
      enum_key("ray_generation", "who generates primary rays: host (the paper: generated and sent by the host) or pe (each PE from the camera)",
               &M::ray_generation, {M::RayGeneration::Host, M::RayGeneration::Pe}),
      int_key("pe_ray_cycles", "PE cycles to generate one primary ray (ray_generation = pe)", &M::pe_ray_cycles),
      double_key("host_clock_ns", "host clock period, ns", &M::host_clock_ns),
      int_key("host_voxel_cycles", "host cycles per primitive reference registered in a voxel", &M::host_voxel_cycles),
      int_key("host_ray_cycles", "host cycles per primary ray generated", &M::host_ray_cycles),
      double_key("link_bandwidth_mb_s", "host <-> PE link bandwidth, MB/s", &M::link_bandwidth_mb_s),
      double_key("link_latency_ns", "host <-> PE link latency per transaction, ns", &M::link_latency_ns),
      bool_key("broadcast", "one scene transfer reaches every PE (else one transfer per PE)", &M::broadcast),
      int_key("ray_block", "primary rays per host -> PE transfer (0: all of a PE's rays at once)", &M::ray_block),
      enum_key("arbitration", "same-cycle order: ranked (a fixed order by unit, independent of the kernel: clocked and fast timing give the same cycles on any frame) or kernel (SystemC's event queue decides)",
               &M::arbitration, {M::Arbitration::Kernel, M::Arbitration::Ranked}),
      enum_key("pe_simulation", "auto (each PE's pipeline on the PE engine where the configuration allows: the same cycles, several times faster) or modules (one SystemC process per unit)",
               &M::pe_simulation, {M::PeSimulation::Auto, M::PeSimulation::Modules}),
      enum_key("gather", "after_all (the host reads the frame buffers once every PE is done, as in the paper) or as_finished (each PE's as soon as it is done)",
               &M::gather, {M::Gather::AfterAll, M::Gather::AsFinished}),
  };
  return keys;
}

void set_config(MachineConfig& c, const std::string& key, const std::string& value) {
  for (const ConfigKey& k : config_keys())
    if (k.name == key) return k.set(c, value);
  bad(key, "unknown machine configuration key (rtm config lists them)");
}

void load_config_file(MachineConfig& c, const std::string& path) {
  std::ifstream f(path);
  if (!f) throw ConfigError(path, 0, "cannot read the configuration file");
  std::stringstream text;
  text << f.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line + 1, e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw ConfigError(path, root.Mark().line + 1, "expected a map of key: value");
  for (const auto& kv : root) {
    const int line = kv.first.Mark().line + 1;
    if (!kv.second.IsScalar()) throw ConfigError(path, line, kv.first.Scalar() + ": expected a single value");
    try {
      set_config(c, kv.first.Scalar(), kv.second.Scalar());
    } catch (const std::invalid_argument& e) {
      throw ConfigError(path, line, e.what());
    }
  }
}

std::string describe_config(const MachineConfig& c) {
  std::ostringstream s;
  for (const ConfigKey& k : config_keys()) s << k.name << " = " << k.get(c) << "    # " << k.doc << "\n";
  return s.str();
}

int MachineConfig::safe_credits() const {
  return std::min({search_fifo_depth, intersect_fifo_depth, root_fifo_depth, shade_fifo_depth});
}

void MachineConfig::validate() const {
  auto at_least = [](const char* key, long v, long lo) {
    if (v < lo) bad(key, "must be at least " + std::to_string(lo) + ", got " + std::to_string(v));
  };
  at_least("pes", pes, 1);
  if (pes > 65536) bad("pes", "at most 65536");
  at_least("tile", tile, 1);
  at_least("search_units", search_units, 1);
  if (search_units > 256) bad("search_units", "at most 256");
  at_least("intersection_units", intersection_units, 1);
  if (intersection_units > 64) bad("intersection_units", "at most 64");
  for (auto [key, v] : {std::pair<const char*, int>{"dda_step_cycles", dda_step_cycles},
                        {"voxel_read_cycles", voxel_read_cycles},
                        {"coef_load_cycles", coef_load_cycles},
                        {"clip_cycles", clip_cycles},
                        {"sort_cycles", sort_cycles},
                        {"shade_cycles", shade_cycles},
                        {"spawn_cycles", spawn_cycles},
                        {"accumulate_cycles", accumulate_cycles},
                        {"spill_cycles", spill_cycles},
                        {"host_voxel_cycles", host_voxel_cycles},
                        {"host_ray_cycles", host_ray_cycles},
                        {"pe_ray_cycles", pe_ray_cycles},
                        {"fma_discriminant_cycles", fma_discriminant_cycles},
                        {"advance_cycles", advance_cycles}})
    at_least(key, v, 0);
  for (auto [key, v] : {std::pair<const char*, int>{"mul_latency", mul_latency},
                        {"add_latency", add_latency},
                        {"root_latency", root_latency},
                        {"fb_dispatch_cycles", fb_dispatch_cycles},
                        {"front_buffer_capacity", front_buffer_capacity},
                        {"search_fifo_depth", search_fifo_depth},
                        {"intersect_fifo_depth", intersect_fifo_depth},
                        {"root_fifo_depth", root_fifo_depth},
                        {"shade_fifo_depth", shade_fifo_depth},
                        {"feedback_fifo_depth", feedback_fifo_depth}})
    at_least(key, v, 1);
  at_least("loop_credits", loop_credits, 0);
  at_least("ray_block", ray_block, 0);
  if (loop_credits > safe_credits())
    bad("loop_credits", "must not exceed the smallest FIFO depth past the front buffer (" +
                            std::to_string(safe_credits()) + "), or a full FIFO could deadlock the loop");
  if (!(clock_ns > 0)) bad("clock_ns", "must be positive");
  if (!(host_clock_ns > 0)) bad("host_clock_ns", "must be positive");
  if (!(link_bandwidth_mb_s > 0)) bad("link_bandwidth_mb_s", "must be positive");
  if (!(link_latency_ns >= 0)) bad("link_latency_ns", "must not be negative");
}

}  // namespace rtm
