#include "render/reference.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>
#include <utility>

#include "geom/occupancy.h"
#include "render/camera.h"
#include "render/pixel_sum.h"
#include "render/progress.h"
#include "render/shade.h"
#include "render/voxel_test.h"

namespace rtm {

void TraceCounts::add(const TraceCounts& o) {
  for (int k = 0; k < kRayKinds; ++k) rays[k] += o.rays[k];
  voxel_steps += o.voxel_steps;
  intersection_tests += o.intersection_tests;
  clip_tests += o.clip_tests;
}

std::vector<CountDifference> count_differences(const TraceCounts& a, const TraceCounts& b) {
  std::vector<CountDifference> d;
  for (int k = 0; k < kRayKinds; ++k)
    if (a.rays[size_t(k)] != b.rays[size_t(k)])
      d.push_back(
          {std::string(ray_kind_name(RayKind(k))) + " rays", a.rays[size_t(k)], b.rays[size_t(k)]});
  for (auto [count, name] : {std::pair{&TraceCounts::voxel_steps, "voxel steps"},
                             {&TraceCounts::intersection_tests, "intersection tests"},
                             {&TraceCounts::clip_tests, "clip tests"}})
    if (a.*count != b.*count) d.push_back({name, a.*count, b.*count});
  return d;
}

namespace {

/// A per-thread memo of each primitive's test against the current ray (a "mailbox"). A primitive
/// spanning several voxels is listed, and tested, in each of them, but its roots and clip tests
/// depend only on the ray; only the voxel window differs. So the MAC and root work runs once per
/// ray and primitive, with exactly the arithmetic of form_voxel_abg / resolve_voxel, and the
/// counters still count every listed test, as the machine performs them (§5.1).
class Mailbox {
 public:
  explicit Mailbox(size_t prims) : stamp_(prims, 0), hit_(prims) {}

  /// Starts a new ray: every slot becomes stale.
  void next_ray() {
    if (++serial_ == 0) {  // wrapped: clear, so no slot looks current
      std::fill(stamp_.begin(), stamp_.end(), 0u);
      serial_ = 1;
    }
  }

  /// The primitive's first hit beyond t = 0 in an unbounded window, computed once per ray.
  const PrimitiveHit& test(const SceneMemory<double>& mem, const Ray& ray, uint32_t id) {
    if (stamp_[id] != serial_) {
      stamp_[id] = serial_;
      const Latches<double> l = mem.latches(ray, id);
      const Abg<double> abg = form_abg_fast(l, mem.rams[id]);
      hit_[id] = first_hit_in_window(
          mem.clips[id], solve_quadratic(abg.a, abg.b, abg.g, mem.numerics.discriminant), l, 0.0,
          -kInf, kInf);
    }
    return hit_[id];
  }

