#include "render/reference.h"

#include <atomic>
#include <chrono>
#include <thread>
#include <utility>

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
      hit_[id] = first_hit_in_window(mem.clips[id], solve_quadratic(abg.a, abg.b, abg.g, mem.numerics.discriminant), l,
                                   0.0, -kInf, kInf);
    }
    return hit_[id];
  }

 private:
  std::vector<uint32_t> stamp_;
  std::vector<PrimitiveHit> hit_;
  uint32_t serial_ = 0;
};

/// One bit per voxel: is it occupied? The walk asks this for every voxel it steps through; the
/// bitmap is 32 times smaller than the grid's start array, so it stays in cache on fine grids,
/// where the start array's misses were the largest single cost. A second, coarser map marks
/// blocks of 8³ voxels holding any occupied voxel, so a walk can cross an empty block at once.
class Occupancy {
 public:
  static constexpr int kShift = 3;  ///< blocks of 8³ voxels
  explicit Occupancy(const Grid& g) : bits_(size_t(g.voxel_count() + 63) / 64, 0) {
    for (int a = 0; a < 3; ++a) nb_[a] = ((g.n[a] - 1) >> kShift) + 1;
    blocks_.assign(size_t(nb_[0]) * nb_[1] * nb_[2], 0);
    for (int z = 0; z < g.n[2]; ++z)
      for (int y = 0; y < g.n[1]; ++y)
        for (int x = 0; x < g.n[0]; ++x) {
          const int64_t v = g.index(x, y, z);
          if (g.count(v) == 0) continue;
          bits_[size_t(v) >> 6] |= uint64_t(1) << (v & 63);
          blocks_[block({x, y, z})] = 1;
        }
  }
  bool operator[](int64_t v) const { return bits_[size_t(v) >> 6] >> (v & 63) & 1; }
  bool block_empty(const std::array<int, 3>& cell) const { return blocks_[block(cell)] == 0; }

 private:
  size_t block(const std::array<int, 3>& c) const {
    return (size_t(c[2] >> kShift) * nb_[1] + size_t(c[1] >> kShift)) * nb_[0] + size_t(c[0] >> kShift);
  }
  std::array<int, 3> nb_{};
  std::vector<uint64_t> bits_;
  std::vector<uint8_t> blocks_;
};

/// Dda's crossing, repeated for the block skip below, which must reproduce Dda::advance bit for
/// bit: keep the two expressions identical.
inline double crossing(const Grid& g, const Vec3& o, const Vec3& d, int axis, int cell) {
  if (d[axis] == 0) return kInf;
  const int boundary = d[axis] > 0 ? cell + 1 : cell;
  return (g.plane(axis, boundary) - o[axis]) / d[axis];
}

/// Moves the walk from a voxel of an empty block to the block's last voxel on the ray, in one
/// go, leaving `s` exactly as the Dda::advance calls it replaces would; returns how many voxels
/// that entered (each one a voxel step to count). 0 leaves `s` alone.
///
/// Dda::advance crosses planes in order of (t, axis), ties to the lower axis, and each axis's
/// crossings grow monotonically with its cell index (t_next is recomputed from the index, so
/// there is no drift). The walk leaves the block at the first of the three "leave the block's
/// last cell on this axis" crossings; every crossing ordered before that one happens inside the
/// block, and counting them per axis gives the cell where the walk stands just before it leaves.
int skip_empty_block(const Grid& g, const Ray& ray, DdaState& s) {
  const Vec3 &o = ray.origin, &d = ray.dir;
  constexpr int kShift = Occupancy::kShift;
  std::array<int, 3> last = s.cell;  // the block's last cell on each axis, in the walk's direction
  double t_out = kInf;
  int axis_out = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    const int first = (s.cell[a] >> kShift) << kShift;
    last[a] = d[a] > 0 ? std::min(first + (1 << kShift) - 1, g.n[a] - 1) : first;
    const double t = crossing(g, o, d, a, last[a]);
    if (t < t_out) {  // strict: a tie goes to the lower axis, as in Dda
      t_out = t;
      axis_out = a;
    }
  }
  // The walk might end inside the block (a shadow ray reaching its light): step normally.
  if (axis_out < 0 || !(t_out <= ray.t_max)) return 0;

  DdaState n = s;
  int steps = 0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    const int dir = d[a] > 0 ? 1 : -1;
    // Crossings of this axis ordered before (t_out, axis_out); on axis_out itself that is every
    // cell before the last.
    int cell = s.cell[a];
    while (cell != last[a]) {
      const double t = crossing(g, o, d, a, cell);
      if (a != axis_out && !(t < t_out || (t == t_out && a < axis_out))) break;
      n.t_enter = std::max(n.t_enter, t);  // each step's t_enter is the previous t_exit
      cell += dir;
      ++steps;
    }
    n.cell[a] = cell;
    n.t_next[a] = crossing(g, o, d, a, cell);
  }
  if (steps == 0) return 0;
  int a = 0;  // Dda::exit_axis
  if (n.t_next[1] < n.t_next[a]) a = 1;
  if (n.t_next[2] < n.t_next[a]) a = 2;
  n.t_exit = std::max(n.t_enter, n.t_next[a]);
  s = n;
  return steps;
}

