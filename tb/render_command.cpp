// `rtm render`: load a scene, pre-process it, render it on the machine (or the reference),
// compare, write the image and the statistics.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "machine/bottleneck.h"
#include "machine/machine.h"
#include "options.h"
#include "reference_cache.h"
#include "render/image_io.h"
#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {
extern const char* const kDefaultSceneYaml;

namespace {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void parse_size(const std::string& text, int& w, int& h) {
  std::smatch m;
  if (!std::regex_match(text, m, std::regex(R"((\d{1,6})x(\d{1,6}))")))
    throw UsageError("--size: expected WxH, e.g. 320x240, got '" + text + "'");
  w = std::stoi(m[1]);
  h = std::stoi(m[2]);
  if (w < 1 || h < 1) throw UsageError("--size: the image must have at least one pixel, got '" + text + "'");
}

std::array<int, 3> parse_grid(const std::string& text) {
  if (text == "auto" || text == "machine") return {0, 0, 0};
  std::smatch m;
  if (std::regex_match(text, m, std::regex(R"((\d{1,5}))"))) {
    const int n = std::stoi(m[1]);
    if (n >= 1) return {n, n, n};
  }
  if (std::regex_match(text, m, std::regex(R"((\d{1,5})x(\d{1,5})x(\d{1,5}))"))) {
    std::array<int, 3> n{std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3])};
    if (n[0] >= 1 && n[1] >= 1 && n[2] >= 1) return n;
  }
  throw UsageError("--grid: expected auto, machine, N or NxNyNz with N >= 1, got '" + text + "'");
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

MachineConfig machine_config(const RenderOptions& opt) {
  MachineConfig c;
  if (!opt.config_file.empty()) {
    try {
      load_config_file(c, opt.config_file);
    } catch (const ConfigError& e) {
      throw UsageError(e.what());
    }
  }
  auto set = [&](const std::string& key, const std::string& value, const char* flag) {
    try {
      set_config(c, key, value);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string(flag) + ": " + e.what());
    }
  };
  for (const std::string& kv : opt.sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--set: expected KEY=VALUE, got '" + kv + "'");
    set(kv.substr(0, eq), kv.substr(eq + 1), "--set");
  }
  if (opt.pes) set("pes", std::to_string(*opt.pes), "--pes");
  if (!opt.timing.empty()) set("timing", opt.timing, "--timing");
  if (!opt.precision.empty()) set("precision", opt.precision, "--precision");
  if (!opt.partition.empty()) set("partition", opt.partition, "--partition");
  if (!opt.mac_schedule.empty()) set("mac_schedule", opt.mac_schedule, "--mac-schedule");
  if (opt.search_units) set("search_units", std::to_string(*opt.search_units), "--search-units");
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("machine configuration: ") + e.what());
  }
  return c;
}

MachineOptions machine_options(const RenderOptions& opt, const MachineConfig& c) {
  MachineOptions m;
  m.vcd = opt.vcd;
  m.progress = !opt.quiet;
  if (!opt.vcd_window.empty()) {
    std::smatch w;
    if (!std::regex_match(opt.vcd_window, w, std::regex(R"((\d*):(\d*))")))
      throw UsageError("--vcd-window: expected FROM:TO in cycles, got '" + opt.vcd_window + "'");
    if (w[1].length()) m.vcd_from_cycle = std::stoull(w[1]);
    if (w[2].length()) m.vcd_to_cycle = std::stoull(w[2]);
    if (m.vcd_to_cycle < m.vcd_from_cycle) throw UsageError("--vcd-window: TO is before FROM");
  }
  if (!opt.vcd_pes.empty()) {
    m.vcd_pes.clear();
    std::stringstream s(opt.vcd_pes);
    for (std::string item; std::getline(s, item, ',');) {
      if (!std::regex_match(item, std::regex(R"(\d{1,6})")) || std::stoi(item) >= c.pes)
        throw UsageError("--vcd-pes: '" + item + "' is not a PE number below " + std::to_string(c.pes));
      m.vcd_pes.push_back(std::stoi(item));
    }
  }
  return m;
}