 private:
  std::vector<uint32_t> stamp_;
  std::vector<PrimitiveHit> hit_;
  uint32_t serial_ = 0;
};

/// What the walk reads: the scene memory and the grid's occupancy.
struct TraceData {
  const SceneMemory<double>& mem;
  const Occupancy& occupied;
};

/// Where a walk over the whole grid ends: where the ray leaves the grid, or its t_max.
double walk_end(const Grid& g, const Ray& r) {
  double t = r.t_max;
  for (int a = 0; a < 3; ++a)
    if (r.dir[a] != 0)
      t = std::min(t, ((r.dir[a] > 0 ? g.box.hi[a] : g.box.lo[a]) - r.origin[a]) / r.dir[a]);
  return t;
}

/// The box of cells from `cell` to where the walk ends, one cell wider at the far end (so
/// rounding in the estimate cannot cut off a voxel the walk visits; Dda::skip_box is exact
/// whatever box it is given).
void rest_box(const Grid& g, const Ray& r, double t_end, const std::array<int, 3>& cell,
              std::array<int, 3>& lo, std::array<int, 3>& hi) {
  for (int a = 0; a < 3; ++a) {
    const double p = (r.origin[a] + t_end * r.dir[a] - g.box.lo[a]) / g.cell[a];
    const int e = !(p > 0) ? 0 : p >= g.n[a] ? g.n[a] - 1 : static_cast<int>(p);
    if (r.dir[a] > 0) {
      lo[a] = cell[a];
      hi[a] = std::min(std::max(e + 1, cell[a]), g.n[a] - 1);
    } else if (r.dir[a] < 0) {
      lo[a] = std::max(std::min(e - 1, cell[a]), 0);
      hi[a] = cell[a];
    } else {
      lo[a] = hi[a] = cell[a];
    }
  }
}

/// Walks one ray to its end; returns the hit that ends it (none: left the grid, or a shadow ray
/// that reached its light). Same result as the machine's voxel test (render/voxel_test.h) on every
/// occupied voxel: a memoised hit counts in a voxel exactly when first_hit_in_window would report
/// it there.
VoxelHit walk(const TraceData& d, const Ray& ray, TraceCounts& c, Mailbox& mb) {
  const SceneMemory<double>& mem = d.mem;
  const Grid& g = *mem.grid;
  mb.next_ray();
  double t_end = std::numeric_limits<double>::quiet_NaN();  // computed when first needed
  DdaState s = Dda::start(g, ray.origin, ray.dir, 0.0, ray.t_max);
  std::array<double, 3> ahead = Dda::ahead(g, ray.origin, ray.dir, s);
  for (; !s.done; Dda::advance_ahead(g, ray.origin, ray.dir, ray.t_max, s, ahead)) {
    ++c.voxel_steps;
    const int64_t v = g.index(s.cell[0], s.cell[1], s.cell[2]);
    if (!d.occupied.voxel(v)) {
      std::array<int, 3> lo, hi;
      if (d.occupied.empty_block(s.cell, lo, hi)) {
        // If nothing lies between here and where the walk ends, cross all of it at once.
        std::array<int, 3> rest_lo, rest_hi;
        if (std::isnan(t_end)) t_end = walk_end(g, ray);
        rest_box(g, ray, t_end, s.cell, rest_lo, rest_hi);
        if (d.occupied.box_empty(rest_lo, rest_hi)) {
          lo = rest_lo;
          hi = rest_hi;
        }
        if (const int k = Dda::skip_box(g, ray.origin, ray.dir, ray.t_max, s, lo, hi)) {
          c.voxel_steps += uint64_t(k);
          ahead = Dda::ahead(g, ray.origin, ray.dir, s);
        }
      }
      continue;
    }
    const uint32_t n = g.count(v);
    const double t_hi = window_end(ray, s);
    const double t_lo = s.t_enter - entry_reach(mem.numerics.origin, s, t_hi);
    const uint32_t* ids = g.begin(v);
    VoxelHit best;
    for (uint32_t i = 0; i < n; ++i) {
      const PrimitiveHit& h = mb.test(mem, ray, ids[i]);
      ++best.tests;
      best.clip_tests += uint32_t(h.clip_tests);
      // Ties go to the lower primitive number, the order the voxel lists them in.
      if (h.hit && h.t >= t_lo && h.t <= t_hi && h.t < best.t) {
        best.hit = true;
        best.t = h.t;
        best.prim = ids[i];
      }
    }
    c.intersection_tests += best.tests;
    c.clip_tests += best.clip_tests;
    if (best.hit) return best;
  }
  return VoxelHit{};
}

/// What the workers share with the watch: how far they are, and its word to stop.
struct Shared {
  std::atomic<uint64_t> rays{0}, pixels{0};
  std::atomic<bool> stop{false};
};
/// A worker adds its rays to Shared::rays, and looks whether to stop, this often: inside one
/// pixel too, whose tree may never end.
constexpr uint64_t kRaysPerReport = 4096;

/// Traces a pixel's whole ray tree depth first.
struct Scratch {
  explicit Scratch(size_t prims) : mailbox(prims) {}
  std::vector<Ray> stack;
  Mailbox mailbox;
  ShadeOut shade;
  RayResult result;
  uint64_t unreported = 0;  ///< rays traced since the last report to Shared
};

/// One ray, as the reference renderer traces it. `shade` is scratch.
void trace_ray(const TraceData& d, const Ray& ray, TraceCounts& c, Mailbox& mb, ShadeOut& shade,
               RayResult& out) {
  const Scene& s = *d.mem.scene;
  const VoxelHit h = walk(d, ray, c, mb);
  out.added = PixelSum{};
  out.spawned.clear();
  out.prim = h.prim;
  out.t = h.t;
  if (ray.kind == RayKind::Shadow) {
    out.end = h.hit ? RayResult::End::Blocked : RayResult::End::LightReached;
    if (!h.hit) out.added.add(ray.brightness);
    return;
  }
  if (!h.hit) {
    out.end = RayResult::End::Missed;
    out.added.add(miss_brightness(s, ray));
    return;
  }
  out.end = RayResult::End::Hit;
  shade_hit(s, ray, h.t, s.primitives[h.prim], shade);
  out.added.add(shade.brightness);
  out.spawned.swap(shade.rays);
}

/// False when the watch said stop before the tree was done (the pixel is left unfinished).
bool trace_pixel(const TraceData& d, const Ray& primary, Image& img, TraceCounts& c, Scratch& w,
                 Shared& shared) {
  PixelSum sum;
  std::vector<Ray>& stack = w.stack;
  RayResult& out = w.result;
  stack.clear();
  stack.push_back(primary);
  while (!stack.empty()) {
    const Ray ray = stack.back();
    stack.pop_back();
    ++c.rays[size_t(ray.kind)];
    if (++w.unreported == kRaysPerReport) {
      shared.rays.fetch_add(w.unreported, std::memory_order_relaxed);
      w.unreported = 0;
      if (shared.stop.load(std::memory_order_relaxed)) return false;
    }
    trace_ray(d, ray, c, w.mailbox, w.shade, out);
    if (ray.kind == RayKind::Primary)
      img.ids[ray.pixel] = out.end == RayResult::End::Hit ? int32_t(out.prim) : -1;
    sum.add(out.added);
    // Reverse so rays are traced in the order shading spawned them.
    stack.insert(stack.end(), out.spawned.rbegin(), out.spawned.rend());
  }
  img.rgb[primary.pixel] = sum.value();
  shared.pixels.fetch_add(1, std::memory_order_relaxed);
  return true;
}

/// Every 50 ms of wall time while the workers run: the budgets, then (at most twice a second,
/// after the first) the progress line. Returns why the render must stop; empty: it goes on.
class Watcher {
 public:
  Watcher(const ReferenceWatch& w, const Scene& s, const Shared& shared)
      : watch_(w), scene_(s), shared_(shared) {}

