#include "render_options.h"

#include <array>
#include <cerrno>
#include <filesystem>
#include <stdexcept>
#include <iostream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "scene/scene_checks.h"

namespace rtm {

int run_command(const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 2;
  } catch (const MachineLimitError& e) {
    std::cerr << "rtm: machine configuration: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rtm: " << e.what() << "\n";
    return 1;
  }
}

namespace {

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

}  // namespace

void check_writable(const char* option, const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return;
  const fs::path folder =
      fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  std::error_code ec, ignored;
  fs::create_directories(folder, ec);
  if (!ec && !fs::is_directory(fs::status(folder, ignored)))
    ec = std::make_error_code(std::errc::not_a_directory);
  if (!ec && fs::is_directory(fs::status(path, ignored)))
    ec = std::make_error_code(std::errc::is_a_directory);
  if (!ec && access(folder.c_str(), W_OK) != 0)
    ec = std::error_code(errno, std::generic_category());
  if (ec) throw UsageError(std::string(option) + ": " + path + ": cannot write: " + ec.message());
}

void apply_size(const std::string& size, Scene& scene) {
  std::smatch m;
  // N is NxN, as in a sweep's sizes.
  if (!std::regex_match(size, m, std::regex(R"((\d{1,6})(?:x(\d{1,6}))?)")))
    throw UsageError("--size: expected WxH (e.g. 320x240) or N (NxN), got '" + size + "'");
  const int w = std::stoi(m[1]), h = m[2].matched ? std::stoi(m[2]) : w;
  if (w < 1 || h < 1)
    throw UsageError("--size: the image must have at least one pixel, got '" + size + "'");
  try {
    set_resolution(scene, w, h);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--size: ") + e.what());
  }
}

void apply_scene_options(const RenderOptions& opt, Scene& scene) {
  if (!opt.camera.empty()) {
    try {
      override_camera(scene.camera, opt.camera);
    } catch (const SceneError& e) {
      const std::string where = e.file() + ":" + std::to_string(e.line()) + ": ";
      throw UsageError("--camera: " + std::string(e.what()).substr(where.size()));
    }
  }
  if (!opt.size.empty()) apply_size(opt.size, scene);
  if (!opt.grid.empty()) {
    scene.grid.resolution = parse_grid(opt.grid);
    try {
      scene_checks::check_grid(scene.grid);
    } catch (const std::invalid_argument& e) {
      throw UsageError("--grid: " + opt.grid + ": " + e.what());
    }
  }
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
}

MachineConfig machine_config(const RenderOptions& opt) {
  MachineConfig c;
  if (!opt.preset.empty()) {
    try {
      apply_preset(c, opt.preset);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--preset: ") + e.what());
    }
  }
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
    try {
      set_config_assignment(c, kv);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--set: ") + e.what());
    }
  }
  if (opt.pes) set("pes", std::to_string(*opt.pes), "--pes");
  if (!opt.timing.empty()) set("timing", opt.timing, "--timing");
  if (!opt.precision.empty()) set("precision", opt.precision, "--precision");
  if (!opt.partition.empty()) set("partition", opt.partition, "--partition");
  if (!opt.mac_schedule.empty()) set("mac_schedule", opt.mac_schedule, "--mac-schedule");
  if (opt.search_units) set("search_units", std::to_string(*opt.search_units), "--search-units");
  if (opt.frames) set("frames", std::to_string(*opt.frames), "--frames");
  if (!opt.tech.empty()) set("tech", opt.tech, "--tech");
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("machine configuration: ") + e.what());
  }
  technology(c.tech);  // a bad technology file is refused before any work
  return c;
}

Technology technology(const std::string& spec) {
  try {
    return load_technology(spec);
  } catch (const TechnologyError& e) {
    throw UsageError(e.what());
  }
}

MachineOptions machine_options(const RenderOptions& opt, const MachineConfig& c) {
  MachineOptions m;
  m.vcd = opt.vcd;
  if (!opt.vcd.empty())
    m.gtkw = std::filesystem::path(vcd_file(opt.vcd)).replace_extension(".gtkw").string();
  m.event_log = opt.event_log;
  m.progress = !opt.quiet;
  m.max_rays = uint64_t(opt.max_rays);
  m.sim_threads = opt.sim_threads;
  if (!opt.vcd_window.empty()) {
    std::smatch w;
    if (!std::regex_match(opt.vcd_window, w, std::regex(R"((?:pe(\d{1,6})\+)?(\d*):(\d*))")))
      throw UsageError(
          "--vcd-window: expected FROM:TO in cycles, or peN+FROM:TO in cycles after PE N's first "
          "primary ray, got '" +
          opt.vcd_window + "'");
    try {
      if (w[2].length()) m.vcd_from_cycle = std::stoull(w[2]);
      if (w[3].length()) m.vcd_to_cycle = std::stoull(w[3]);
    } catch (const std::out_of_range&) {
      throw UsageError("--vcd-window: a cycle past 2^64 in '" + opt.vcd_window + "'");
    }
    if (m.vcd_to_cycle < m.vcd_from_cycle) throw UsageError("--vcd-window: TO is before FROM");
    if (w[1].length()) {
      m.vcd_anchor_pe = std::stoi(w[1]);
      if (m.vcd_anchor_pe >= c.pes)
        throw UsageError("--vcd-window: '" + opt.vcd_window + "' names PE " + w[1].str() +
                         ", but there " +
                         (c.pes == 1 ? "is 1 PE" : "are " + std::to_string(c.pes) + " PEs") +
                         " (pe0..pe" + std::to_string(c.pes - 1) + ")");
    }
  }
  if (!opt.vcd_pes.empty()) {
    m.vcd_pes.clear();
    std::stringstream s(opt.vcd_pes);
    for (std::string item; std::getline(s, item, ',');) {
      if (!std::regex_match(item, std::regex(R"(\d{1,6})")) || std::stoi(item) >= c.pes)
        throw UsageError("--vcd-pes: '" + item + "' is not a PE number below " +
                         std::to_string(c.pes));
      m.vcd_pes.push_back(std::stoi(item));
    }
  }
  return m;
}

}  // namespace rtm
