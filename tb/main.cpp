// rtm: the command-line front end of the ray-tracing machine model.
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <systemc>

#include "build_info.h"
#include "config/config.h"
#include "config/nearest_name.h"
#include "options.h"
#include "pov_export.h"
#include "reference_cache.h"
#include "render/ray.h"
#include "render_options.h"
#include "scene/scene_checks.h"

namespace {
// The kernel's banner would land in the middle of rtm's own output. It is printed before
// sc_main runs, so the variable is set by a static initialiser.
const bool kQuietKernel = [] { return setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0) == 0; }();

/// " (did you mean --pes?)" for the first word of the command line that names no command, or no
/// option of its command, but is close to one; else "".
std::string did_you_mean(CLI::App& app, int argc, char* argv[]) {
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    commands.push_back(sub->get_name());
  const CLI::App* command = nullptr;
  auto suggest = [](const std::string& typed, const std::vector<std::string>& known) {
    if (std::find(known.begin(), known.end(), typed) != known.end()) return std::string();
    const std::string near = rtm::nearest_name(typed, known);
    return near.empty() ? near : " (did you mean " + near + "?)";
  };
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] != '-') {  // the command, else a value or a scene
      if (command) continue;
      if (std::find(commands.begin(), commands.end(), word) != commands.end()) {
        command = app.get_subcommand(word);
        continue;
      }
      if (std::string s = suggest(word, commands); !s.empty()) return s;
      continue;
    }
    std::vector<std::string> options;
    for (const CLI::Option* o : (command ? command : &app)->get_options()) {
      for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
      for (const std::string& n : o->get_snames()) options.push_back("-" + n);
    }
    if (std::string s = suggest(word.substr(0, word.find('=')), options); !s.empty()) return s;
  }
  return "";
}

/// A scene setting's range (scene/scene_checks.h) as the option's check: --help shows the range
/// the scene's own check enforces, and a value outside it is a bad command line.
CLI::Validator in_range(const rtm::scene_checks::NumberRange& range) {
  return CLI::Validator(
      [range](std::string& text) {
        double x = 0;
        if (!CLI::detail::lexical_cast(text, x)) return "expected a number, got '" + text + "'";
        return range.contains(x) ? std::string() : "must be in " + range.text() + ", got " + text;
      },
      range.text());
}

}  // namespace