  std::string look() {
    const auto now = std::chrono::steady_clock::now();
    const uint64_t rays = shared_.rays.load(std::memory_order_relaxed);
    const uint64_t pixels = uint64_t(scene_.camera.width) * uint64_t(scene_.camera.height);
    const std::string where = std::to_string(shared_.pixels.load(std::memory_order_relaxed)) +
                              " of " + std::to_string(pixels) + " pixels done";
    if (watch_.max_rays && rays > watch_.max_rays) {
      std::ostringstream why;
      why << "the reference render stopped at its work budget of " << watch_.max_rays
          << " rays (--max-rays), with " << where << ": the ray trees grow with max_depth "
          << scene_.max_depth << " and threshold " << scene_.threshold;
      return why.str();
    }
    if (const uint64_t rss = watch_.max_memory ? resident_bytes() : 0; rss > watch_.max_memory)
      return "the reference render stopped holding " + bytes_text(rss) +
             ", more than its memory budget of " + bytes_text(watch_.max_memory) +
             " (--max-memory), with " + where + " and " + std::to_string(rays) + " rays traced";
    if (watch_.progress && now - start_ >= std::chrono::seconds(1) &&
        now - last_draw_ >= std::chrono::milliseconds(500)) {
      last_draw_ = now;
      Progress p;
      p.phase = "reference";
      p.pixels_started = shared_.pixels.load(std::memory_order_relaxed);
      p.pixels = pixels;
      p.seconds = std::chrono::duration<double>(now - start_).count();
      p.rays = rays;
      p.resident_bytes = resident_bytes();
      std::fprintf(stderr, "\r%-79s", progress_line(p).c_str());
      std::fflush(stderr);
      drew_ = true;
    }
    return {};
  }