/// What the walk reads: the scene memory and the grid's occupancy.
struct TraceData {
  const SceneMemory<double>& mem;
  const Occupancy& occupied;
};

/// Walks one ray to its end; returns the hit that ends it (none: left the grid, or a shadow ray
/// that reached its light). Same result as intersect_voxel on every occupied voxel: a memoised
/// hit counts in a voxel exactly when first_hit_in_window would report it there.
VoxelHit walk(const TraceData& d, const Ray& ray, TraceCounts& c, Mailbox& mb) {
  const SceneMemory<double>& mem = d.mem;
  const Grid& g = *mem.grid;
  mb.next_ray();
  for (DdaState s = Dda::start(g, ray.origin, ray.dir, 0.0, ray.t_max); !s.done;
       Dda::advance(g, ray.origin, ray.dir, ray.t_max, s)) {
    ++c.voxel_steps;
    const int64_t v = g.index(s.cell[0], s.cell[1], s.cell[2]);
    if (!d.occupied[v]) {
      if (d.occupied.block_empty(s.cell)) c.voxel_steps += uint64_t(skip_empty_block(g, ray, s));
      continue;
    }
    const uint32_t n = g.count(v);
    const double t_hi = window_end(ray, s);
    const uint32_t* ids = g.begin(v);
    VoxelHit best;
    for (uint32_t i = 0; i < n; ++i) {
      const PrimitiveHit& h = mb.test(mem, ray, ids[i]);
      ++best.tests;
      best.clip_tests += uint32_t(h.clip_tests);
      // Ties go to the lower primitive number, the order the voxel lists them in.
      if (h.hit && h.t >= s.t_enter && h.t <= t_hi && h.t < best.t) {
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

/// Traces a pixel's whole ray tree depth first.
struct Scratch {
  explicit Scratch(size_t prims) : mailbox(prims) {}
  std::vector<Ray> stack;
  Mailbox mailbox;
  ShadeOut shade;
};

void trace_pixel(const TraceData& d, const Ray& primary, Image& img, TraceCounts& c, Scratch& w) {
  const Scene& s = *d.mem.scene;
  PixelSum sum;
  std::vector<Ray>& stack = w.stack;
  ShadeOut& out = w.shade;
  stack.clear();
  stack.push_back(primary);
  while (!stack.empty()) {
    const Ray ray = stack.back();
    stack.pop_back();
    ++c.rays[size_t(ray.kind)];
    const VoxelHit h = walk(d, ray, c, w.mailbox);
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
  const Occupancy occupied(g);
  const TraceData data{mem, occupied};
  const PrimaryRays camera(s.camera);
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));

  std::atomic<int> next_row{0};
  std::vector<TraceCounts> counts(static_cast<size_t>(threads));
  auto worker = [&](int id) {
    Scratch scratch(s.primitives.size());
    TraceCounts mine;  // local, not counts[id]: neighbouring entries share a cache line
    for (int y; (y = next_row.fetch_add(1)) < s.camera.height;)
      for (int x = 0; x < s.camera.width; ++x) trace_pixel(data, camera.at(x, y), r.image, mine, scratch);
    counts[size_t(id)] = mine;
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
