// `rtm render`: load a scene, pre-process it, render it on the machine (or the reference),
// compare, write the image and the statistics.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>

#include <unistd.h>

#include "byte_size.h"
#include "error/error_causes.h"
#include "error/error_map.h"
#include "machine/engine_driver.h"
#include "machine/machine.h"
#include "frame/partition.h"
#include "memory_budget.h"
#include "options.h"
#include "frame/frame_cost.h"
#include "printed_summary.h"
#include "reference_cache.h"
#include "render/atomic_file.h"
#include "render/image_formats.h"
#include "render/image_io.h"
#include "render/partial_files.h"
#include "render/progress.h"
#include "render/reference.h"
#include "render_options.h"
#include "scene/scene.h"
#include "stats_json.h"

namespace rtm {
extern const char* const kDefaultSceneYaml;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Removes what an earlier run left at the paths this one writes, and temporaries beside them
/// whose writers are gone: if this run fails, nothing there looks as if it came from it.
void clear_outputs(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  for (const std::string& p : paths) {
    if (p.empty()) continue;
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(p, ec);
    if (fs::is_regular_file(st) || fs::is_symlink(st)) fs::remove(p, ec);
    remove_abandoned_partials(p);
  }
}

/// The memory budget --max-memory names (or the default); a bad size is a usage error.
uint64_t memory_budget(const RenderOptions& opt) {
  try {
    return opt.max_memory.empty() ? default_memory_budget() : parse_byte_size(opt.max_memory);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--max-memory: ") + e.what());
  }
}

/// The outputs' formats, before anything is loaded or run.
void check_output_formats(const RenderOptions& opt) {
  if (!opt.out.empty() && !is_image_path(opt.out))
    throw UsageError("--out: " + opt.out + ": must be a .png or .exr file");
  if (!opt.id_map.empty() && !is_exr_path(opt.id_map))
    throw UsageError("--id-map: " + opt.id_map + ": must be an .exr file");
  if (!opt.error_map.empty() && opt.reference)
    throw UsageError(
        "--error-map: it explains the machine's image against the reference; not with "
        "--reference");
  if (!opt.error_map.empty() && !is_exr_path(opt.error_map))
    throw UsageError("--error-map: " + opt.error_map +
                     ": must be an .exr file (its picture is written beside it as .png)");
}

/// The PE engines' threads start before the image library loads: one started during the load
/// would wait for it. A configuration that is not valid is read again later and reported there,
/// after the scene's errors.
void start_engine_threads(const RenderOptions& opt, std::optional<MachineConfig>& early_config,
                          std::optional<WorkerPool>& engine_pool) {
  if (opt.reference) return;
  try {
    early_config = machine_config(opt);
  } catch (const UsageError&) {
  }
  if (early_config && engine_unsupported(*early_config, !opt.vcd.empty()).empty())
    engine_pool.emplace(engine_threads(opt.sim_threads, early_config->pes));
}

/// A scene as read: the scene, its text and the mesh files it includes (the reference cache's
/// key and the stats' scene_fnv1a), and the seconds it took.
struct LoadedScene {
  Scene scene;
  std::string text;
  double load_seconds = 0;
};

/// Reads the scene (the default one without a file), applies the scene options and checks it.
LoadedScene read_scene(const RenderOptions& opt, StepLine& steps, const StepProgress& progress) {
  LoadedScene in;
  const auto loading = std::chrono::steady_clock::now();
  SceneReadOptions read;
  read.strict = opt.strict;
  read.skip_unknown = opt.skip_unknown;
  read.progress = progress;
  in.scene = opt.scene.empty() ? default_scene() : load_scene(opt.scene, read);
  in.load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - loading).count();
  steps.erase();
  for (const std::string& w : skipped_warnings(in.scene, opt.scene))
    std::cerr << "rtm: warning: " << w << "\n";
  in.text = opt.scene.empty() ? std::string(kDefaultSceneYaml) : read_text(opt.scene);
  // The mesh files a YAML scene includes are as much the scene as its own text.
  std::set<std::string> included;
  for (const SourceLocation& o : in.scene.origins)
    if (!opt.scene.empty() && o.file != opt.scene && included.insert(o.file).second)
      in.text += "\n" + read_text(o.file);
  apply_scene_options(opt, in.scene);
  validate(in.scene);
  return in;
}