  ~Watcher() {
    if (drew_) std::fprintf(stderr, "\r%80s\r", "");
  }

 private:
  const ReferenceWatch& watch_;
  const Scene& scene_;
  const Shared& shared_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_draw_ = start_;
  bool drew_ = false;
};

}  // namespace

const char* reference_build_id() { return __DATE__ " " __TIME__; }

ReferenceResult render_reference(const Scene& world, const Grid& world_grid, int threads,
                                 const ReferenceWatch& watch, PeFrame frame) {
  const auto t0 = std::chrono::steady_clock::now();
  const FramedScene view = framed(world, world_grid, frame);
  const Scene& s = view.scene;
  const Grid& g = view.grid;
  ReferenceResult r;
  r.image = Image(s.camera.width, s.camera.height);
  const SceneMemory<double> mem(s, g);
  const Occupancy occupied(g);
  const TraceData data{mem, occupied};
  const PrimaryRays camera(s.camera);
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));

  std::atomic<int> next_row{0};
  std::vector<TraceCounts> counts(static_cast<size_t>(threads));
  Shared shared;
  std::mutex m;
  std::condition_variable finished;
  int running = threads;
  auto worker = [&](int id) {
    Scratch scratch(s.primitives.size());
    TraceCounts mine;  // local, not counts[id]: neighbouring entries share a cache line
    bool go = true;
    for (int y; go && (y = next_row.fetch_add(1)) < s.camera.height;)
      for (int x = 0; go && x < s.camera.width; ++x)
        go = trace_pixel(data, camera.at(x, y), r.image, mine, scratch, shared);
    counts[size_t(id)] = mine;
    const std::lock_guard<std::mutex> lock(m);
    --running;
    finished.notify_one();
  };
  // The watch has a thread of its own. A thread started while the image library loads waits for
  // the loader's lock, so the first one waits here until it has loaded: not the reference's time.
  std::string stopped;
  const auto before_watch = std::chrono::steady_clock::now();
  std::thread watching([&] {
    Watcher watcher(watch, s, shared);
    std::unique_lock<std::mutex> lock(m);
    while (!finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return running == 0; }))
      if (stopped.empty() && !(stopped = watcher.look()).empty()) shared.stop = true;
  });
  const auto waited_for_loader = std::chrono::steady_clock::now() - before_watch;
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker, i);
  worker(0);
  for (auto& t : pool) t.join();
  watching.join();
  if (!stopped.empty()) throw BudgetExceeded(stopped);
  for (const TraceCounts& c : counts) r.counts.add(c);
  r.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0 - waited_for_loader)
          .count();
  return r;
}

struct ReferenceTracer::State {
  State(const Scene& s, const Grid& g)
      : mem(s, g), occupied(g), data{mem, occupied}, mailbox(s.primitives.size()) {}
  const SceneMemory<double> mem;
  const Occupancy occupied;
  const TraceData data;
  Mailbox mailbox;
  ShadeOut shade;
  TraceCounts counts;
};

ReferenceTracer::ReferenceTracer(const Scene& s, const Grid& g)
    : state_(std::make_unique<State>(s, g)) {}
ReferenceTracer::~ReferenceTracer() = default;

void ReferenceTracer::trace(const Ray& ray, RayResult& out) {
  trace_ray(state_->data, ray, state_->counts, state_->mailbox, state_->shade, out);
}

const TraceCounts& ReferenceTracer::counts() const { return state_->counts; }

}  // namespace rtm
