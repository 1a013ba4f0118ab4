#include "render/reference.h"

#include <atomic>
#include <chrono>
#include <thread>

#include "render/camera.h"
#include "render/pixel_sum.h"
#include "render/shade.h"
#include "render/trace.h"

namespace rtm {

void TraceCounts::add(const TraceCounts& o) {
  for (int k = 0; k < kRayKinds; ++k) rays[k] += o.rays[k];
  voxel_steps += o.voxel_steps;
  intersection_tests += o.intersection_tests;
  clip_tests += o.clip_tests;
}

namespace {

/// Walks one ray to its end; returns the hit that ends it (none: left the grid, or a shadow ray
/// that reached its light).
VoxelHit walk(const SceneMemory<double>& mem, const Ray& ray, TraceCounts& c, std::vector<Abg<double>>& abg) {
  const Grid& g = *mem.grid;
  for (DdaState s = Dda::start(g, ray.origin, ray.dir, 0.0, ray.t_max); !s.done;
       Dda::advance(g, ray.origin, ray.dir, ray.t_max, s)) {
    ++c.voxel_steps;
    if (g.count(g.index(s.cell[0], s.cell[1], s.cell[2])) == 0) continue;
    const VoxelHit h = intersect_voxel(mem, ray, s, abg);
    c.intersection_tests += h.tests;
    c.clip_tests += h.clip_tests;
    if (h.hit) return h;
  }
  return VoxelHit{};
}

/// Traces a pixel's whole ray tree depth first.
struct Scratch {
  std::vector<Ray> stack;
  std::vector<Abg<double>> abg;
  ShadeOut shade;
};

void trace_pixel(const SceneMemory<double>& mem, const Ray& primary, Image& img, TraceCounts& c, Scratch& w) {
  const Scene& s = *mem.scene;
  PixelSum sum;
  std::vector<Ray>& stack = w.stack;
  ShadeOut& out = w.shade;
  stack.clear();
  stack.push_back(primary);
  while (!stack.empty()) {
    const Ray ray = stack.back();
    stack.pop_back();
    ++c.rays[size_t(ray.kind)];
    const VoxelHit h = walk(mem, ray, c, w.abg);
    if (ray.kind == RayKind::Shadow) {
      if (!h.hit) sum.add(ray.brightness);
      continue;
    }
    if (ray.kind == RayKind::Primary) img.ids[ray.pixel] = h.hit ? int32_t(h.prim) : -1;
    if (!h.hit) {
      sum.add(miss_brightness(s, ray));
      continue;
    }
    shade_hit(s, ray, h.t, s.primitives[h.prim], out);
    sum.add(out.brightness);
    // Reverse so rays are traced in the order shading spawned them.
    stack.insert(stack.end(), out.rays.rbegin(), out.rays.rend());
  }
  img.rgb[primary.pixel] = sum.value();
}

}  // namespace

const char* reference_build_id() { return __DATE__ " " __TIME__; }

ReferenceResult render_reference(const Scene& s, const Grid& g, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  ReferenceResult r;
  r.image = Image(s.camera.width, s.camera.height);
  const SceneMemory<double> mem(s, g);
  const PrimaryRays camera(s.camera);
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));

  std::atomic<int> next_row{0};
  std::vector<TraceCounts> counts(static_cast<size_t>(threads));
  auto worker = [&](int id) {
    Scratch scratch;
    for (int y; (y = next_row.fetch_add(1)) < s.camera.height;)
      for (int x = 0; x < s.camera.width; ++x) trace_pixel(mem, camera.at(x, y), r.image, counts[size_t(id)], scratch);
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker, i);
  worker(0);
  for (auto& t : pool) t.join();
  for (const TraceCounts& c : counts) r.counts.add(c);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rtm