/// The options of the machine's run, and the warnings about them: PEs left without pixels, a
/// waveform of fast timing.
MachineOptions machine_run_options(const RenderOptions& opt, const MachineConfig& config,
                                   const Scene& scene, uint64_t budget, WorkerPool* pool) {
  MachineOptions mopt = opt.reference ? MachineOptions{} : machine_options(opt, config);
  mopt.pool = pool;
  if (const int idle =
          opt.reference ? 0 : pes_without_pixels(scene.camera.width, scene.camera.height, config))
    std::cerr << "rtm: warning: " << idle << " of " << config.pes
              << " PEs have no pixels to render (partition " << to_string(config.partition)
              << (config.partition == Partition::Blocks ? ", tile " + std::to_string(config.tile)
                                                        : std::string())
              << ", " << scene.camera.width << "x" << scene.camera.height
              << " pixels): they stay idle\n";
  if (!mopt.vcd.empty() && config.timing == Timing::Fast)
    std::cerr << "rtm: warning: --vcd in fast timing records the FIFOs and each unit's busy flag "
                 "and ray; the MAC "
                 "pipeline's signals (m1_*, m2_*, acc, product_counter) need --timing clocked\n";
  mopt.max_memory = budget;
  return mopt;
}

/// The files the render writes, each checked writable and cleared of what an earlier run left.
RenderFiles prepare_outputs(const RenderOptions& opt, const Scene& scene,
                            const MachineOptions& mopt) {
  RenderFiles files;
  files.image = opt.out.empty() ? "out/" + scene.name + ".png" : opt.out;
  files.stats = opt.stats.empty()
                    ? (std::filesystem::path(files.image).replace_extension(".json")).string()
                    : opt.stats;
  files.id_map = opt.id_map;
  if (!opt.error_map.empty()) {
    files.error_map = opt.error_map;
    files.error_picture = std::filesystem::path(opt.error_map).replace_extension(".png").string();
  }
  if (!opt.reference && !opt.vcd.empty()) {
    files.vcd = vcd_file(opt.vcd);
    files.gtkw = mopt.gtkw;
  }
  check_writable("--out", files.image);
  check_writable("--stats", files.stats);
  check_writable("--id-map", files.id_map);
  check_writable("--error-map", files.error_map);
  check_writable("--vcd", files.vcd);
  check_writable("--vcd", files.gtkw);
  if (!opt.reference) check_writable("--event-log", opt.event_log);
  // The statistics are written last: an image without them is from a run that did not finish.
  clear_outputs({files.image, files.stats, files.id_map, files.error_map, files.error_picture,
                 files.vcd, files.gtkw, opt.reference ? "" : opt.event_log});
  return files;
}

/// Before any frame-sized allocation: what the render will need, against the budget, and a note
/// when a primary ray's tree may grow beyond what can finish.
void check_render_size(const RenderOptions& opt, const Scene& scene, const Grid& grid,
                       const MachineConfig& config, uint64_t budget) {
  check_memory_budget(estimate_memory(scene, grid, opt.reference ? nullptr : &config,
                                      !opt.vcd.empty(), opt.threads),
                      budget, !opt.max_memory.empty());
  if (const double tree = rays_per_primary_bound(scene); tree > 1e6)
    std::cerr << "rtm: note: one primary ray can grow into up to " << std::setprecision(3) << tree
              << " rays (max_depth " << scene.max_depth << ", threshold " << scene.threshold
              << "): the render may not finish; it stops if its ray trees "
              << (opt.reference ? "" : "outgrow --max-memory or ")
              << "pass --max-rays, and Ctrl-C stops it cleanly\n";
}

/// The reference alone: its image, ID map and statistics, and its summary.
int render_reference_only(const RenderOptions& opt, const Scene& scene, const Grid& grid,
                          double grid_seconds, const ReferenceWatch& watch,
                          const RenderFiles& files, nlohmann::json& stats) {
  const ReferenceResult r = render_reference(scene, grid, opt.threads, watch);
  write_image(files.image, r.image);
  if (!opt.id_map.empty()) write_id_map(opt.id_map, r.image);
  stats.update(reference_render_json(r));
  stats["grid_build_seconds"] = grid_seconds;  // beside the trace's wall_seconds
  write_text_atomically(files.stats, stats.dump(2) + "\n");
  if (!opt.quiet) print_reference_summary(scene, grid, grid_seconds, r, files);
  return 0;
}

