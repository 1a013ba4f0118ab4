#include "error/error_causes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <map>
#include <tuple>

#include "error/pe_tracer.h"
#include "render/camera.h"

namespace rtm {

const char* error_cause_name(ErrorCause c) {
  switch (c) {
    case ErrorCause::None:
      return "none";
    case ErrorCause::Missed:
      return "missed";
    case ErrorCause::ExtraHit:
      return "extra_hit";
    case ErrorCause::OtherPrimitive:
      return "other_primitive";
    case ErrorCause::ShadowBlocked:
      return "shadow_blocked";
    case ErrorCause::ShadowUnblocked:
      return "shadow_unblocked";
    case ErrorCause::HitPoint:
      return "hit_point";
    case ErrorCause::Spawned:
      return "spawned";
    case ErrorCause::Brightness:
      return "brightness";
    case ErrorCause::Unknown:
      break;
  }
  return "unknown";
}

bool pixel_differs(const Vec3& a, const Vec3& b) {
  const double limit = double(float(1.0 / 255.0));
  for (int c = 0; c < 3; ++c)
    if (std::abs(a[c] - b[c]) > limit) return true;
  return false;
}

namespace {

bool is_hit(RayResult::End e) { return e == RayResult::End::Hit || e == RayResult::End::Blocked; }

/// How a pair of rays traced from the same place parts; None: they agree.
ErrorCause part(const Ray& m_ray, const RayResult& m, const Ray& r_ray, const RayResult& r,
                double tolerance) {
  using End = RayResult::End;
  if (m.end != r.end) {
    if (m_ray.kind == RayKind::Shadow)
      return m.end == End::Blocked ? ErrorCause::ShadowBlocked : ErrorCause::ShadowUnblocked;
    return m.end == End::Hit ? ErrorCause::ExtraHit : ErrorCause::Missed;
  }
  if (m.end != End::Hit)
    return ErrorCause::None;  // both missed, both blocked or both reached the light
  if (m.prim != r.prim) return ErrorCause::OtherPrimitive;
  const Vec3 pm = m_ray.origin + m.t * m_ray.dir, pr = r_ray.origin + r.t * r_ray.dir;
  if (!(length(pm - pr) <= tolerance)) return ErrorCause::HitPoint;
  if (m.spawned.size() != r.spawned.size()) return ErrorCause::Spawned;
  for (size_t i = 0; i < m.spawned.size(); ++i)
    if (m.spawned[i].kind != r.spawned[i].kind) return ErrorCause::Spawned;
  return ErrorCause::None;
}

double brightness_gap(const PixelSum& a, const PixelSum& b) {
  const Vec3 d = a.value() - b.value();
  return std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
}

/// A ray in a tree, with its generation (a shadow ray is one more than the ray that spawned it,
/// although Ray::depth, which limits reflection and refraction, does not count it).
struct TreeRay {
  Ray ray;
  int generation = 1;
};

/// One side's breadth-first walk of a tree: traced rays and their pixel's running sum.
struct Side {
  Side(RayTracer& t, const Ray& primary) : tracer(t), queue{{primary, 1}} {}
  RayTracer& tracer;
  std::deque<TreeRay> queue;
  PixelSum sum;
  uint64_t traced = 0;
  std::array<uint64_t, kRayKinds> rays{};  ///< traced, by kind