int sc_main(int argc, char* argv[]) {
  // Model errors become exceptions the command reports (with a non-zero exit), not aborts.
  sc_core::sc_report_handler::set_actions(sc_core::SC_ERROR,
                                          sc_core::SC_DISPLAY | sc_core::SC_THROW);
  sc_core::sc_report_handler::set_actions(sc_core::SC_FATAL,
                                          sc_core::SC_DISPLAY | sc_core::SC_THROW);
  CLI::App app{"rtm - a SystemC model of the Gwun/Murakami/Tomita parallel ray-tracing machine"};
  app.require_subcommand(1);
  app.set_version_flag("--version", rtm::version_text());

  // Every preset with its meaning, from their one declaration.
  std::string preset_help = "Machine preset, applied before --config and --set:";
  for (const rtm::Preset& p : rtm::presets()) preset_help += " " + p.name + " (" + p.meaning + ");";
  preset_help.back() = '.';

  rtm::RenderOptions r;
  r.command_line.assign(argv, argv + argc);
  CLI::App* render = app.add_subcommand(
      "render", "Render a whole frame (the built-in default scene if SCENE is omitted)");
  render->add_option("scene", r.scene,
                     "Scene file: .nff (NFF), .yaml (native format) or a mesh file (.obj, .ply, "
                     ".gltf, .glb, .stl, .off, ...)");
  render->add_flag("--reference", r.reference,
                   "Use the untimed double-precision reference renderer instead of the machine");
  render->add_option("--size", r.size,
                     "Image size WxH, or N for NxN (keeps the scene's horizontal field of view)");
  render->add_option("--camera", r.camera,
                     "Camera keys as in the native format, a YAML mapping: '{eye: [0, 2, 10], "
                     "look_at: [0, 0, 0], up: "
                     "[0, 1, 0], fov: 40}'; the keys given replace the scene's");
  render->add_option("--out", r.out,
                     "Image file, .png (8-bit, clamped) or .exr (float); default out/<scene>.png");
  render->add_option("--stats", r.stats, "Statistics JSON file; default beside the image");
  render->add_option("--id-map", r.id_map,
                     "One-channel EXR: primitive number seen by each primary ray, -1 background");
  render->add_option(
      "--error-map", r.error_map,
      "EXR of why each pixel differs from the reference (channels generation, kind, cause, "
      "primitive, "
      "reference_primitive), and a PNG of the causes in colour beside it (docs/numerics.md)");
  render->add_option("--grid", r.grid,
                     "Grid resolution: auto, machine (with --reference: the machine's automatic "
                     "grid), N, or NxNyNz; "
                     "default the scene's own (auto)");
  render
      ->add_option("--threshold", r.threshold,
                   "Branch-ray contribution threshold (overrides the scene)")
      ->check(in_range(rtm::scene_checks::kThresholdRange));
  render
      ->add_option("--max-depth", r.max_depth,
                   "Maximum ray generation, primary = 1 (overrides the scene)")
      ->check(CLI::Range(1, rtm::kMaxRayDepth));
  render
      ->add_option("--spawn-offset", r.spawn_offset,
                   "Spawned rays start this far off the surface, relative to max(1, |hit point|) "
                   "(overrides the scene)")
      ->check(in_range(rtm::scene_checks::kSpawnOffsetRange));
  render->add_option("--spawn-policy", r.spawn_policy,
                     "How --spawn-offset is applied: relative (x max(1, |hit point|)) or bound (x "
                     "an error bound of the hit point; docs/numerics.md)");
  render->add_option("--threads", r.threads, "Reference renderer threads (0: all cores)")
      ->check(CLI::Range(0, 1024));
  render
      ->add_option("--sim-threads", r.sim_threads,
                   "Threads simulating the PEs side by side once their rays are in (0: all cores); "
                   "the figures "
                   "are the same for any number")
      ->check(CLI::Range(0, 1024));
  render->add_flag("--quiet,-q", r.quiet, "No progress display and no summary");
  render->add_option("--max-memory", r.max_memory,
                     "Memory budget, e.g. 512M or 4G (default 3/4 of the machine's): a render "
                     "estimated to need more is "
                     "refused before it starts, and one whose ray trees outgrow it is stopped");
  render
      ->add_option("--max-rays", r.max_rays,
                   "Work budget, e.g. 1e9: a render (the machine's or the reference's) that traces "
                   "more rays is "
                   "stopped (default no limit)")
      ->check(CLI::Range(1.0, 1e18));
  render->add_flag("--strict", r.strict,
                   "Degenerate shapes (zero area, radius or length) are errors instead of skipped "
                   "with a warning");
  render->add_flag(
      "--skip-unknown", r.skip_unknown,
      "Skip NFF records rtm does not know (renderers' extensions), with one warning per kind");
  render->add_option("--preset", r.preset, preset_help);
  render->add_option("--config", r.config_file,
                     "Machine configuration file (YAML key: value; see rtm config)");
  render->add_option("--set", r.sets, "Machine configuration override KEY=VALUE (repeatable)");
  // --pes, --search-units and --frames are checked as their configuration keys (config/config.cpp).
  render->add_option("--pes", r.pes, "Processing elements");
  render->add_option("--timing", r.timing,
                     "fast (default: the MAC by formula, the PEs on the PE engine) or clocked (the "
                     "MAC on a clock, every unit a SystemC process); the same cycles either way");
  render->add_option("--precision", r.precision,
                     "Every PE unit's arithmetic: fp32 (default) or fp64 (the keys "
                     "intersection_precision, dda_precision, shading_precision set one unit's)");
  render->add_option(
      "--partition", r.partition,
      "Screen partitioning: scanlines, blocks, strips, pixels or dynamic (tiles on demand)");
  render->add_option("--search-units", r.search_units, "Replicated 3DDDA units per PE");
  render->add_option("--frames", r.frames,
                     "Frames to render, the same frame each time, the host preparing the next "
                     "while the PEs render one (the key frames); the statistics give the steady "
                     "state's frame time");
  render->add_option("--mac-schedule", r.mac_schedule,
                     "MAC schedule: sparse (default) or full (the paper's 28 products)");
  render->add_option("--tech", r.tech,
                     "Technology file the cost is figured in (the key tech; default the built-in "
                     "45nm; docs/cost.md)");
  render->add_option("--vcd", r.vcd, "Write a waveform (VCD) and a GTKWave save file beside it");
  render->add_option("--vcd-window", r.vcd_window,
                     "Waveform window FROM:TO in PE cycles (either may be empty), or peN+FROM:TO "
                     "counted from PE N's "
                     "first primary ray (e.g. pe0+0:2000: PE 0's first 2000 cycles of work)");
  render->add_option("--vcd-pes", r.vcd_pes, "PEs to trace, comma-separated (default 0)");
  render->add_option(
      "--event-log", r.event_log,
      "Write every unit event (cycle, PE, unit, ray, what happened) to this file, one line each; "
      "the same for the PE engine and the modules (docs/architecture.md)");

  rtm::RenderOptions c;
  bool markdown = false;
  CLI::App* config = app.add_subcommand("config",
                                        "Print every machine configuration key with its value, "
                                        "meaning and range, as a YAML file --config reads");
  config->add_option("--preset", c.preset, preset_help);
  CLI::Option* from = config->add_option("--config", c.config_file, "Then this configuration file");
  CLI::Option* set = config->add_option("--set", c.sets, "Then override KEY=VALUE (repeatable)");
  config
      ->add_flag("--markdown", markdown,
                 "Instead, docs/machine.md's table of the keys and their defaults, or with "
                 "--preset of the keys "
                 "on which the preset differs from them (scripts/config-doc)")
      ->excludes(from)
      ->excludes(set);

  std::string tech_file;
  CLI::App* tech = app.add_subcommand("tech",
                                      "Print every entry of the technology (energy, area, leakage) "
                                      "with its value, unit and source");
  tech->add_option("file", tech_file, "Technology file (docs/cost.md); default the built-in 45nm");
  bool tech_markdown = false;
  tech->add_flag("--markdown", tech_markdown,
                 "Instead, docs/cost.md's table of the entries (scripts/config-doc)");

  std::string cache_action;
  CLI::App* cache =
      app.add_subcommand("cache",
                         "The reference cache ($RTM_CACHE_DIR, else $XDG_CACHE_HOME/rtm, else "
                         "~/.cache/rtm; capped at $RTM_CACHE_SIZE, default 2G)");
  cache
      ->add_option("action", cache_action,
                   "info (entries, size, cap, partial files) or clean (remove them all)")
      ->required()
      ->check(CLI::IsMember({"info", "clean"}));

  rtm::PovOptions pov_opt;
  CLI::App* pov = rtm::add_pov_command(app, pov_opt);

  return rtm::run_command([&] {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      // CLI11 prints the help and the version; any error of its own (its codes: 105 for a value
      // out of range, 106 for a missing subcommand, ...) is a bad command line like rtm's own.
      if (e.get_exit_code() == int(CLI::ExitCodes::Success)) return app.exit(e);
      throw rtm::UsageError(e.what() + did_you_mean(app, argc, argv));
    }
    if (render->parsed()) return rtm::run_render(r);
    if (config->parsed()) return rtm::run_config(c, markdown);
    if (tech->parsed()) return rtm::run_tech(tech_file, tech_markdown);
    if (pov->parsed()) return rtm::run_pov(pov_opt);
    if (cache->parsed()) return rtm::run_cache(cache_action);
    return 2;
  });
}