/// The machine's frame: run, compared with the reference, its differing pixels explained, its
/// image, maps and statistics written and its summary printed. The exit status.
int render_on_machine(const RenderOptions& opt, const LoadedScene& in, const Grid& grid,
                      double grid_seconds, const MachineConfig& config, const MachineOptions& mopt,
                      const ReferenceWatch& watch, const RenderFiles& files,
                      nlohmann::json& stats) {
  const Scene& scene = in.scene;
  const MachineResult m = run_machine(scene, grid, config, mopt);
  for (const std::string& w : m.warnings) std::cerr << "rtm: warning: " << w << "\n";
  if (m.deadlock) {
    std::cerr << "rtm: deadlock: the simulation stopped with rays outstanding; no image written\n"
              << m.deadlock_report;
    return 3;
  }
  bool cache_hit = false;
  const ReferenceResult ref =
      cached_reference(scene, grid, in.text, &cache_hit, watch, config.pe_frame);
  ImageError err;
  try {
    err = compare_images(m.image, ref.image);
  } catch (const NonFiniteImage& e) {
    // Nothing is written: no figure of this run would mean anything.
    std::cerr << "rtm: the machine's image cannot be compared with the reference: " << e.what()
              << "; no image written\n";
    return 1;
  }

  // Only the differing pixels are traced again, through a PE's units and the reference.
  const ErrorCauses causes = explain_errors(scene, grid, config, m.image, ref.image);

  write_image(files.image, m.image);
  if (!opt.id_map.empty()) write_id_map(opt.id_map, m.image);
  if (!files.error_map.empty()) {
    write_channels(files.error_map, error_map_channels(causes));
    write_image(files.error_picture, error_map_picture(causes, m.image));
  }
  const MachineCost cost =
      frame_cost(m, config, uint64_t(scene.camera.width) * uint64_t(scene.camera.height),
                 scene.primitives.size(), technology(config.tech));
  stats.update(machine_render_json(m, config, cost, err, causes, ref, cache_hit));
  stats["grid_build_seconds"] = grid_seconds;  // beside the model's wall_seconds
  write_text_atomically(files.stats, stats.dump(2) + "\n");
  if (!opt.quiet)
    print_machine_summary(scene, grid, grid_seconds, config, m, cost, err, causes, ref, cache_hit,
                          files);
  return 0;
}

}  // namespace

int run_render(const RenderOptions& opt) {
  // Outputs are written under temporary names and renamed; a signal removes the temporaries.
  remove_partial_files_on_signals();
  return run_command([&] {
    const uint64_t budget = memory_budget(opt);
    check_output_formats(opt);
    std::optional<MachineConfig> early_config;
    std::optional<WorkerPool> engine_pool;
    start_engine_threads(opt, early_config, engine_pool);
    // Its ~0.2 s of loading overlaps parsing and rendering instead of following them.
    preload_image_library();
    // However the render ends (a bad option, a deadlock), the load is over before rtm exits.
    struct LoadFinished {
      ~LoadFinished() { finish_loading_image_library(); }
    } load_finished;
    // A mesh of a million triangles takes seconds to load and to voxelise: a line shows how it
    // goes.
    StepLine steps(!opt.quiet && isatty(2));
    const StepProgress progress = std::ref(steps);
    LoadedScene in = read_scene(opt, steps, progress);
    // The reference alone reads the configuration too: its shading follows the machine's
    // normal_interpolation (--preset paper: flat), so that it renders what that machine would.
    const MachineConfig config = early_config ? *early_config : machine_config(opt);
    in.scene.normal_interpolation = config.normal_interpolation;
    const MachineOptions mopt =
        machine_run_options(opt, config, in.scene, budget, engine_pool ? &*engine_pool : nullptr);
    const RenderFiles files = prepare_outputs(opt, in.scene, mopt);

    const auto t0 = std::chrono::steady_clock::now();
    // One thread: a thread started while the image library loads waits for the dynamic loader's
    // lock until the load is done (measured: 0.3 s instead of 0.05 s for balls-4 with two).
    const Grid grid = build_grid(in.scene.primitives, in.scene.grid, 1, progress);
    const double grid_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    steps.erase();
    nlohmann::json stats = run_json(opt.command_line, opt.scene, in.text);
    stats.update(scene_json(in.scene, grid, grid_seconds));
    stats["load_seconds"] = in.load_seconds;

    check_render_size(opt, in.scene, grid, config, budget);
    // The reference, alone or after the machine, is watched as the simulation is.
    const ReferenceWatch watch{!opt.quiet && isatty(2), budget, uint64_t(opt.max_rays)};
    if (opt.reference)
      return render_reference_only(opt, in.scene, grid, grid_seconds, watch, files, stats);
    return render_on_machine(opt, in, grid, grid_seconds, config, mopt, watch, files, stats);
  });
}

}  // namespace rtm
