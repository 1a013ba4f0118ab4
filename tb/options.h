// What the user asked for on the command line, as plain data.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace rtm {

struct RenderOptions {
  std::vector<std::string> command_line;  ///< argv as given: the statistics record it
  std::string scene;                      ///< empty: the built-in default scene
  bool reference = false;                 ///< the untimed reference renderer instead of the machine
  std::string size;                       ///< "WxH", empty: the scene's own
  std::string
      camera;  ///< camera keys as a YAML mapping, e.g. "{eye: [0, 2, 10]}"; empty: the scene's own
  std::string out;        ///< image path; empty: out/<scene>.png
  std::string stats;      ///< stats JSON path; empty: beside the image
  std::string id_map;     ///< optional ID map (.exr)
  std::string error_map;  ///< optional error map (.exr, and a .png beside it)
  std::string grid;       ///< "auto", "N" or "NxNyNz"; empty: the scene's own
  std::optional<double> threshold;
  std::optional<int> max_depth;
  std::optional<double> spawn_offset;
  std::string spawn_policy;  ///< relative or bound; empty: the scene's own
  int threads = 0;           ///< reference renderer threads; 0: all cores
  int sim_threads = 0;       ///< threads simulating the PEs side by side; 0: all cores
  bool quiet = false;
  std::string max_memory;     ///< the memory budget, e.g. "4G"; empty: 3/4 of the machine's
  double max_rays = 0;        ///< the work budget in rays traced; 0: none
  bool strict = false;        ///< degenerate shapes are errors, not skipped records
  bool skip_unknown = false;  ///< unknown NFF records are skipped with a warning, not errors

  // The machine
  std::string preset;       ///< machine preset, applied first; empty: default
  std::string config_file;  ///< machine configuration (YAML key: value), applied after the preset
  std::vector<std::string> sets;  ///< key=value overrides, applied after the file
  std::optional<int> pes;
  std::string timing, precision, partition, mac_schedule;
  std::optional<int> search_units;
  std::optional<int> frames;
  std::string tech;        ///< technology file; empty: the `tech` key's
  std::string vcd;         ///< waveform file
  std::string vcd_window;  ///< "FROM:TO" in PE cycles (either side may be empty)
  std::string vcd_pes;     ///< comma-separated PE numbers; default 0
  std::string event_log;   ///< one line per unit event; empty: none
};

/// Runs `rtm render`; returns the process exit code.
int run_render(const RenderOptions& opt);
/// Runs `rtm config`: prints the machine configuration of opt's preset, file and --set options as
/// a YAML file --config reads back, or with `markdown` docs/machine.md's table of the keys (of
/// how the preset differs from the defaults, with a preset).
int run_config(const RenderOptions& opt, bool markdown);
/// Runs `rtm tech`: prints every entry of the technology in `file` (empty: the built-in one), or
/// with `markdown` docs/cost.md's table of the entries.
int run_tech(const std::string& file, bool markdown);

}  // namespace rtm