nlohmann::json counts_json(const TraceCounts& c) {
  nlohmann::json rays;
  for (int k = 0; k < kRayKinds; ++k) rays[ray_kind_name(RayKind(k))] = c.rays[size_t(k)];
  return {{"rays", rays},
          {"voxel_steps", c.voxel_steps},
          {"intersection_tests", c.intersection_tests},
          {"clip_tests", c.clip_tests}};
}

struct Utilisation {
  double front, search, mac, root, shade;
};

/// Busy fraction of each stage over the frame (replicated units: per unit).
Utilisation utilisation(const MachineResult& m, const MachineConfig& c) {
  Utilisation u{};
  const double cycles = double(m.cycles) * c.pes;
  if (cycles <= 0) return u;
  for (const PeCounters& p : m.per_pe) {
    u.front += double(p.front.busy_cycles);
    u.search += double(p.search.busy_cycles) / c.search_units;
    u.mac += double(p.mac.busy_cycles) / c.intersection_units;
    u.root += double(p.root.busy_cycles) / c.intersection_units;
    u.shade += double(p.shade.busy_cycles);
  }
  return {u.front / cycles, u.search / cycles, u.mac / cycles, u.root / cycles, u.shade / cycles};
}

/// Phases, unit utilisation over the PEs' working windows, and the bottleneck.
FrameProfile profile(const MachineResult& m, const MachineConfig& c) {
  const sc_core::sc_time period(c.clock_ns, sc_core::SC_NS);
  FrameProfile f;
  f.total = double(m.cycles);
  f.host_preprocess = m.host.rays / period;
  f.transfer = (m.host.transfer - m.host.rays) / period;
  f.gather = (m.host.gathered - m.host.pes_done) / period;
  double window = 0, longest = 0, stall = 0;
  for (const PeCounters& p : m.per_pe) {
    const double w = (p.finish - p.start) / period;
    window += w;
    longest = std::max(longest, w);
    stall += p.credit_stall / period;
    f.search += double(p.search.busy_cycles) / c.search_units;
    f.mac += double(p.mac.busy_cycles) / c.intersection_units;
    f.root += double(p.root.busy_cycles) / c.intersection_units;
    f.shading += double(p.shade.busy_cycles);
    f.front_buffer += double(p.front.busy_cycles);
  }
  if (window > 0) {
    for (double* u : {&f.search, &f.mac, &f.root, &f.shading, &f.front_buffer}) *u /= window;
    f.credit_stall = stall / window;
    f.imbalance = longest / (window / double(m.per_pe.size()));
  }
  return f;
}