  /// Traces the next ray into `out`, queues its children; false when the tree is done or too big.
  bool next(TreeRay& ray, RayResult& out, uint64_t max_rays) {
    if (queue.empty() || traced == max_rays) return false;
    ray = queue.front();
    queue.pop_front();
    ++traced;
    ++rays[size_t(ray.ray.kind)];
    tracer.trace(ray.ray, out);
    sum.add(out.added);
    for (const Ray& child : out.spawned) queue.push_back({child, ray.generation + 1});
    return true;
  }
  /// Traces the rest of the tree; false when it was too big to finish.
  bool finish(uint64_t max_rays) {
    TreeRay ray;
    RayResult out;
    while (next(ray, out, max_rays)) {
    }
    return queue.empty();
  }
};

int32_t hit_prim(const RayResult& r) { return is_hit(r.end) ? int32_t(r.prim) : -1; }

}  // namespace

Vec3 traced_pixel(RayTracer& tracer, const Ray& primary, uint64_t max_rays) {
  Side side(tracer, primary);
  if (!side.finish(max_rays))
    throw std::length_error("traced_pixel: the ray tree has more than max_rays rays");
  return side.sum.value();
}

PixelCause explain_pixel(const Ray& primary, RayTracer& machine, RayTracer& reference,
                         double hit_tolerance, const Vec3& machine_pixel,
                         const Vec3& reference_pixel, uint64_t max_rays, TreeWork* rays) {
  Side m(machine, primary), r(reference, primary);
  PixelCause cause, brightest;
  double widest = -1;
  TreeRay mr, rr;
  RayResult mo, ro;
  while (m.next(mr, mo, max_rays)) {
    if (!r.next(rr, ro, max_rays)) break;  // cannot happen while the trees agree
    const ErrorCause c = part(mr.ray, mo, rr.ray, ro, hit_tolerance);
    const PixelCause here{c, mr.generation, mr.ray.kind, hit_prim(mo), hit_prim(ro)};
    if (c != ErrorCause::None) {
      cause = here;
      break;
    }
    if (const double gap = brightness_gap(mo.added, ro.added); gap > widest) {
      widest = gap;
      brightest = here;
    }
  }
  if (cause.cause == ErrorCause::None) {
    cause = brightest;
    cause.cause = ErrorCause::Brightness;
  }
  // The trees must be the images' own: each traced to its end sums to its pixel exactly.
  const bool whole = m.finish(max_rays) & r.finish(max_rays);
  if (!whole || m.sum.value() != machine_pixel || r.sum.value() != reference_pixel)
    cause.cause = ErrorCause::Unknown;
  if (rays)
    for (size_t k = 0; k < size_t(kRayKinds); ++k)
      rays->machine.rays[k] += m.rays[k], rays->reference.rays[k] += r.rays[k];
  return cause;
}

std::vector<CountGap> count_gaps(const TraceCounts& machine, const TraceCounts& reference,
                                 const ErrorCauses& e) {
  std::map<std::string, int64_t> in_trees;
  for (const CountDifference& d : count_differences(e.trees.machine, e.trees.reference))
    in_trees[d.what] = int64_t(d.a) - int64_t(d.b);
  std::vector<CountGap> gaps;
  for (const CountDifference& d : count_differences(machine, reference)) {
    CountGap g{d, in_trees.count(d.what) ? in_trees[d.what] : 0};
    g.explained = e.trees_whole && g.in_trees == g.difference();
    gaps.push_back(g);
  }
  return gaps;
}

ErrorCauses explain_errors(const Scene& world, const Grid& world_grid, const MachineConfig& config,
                           const Image& machine, const Image& reference) {
  const auto t0 = std::chrono::steady_clock::now();
  // Both traced in the frame the machine and its reference computed in.
  const FramedScene view = framed(world, world_grid, config.pe_frame);
  const Scene& s = view.scene;
  const Grid& g = view.grid;
  ErrorCauses e;
  e.width = machine.width;
  e.height = machine.height;
  e.pixels.resize(machine.rgb.size());
  const PrimaryRays camera(s.camera);
  const double tolerance = kHitPointTolerance * length(g.box.hi - g.box.lo);
  std::unique_ptr<PeTracer> pe;
  std::unique_ptr<ReferenceTracer> ref;
  std::map<std::tuple<ErrorCause, int, RayKind>, uint64_t> tally;
  for (int y = 0; y < machine.height; ++y)
    for (int x = 0; x < machine.width; ++x) {
      const size_t i = size_t(y) * size_t(machine.width) + size_t(x);
      if (!pixel_differs(machine.rgb[i], reference.rgb[i])) continue;
      if (!pe) {  // only a frame with differing pixels pays for the tracers' scene copies
        pe = std::make_unique<PeTracer>(s, g, config);
        ref = std::make_unique<ReferenceTracer>(s, g);
      }
      const PixelCause c = explain_pixel(camera.at(x, y), *pe, *ref, tolerance, machine.rgb[i],
                                         reference.rgb[i], kTreeRayLimit, &e.trees);
      e.trees_whole &= c.cause != ErrorCause::Unknown;
      e.pixels[i] = c;
      ++e.differing;
      ++e.by_cause[size_t(c.cause)];
      ++tally[{c.cause, c.generation, c.kind}];
      const int32_t prim = c.prim >= 0 ? c.prim : c.reference_prim;
      if (prim >= 0) ++e.by_shape[size_t(s.primitives[size_t(prim)].kind)];
    }
  for (const auto& [key, n] : tally)
    e.counts.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key), n});
  if (pe) {
    for (auto count :
         {&TraceCounts::voxel_steps, &TraceCounts::intersection_tests, &TraceCounts::clip_tests}) {
      e.trees.machine.*count = pe->counts().*count;
      e.trees.reference.*count = ref->counts().*count;
    }
  }
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

}  // namespace rtm
