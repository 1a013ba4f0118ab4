// `rtm render`: load a scene, pre-process it, render it on the machine (or the reference),
// compare, write the image and the statistics.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "machine/machine.h"
#include "options.h"
#include "printed_summary.h"
#include "reference_cache.h"
#include "render/image_io.h"
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

}  // namespace

int run_render(const RenderOptions& opt) {
  try {
    // Its ~0.2 s of loading overlaps parsing and rendering instead of following them.
    preload_image_library();
    Scene scene = opt.scene.empty() ? default_scene() : load_scene(opt.scene, {opt.strict, opt.skip_unknown});
    for (const std::string& w : skipped_warnings(scene, opt.scene)) std::cerr << "rtm: warning: " << w << "\n";
    const std::string scene_text = opt.scene.empty() ? std::string(kDefaultSceneYaml) : read_text(opt.scene);
    apply_scene_options(opt, scene);
    validate(scene);
    const MachineConfig config = opt.reference ? MachineConfig{} : machine_config(opt);
    const MachineOptions mopt = opt.reference ? MachineOptions{} : machine_options(opt, config);

    RenderFiles files;
    files.image = opt.out.empty() ? "out/" + scene.name + ".png" : opt.out;
    files.stats =
        opt.stats.empty() ? (std::filesystem::path(files.image).replace_extension(".json")).string() : opt.stats;
    files.id_map = opt.id_map;

    const auto t0 = std::chrono::steady_clock::now();
    // One thread: a thread started while the image library loads waits for the dynamic loader's
    // lock until the load is done (measured: 0.3 s instead of 0.05 s for balls-4 with two).
    const Grid grid = build_grid(scene.primitives, scene.grid, 1);
    const double grid_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json stats = scene_json(scene, grid, grid_seconds);

    if (opt.reference) {
      const ReferenceResult r = render_reference(scene, grid, opt.threads);
      write_image(files.image, r.image);
      if (!opt.id_map.empty()) write_id_map(opt.id_map, r.image);
      stats.update(reference_render_json(r));
      stats["grid_build_seconds"] = grid_seconds;  // beside the trace's wall_seconds
      write_text_atomically(files.stats, stats.dump(2) + "\n");
      if (!opt.quiet) print_reference_summary(scene, grid, grid_seconds, r, files);
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

    write_image(files.image, m.image);
    if (!opt.id_map.empty()) write_id_map(opt.id_map, m.image);
    if (!opt.vcd.empty()) {
      files.vcd = opt.vcd;
      files.gtkw = mopt.gtkw;
    }
    stats.update(machine_render_json(m, config, err, ref, cache_hit));
    stats["grid_build_seconds"] = grid_seconds;  // beside the model's wall_seconds
    write_text_atomically(files.stats, stats.dump(2) + "\n");
    if (!opt.quiet) print_machine_summary(scene, grid, grid_seconds, config, m, err, ref, cache_hit, files);
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