nlohmann::json machine_json(const MachineResult& m, const MachineConfig& c) {
  const sc_core::sc_time period(c.clock_ns, sc_core::SC_NS);
  auto cyc = [&](const sc_core::sc_time& t) { return uint64_t(std::llround(t / period)); };
  const FrameProfile f = profile(m, c);
  const double mac_bound = std::ceil(double(m.mac_products) / c.pes);
  nlohmann::json per_pe = nlohmann::json::array();
  for (const PeCounters& p : m.per_pe)
    per_pe.push_back({{"cycles", cyc(p.finish)},
                      {"start_cycle", cyc(p.start)},
                      {"credit_stall_cycles", cyc(p.credit_stall)},
                      {"rays", p.counts.total_rays()},
                      {"spills", p.spills},
                      {"busy_cycles",
                       {{"front_buffer", p.front.busy_cycles},
                        {"search", p.search.busy_cycles},
                        {"mac", p.mac.busy_cycles},
                        {"root", p.root.busy_cycles},
                        {"shading", p.shade.busy_cycles}}}});
  nlohmann::json fifo;
  for (const FifoSummary& f : m.fifos) fifo[f.kind] = {{"depth", f.depth}, {"peak", f.peak}, {"mean", f.mean}};
  const Utilisation u = utilisation(m, c);
  nlohmann::json config;
  for (const ConfigKey& k : config_keys()) config[k.name] = k.get(c);
  return {{"pes", c.pes},
          {"timing", to_string(c.timing)},
          {"precision", to_string(c.precision)},
          {"partition", to_string(c.partition)},
          {"search_units", c.search_units},
          {"pe_simulation",
           {{"engine", m.engine_unsupported.empty()},
            {"modules_because", m.engine_unsupported.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.engine_unsupported)}}},
          {"cycles", m.cycles},
          {"sim_time_ns", m.end.to_seconds() * 1e9},
          {"mac", {{"products", m.mac_products}, {"busy_cycles", m.mac_busy_cycles}}},
          {"spills", m.spills},
          {"host",
           {{"voxels_done_cycle", cyc(m.host.voxels)},
            {"rays_done_cycle", cyc(m.host.rays)},
            {"transfer_done_cycle", cyc(m.host.transfer)},
            {"pes_done_cycle", cyc(m.host.pes_done)},
            {"gathered_cycle", cyc(m.host.gathered)},
            {"link_busy_cycles", cyc(m.host.link_busy)},
            {"scene_bytes", m.scene_bytes}}},
          {"utilisation",
           {{"front_buffer", u.front}, {"search", u.search}, {"mac", u.mac}, {"root", u.root}, {"shading", u.shade}}},
          {"pe_utilisation",
           {{"front_buffer", f.front_buffer},
            {"search", f.search},
            {"mac", f.mac},
            {"root", f.root},
            {"shading", f.shading},
            {"credit_stall", f.credit_stall}}},
          {"phases",
           {{"host_preprocess_cycles", f.host_preprocess},
            {"transfer_cycles", f.transfer},
            {"pe_cycles", (m.host.pes_done - m.host.transfer) / period},
            {"gather_cycles", f.gather}}},
          {"load_imbalance", f.imbalance},
          {"mac_bound_cycles", mac_bound},
          {"cycles_over_mac_bound", mac_bound > 0 ? double(m.cycles) / mac_bound : 0.0},
          {"bottleneck", bottleneck(f)},
          {"left_out",
           {{"units", m.left_out_units},
            {"mac_schedule", to_string(c.mac_schedule)},
            {"mac_products_saved", m.mac_products_saved},
            {"mac_cycles_saved", m.mac_cycles_saved},
            {"scene_needs",
             {{"shadow_rays", m.needs.shadow_rays},
              {"reflected_rays", m.needs.reflected_rays},
              {"transmitted_rays", m.needs.transmitted_rays},
              {"background", m.needs.background},
              {"deepest_generation", m.needs.deepest_generation},
              {"clipped_primitives", m.needs.clipped_primitives},
              {"mac_products_per_test_full", kMacProducts},
              {"mac_products_per_test_sparse",
               m.needs.mac_ops.empty() ? 0.0 : double(m.needs.products_sparse) / double(m.needs.mac_ops.size())},
              {"grid", m.needs.grid}}}}},
          {"per_pe", per_pe},
          {"fifo", fifo},
          {"config", config}};
}

nlohmann::json error_json(const ImageError& e) {
  return {{"rmse", e.rmse},
          {"psnr_db", std::isfinite(e.psnr_db) ? nlohmann::json(e.psnr_db) : nlohmann::json("inf")},
          {"max_abs", e.max_abs},
          {"pixels_over_1_255", e.pixels_over_1_255}};
}

void print_rays(const TraceCounts& c) {
  std::printf("rays: %llu primary, %llu shadow, %llu reflected, %llu transmitted\n", (unsigned long long)c.rays[0],
              (unsigned long long)c.rays[1], (unsigned long long)c.rays[2], (unsigned long long)c.rays[3]);
}

}  // namespace

