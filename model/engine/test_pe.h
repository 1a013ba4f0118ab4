// For the PE engine's tests: one PE rendering a small frame of an SPD scene in process, on the
// engine or on the plain driver (engine/cycle_driver.h), with its event log. pe_engine_test.cpp
// and the test unit's test (model/test_unit/) use it.
#pragma once

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/cycle_driver.h"
#include "engine/pe_engine.h"
#include "geom/grid.h"
#include "memory/memory_layout.h"
#include "memory/scene_image.h"
#include "render/camera.h"
#include "scene/grid_frame.h"
#include "scene/scene.h"

namespace rtm::test {

constexpr uint64_t kCycle = 10000;  // ticks: a 10 ns clock at SystemC's 1 ps resolution

/// One PE rendering all of a small frame of an SPD scene, with its event log.
struct EnginePe {
  Scene scene;
  Grid grid;
  FramedScene view;
  std::vector<Ray> rays;
  PeState pe;
  EventLog log;
  std::vector<PixelSum> frame;
  std::vector<int32_t> ids;

  EnginePe(const std::string& spd, int size, const MachineConfig& c) {
    scene = load_scene(std::string(RTM_SOURCE_DIR) + "/scenes/spd/" + spd + ".nff");
    scene.camera.width = scene.camera.height = size;
    grid = build_grid(scene.primitives, scene.grid, 1);
    view = framed(scene, grid, c.pe_frame);
    const PrimaryRays camera(view.scene.camera);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) rays.push_back(camera.at(x, y));
    pe.config = c;
    pe.cycle = kCycle;
    pe.log = &log;
    pe.counters.size_for(c);
    pe.image = std::make_shared<SceneImage>(view.scene, view.grid, c);
    pe.memory = std::make_shared<PeMemory>(c, *pe.image, rays.size());
    pe.spill_rays = memory_layout(*pe.image, rays.size(), c).spill_rays();
    pe.spawn_fanout = view.scene.lights.size() + 2;
    frame.assign(rays.size(), PixelSum{});
    ids.assign(rays.size(), -1);
  }

  /// Runs the frame to its end; returns the event log's lines.
  std::vector<std::string> run() {
    PeEngine engine(pe, frame, ids, rays, rays.size());
    engine.rays_arrived(0, rays.size(), rays.size());
    engine.run_before(UINT64_MAX);
    EXPECT_TRUE(engine.finished()) << engine.occupancy_report();
    EXPECT_TRUE(engine.idle());
    for (const auto& [name, stats] : engine.fifo_stats(pe.counters.finish, 1e-12))
      EXPECT_GT(stats->depth, 0) << name;
    return lines();
  }
  /// The same on the plain driver (engine/cycle_driver.h).
  std::vector<std::string> run_cycle_driver() {
    CycleDriver driver(pe, frame, ids, rays);
    EXPECT_TRUE(driver.run(10'000'000));
    return lines();
  }
  std::vector<std::string> lines() {
    std::vector<EventLog> logs{log};
    std::ostringstream text;
    write_event_log(text, logs, kCycle);
    std::vector<std::string> lines;
    std::istringstream in(text.str());
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
};

}  // namespace rtm::test