int run_render(const RenderOptions& opt) {
  try {
    // Its ~0.2 s of loading overlaps parsing and rendering instead of following them.
    preload_image_library();
    Scene scene = opt.scene.empty() ? default_scene() : load_scene(opt.scene);
    const std::string scene_text = opt.scene.empty() ? std::string(kDefaultSceneYaml) : read_text(opt.scene);
    if (!opt.size.empty()) {
      int w = 0, h = 0;
      parse_size(opt.size, w, h);
      set_resolution(scene, w, h);
    }
    if (!opt.grid.empty()) scene.grid.resolution = parse_grid(opt.grid);
    // The reference on its own sizes its automatic grid for a CPU, unless asked for the machine's.
    if (opt.reference && opt.grid != "machine") size_for_cpu(scene.grid);
    if (opt.threshold) scene.threshold = *opt.threshold;
    if (opt.max_depth) scene.max_depth = *opt.max_depth;
    if (opt.spawn_offset) scene.spawn_offset = *opt.spawn_offset;
    if (!opt.spawn_policy.empty()) {
      try {
        scene.spawn_policy = parse_spawn_policy(opt.spawn_policy);
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--spawn-policy: ") + e.what());
      }
    }
    validate(scene);
    const MachineConfig config = opt.reference ? MachineConfig{} : machine_config(opt);
    const MachineOptions mopt = opt.reference ? MachineOptions{} : machine_options(opt, config);

    const std::string out = opt.out.empty() ? "out/" + scene.name + ".png" : opt.out;
    const std::string stats_path =
        opt.stats.empty() ? (std::filesystem::path(out).replace_extension(".json")).string() : opt.stats;

    const auto t0 = std::chrono::steady_clock::now();
    const Grid grid = build_grid(scene.primitives, scene.grid);
    const double grid_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    nlohmann::json j;
    j["scene"] = scene.name;
    j["width"] = scene.camera.width;
    j["height"] = scene.camera.height;
    j["primitives"] = scene.primitives.size();
    j["grid"] = {{"resolution", grid.n}, {"references", grid.items.size()}, {"build_seconds", grid_seconds}};
    j["spawn"] = {{"offset", scene.spawn_offset}, {"policy", to_string(scene.spawn_policy)}};

    if (opt.reference) {
      const ReferenceResult r = render_reference(scene, grid, opt.threads);
      write_image(out, r.image);
      if (!opt.id_map.empty()) write_id_map(opt.id_map, r.image);
      j.update(counts_json(r.counts));
      j["renderer"] = "reference";
      j["wall_seconds"] = r.wall_seconds;
      write_text_atomically(stats_path, j.dump(2) + "\n");
      if (!opt.quiet) {
        std::printf("%s: %dx%d, %zu primitives, grid %dx%dx%d\n", scene.name.c_str(), scene.camera.width,
                    scene.camera.height, scene.primitives.size(), grid.n[0], grid.n[1], grid.n[2]);
        print_rays(r.counts);
        std::printf("wall time: %.3f s (reference renderer), %.2f M rays/s\n", r.wall_seconds,
                    double(r.counts.total_rays()) / r.wall_seconds / 1e6);
        std::printf("image: %s\nstats: %s\n", out.c_str(), stats_path.c_str());
        if (!opt.id_map.empty()) std::printf("id map: %s\n", opt.id_map.c_str());
      }
      return 0;
    }

    const MachineResult m = run_machine(scene, grid, config, mopt);
    if (m.deadlock) {
      std::cerr << "rtm: deadlock: the simulation stopped with rays outstanding; no image written\n"
                << m.deadlock_report;
      return 3;
    }
    bool cache_hit = false;
    const ReferenceResult ref = cached_reference(scene, grid, scene_text, &cache_hit);
    const ImageError err = compare_images(m.image, ref.image);

    write_image(out, m.image);
    if (!opt.id_map.empty()) write_id_map(opt.id_map, m.image);
    if (!opt.vcd.empty()) {
      const std::string gtkw = std::filesystem::path(opt.vcd).replace_extension(".gtkw").string();
      write_gtkw(gtkw, opt.vcd, config, m.units, mopt.vcd_pes);
    }
    j.update(counts_json(m.counts));
    j["renderer"] = "machine";
    j["wall_seconds"] = m.wall_seconds;
    j.update(machine_json(m, config));
    j["error"] = error_json(err);
    // The same walk and tests as the machine's (at fp64 always; at fp32 unless a hit moved).
    const bool counts_match = ref.counts.rays == m.counts.rays && ref.counts.voxel_steps == m.counts.voxel_steps &&
                              ref.counts.intersection_tests == m.counts.intersection_tests &&
                              ref.counts.clip_tests == m.counts.clip_tests;
    j["reference"] = {{"wall_seconds", ref.wall_seconds},
                      {"cached", cache_hit},
                      {"rays_match", ref.counts.rays == m.counts.rays},
                      {"counts_match", counts_match}};
    write_text_atomically(stats_path, j.dump(2) + "\n");

    if (!opt.quiet) {
      const Utilisation u = utilisation(m, config);
      std::printf("%s: %dx%d, %zu primitives, grid %dx%dx%d, %d PE%s (%s, %s, %s timing)\n", scene.name.c_str(),
                  scene.camera.width, scene.camera.height, scene.primitives.size(), grid.n[0], grid.n[1], grid.n[2],
                  config.pes, config.pes == 1 ? "" : "s", to_string(config.partition), to_string(config.precision),
                  to_string(config.timing));
      std::printf("cycles: %llu (%.3f ms simulated at %.4g ns)\n", (unsigned long long)m.cycles, m.end.to_seconds() * 1e3,
                  config.clock_ns);
      print_rays(m.counts);
      std::printf("rays per cycle: %.4f\n", double(m.counts.total_rays()) / double(std::max<uint64_t>(1, m.cycles)));
      std::printf("utilisation: front buffer %.1f%%, search %.1f%%, MAC %.1f%%, root/sort %.1f%%, shading %.1f%%\n",
                  100 * u.front, 100 * u.search, 100 * u.mac, 100 * u.root, 100 * u.shade);
      const FrameProfile f = profile(m, config);
      std::printf("bottleneck: %s (cycles / MAC bound %.2f, load imbalance %.2f)\n", bottleneck(f).c_str(),
                  double(m.cycles) / std::max(1.0, std::ceil(double(m.mac_products) / config.pes)), f.imbalance);
      std::printf("error vs reference: rmse %.3g, psnr %.1f dB, max %.3g, %llu pixels off by > 1/255\n", err.rmse,
                  err.psnr_db, err.max_abs, (unsigned long long)err.pixels_over_1_255);
      std::printf("wall time: %.3f s model (%s), %.3f s reference%s\n", m.wall_seconds,
                  m.engine_unsupported.empty() ? "PEs on the PE engine"
                                               : ("PEs as modules: " + m.engine_unsupported).c_str(),
                  ref.wall_seconds, cache_hit ? " (cached)" : "");
      std::printf("image: %s\nstats: %s\n", out.c_str(), stats_path.c_str());
      if (!opt.id_map.empty()) std::printf("id map: %s\n", opt.id_map.c_str());
      if (!opt.vcd.empty()) std::printf("waveform: %s (GTKWave: gtkwave %s)\n", opt.vcd.c_str(),
                                        std::filesystem::path(opt.vcd).replace_extension(".gtkw").c_str());
    }
    return 0;
  } catch (const UsageError& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 1;
  }
}

int run_config(const std::string& config_file, const std::vector<std::string>& sets) {
  RenderOptions opt;
  opt.config_file = config_file;
  opt.sets = sets;
  try {
    std::cout << describe_config(machine_config(opt));
    return 0;
  } catch (const UsageError& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace rtm
