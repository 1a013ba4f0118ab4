// Why each pixel differs from the reference (docs/numerics.md, "Why a pixel differs"). For a
// pixel off by more than 1/255, the machine's ray tree and the reference's are traced again side
// by side, generation by generation, from the same primary ray; the first pair of rays that part
// names the pixel's cause: its generation, its kind, and how they part. Only the differing pixels
// are traced again, so this costs little beside the render.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geom/grid.h"
#include "config/config.h"
#include "render/ray_result.h"
#include "render/reference.h"
#include "scene/scene.h"

namespace rtm {

/// How the machine's ray and the reference's part. Numbered for the error map's `cause` channel.
enum class ErrorCause : uint8_t {
  None,             ///< the pixel is within 1/255 of the reference
  Missed,           ///< the machine's ray missed what the reference's hit
  ExtraHit,         ///< the machine's ray hit something where the reference's missed
  OtherPrimitive,   ///< both hit, different primitives
  ShadowBlocked,    ///< the machine's shadow ray was blocked, the reference's reached its light
  ShadowUnblocked,  ///< the machine's shadow ray reached its light, the reference's was blocked
  HitPoint,         ///< the same primitive, hit points further apart than the tolerance
  Spawned,          ///< the same hit, but one side spawned a ray the other did not
  Brightness,       ///< every ray alike within the tolerance; the brightness formed differs
  Unknown,          ///< a tree traced again did not sum to its image's pixel (never expected)
};
constexpr int kErrorCauses = 10;
constexpr int kShapeKinds = int(ShapeKind::Raw) + 1;
const char* error_cause_name(ErrorCause c);

/// Hit points of one primitive further apart than this fraction of the object space's diagonal
/// part two trees: about a fortieth of a pixel at 256 × 256 over the whole scene, far beyond the
/// ~1e-7 relative rounding of a float hit, so only a hit that moved for a reason counts.
constexpr double kHitPointTolerance = 1e-4;

/// A pixel's cause, and the pair of rays it is named by (for Brightness: the pair whose own
/// brightness differs most; for Spawned: the parent).
struct PixelCause {
  ErrorCause cause = ErrorCause::None;
  int generation = 0;               ///< of the parting ray: 1 for the primary ray; 0 for none
  RayKind kind = RayKind::Primary;  ///< of the parting ray
  int32_t prim = -1;  ///< what the machine's parting ray hit or was blocked by; -1: nothing
  int32_t reference_prim = -1;  ///< the same for the reference's
};

/// The rays traced of one tree at most, on each side.
constexpr uint64_t kTreeRayLimit = uint64_t(1) << 22;

/// What the traced trees did on each side: their rays by kind, their voxel steps and tests.
struct TreeWork {
  TraceCounts machine, reference;
};

/// Traces the primary ray's tree through both tracers and names where they part. The trees are
/// compared breadth first, so the parting named is the shallowest (ties: in the order shading
/// spawned them). machine_pixel and reference_pixel are the images' values: a tree that does not
/// sum to its pixel gives Unknown. hit_tolerance is a distance. Rays past max_rays on either side
/// are not traced: a tree that large gives Unknown unless its parting came first.
/// With `rays`, each tree's rays are added to it by kind.
PixelCause explain_pixel(const Ray& primary, RayTracer& machine, RayTracer& reference,
                         double hit_tolerance, const Vec3& machine_pixel,
                         const Vec3& reference_pixel, uint64_t max_rays = kTreeRayLimit,
                         TreeWork* rays = nullptr);

/// The pixel a primary ray's tree sums to through one tracer.
Vec3 traced_pixel(RayTracer& tracer, const Ray& primary, uint64_t max_rays = kTreeRayLimit);

/// Whether a pixel counts as differing: some channel off by more than 1/255, the test the image
/// comparison's pixels_over_1_255 makes (in float, as OpenImageIO's threshold is).
bool pixel_differs(const Vec3& a, const Vec3& b);

/// One line of the tally: how many pixels part at this generation, kind and cause.
struct CauseCount {
  ErrorCause cause = ErrorCause::None;
  int generation = 0;
  RayKind kind = RayKind::Primary;
  uint64_t pixels = 0;
};

struct ErrorCauses {
  int width = 0, height = 0;
  std::vector<PixelCause> pixels;  ///< per pixel, row by row: None where the pixel does not differ
  std::vector<CauseCount> counts;  ///< by cause, then generation, then kind; no None lines
  std::array<uint64_t, kErrorCauses> by_cause{};
  /// Pixels whose parting ray's primitive (the machine's, else the reference's) is of each shape.
  std::array<uint64_t, kShapeKinds> by_shape{};
  uint64_t differing = 0;  ///< pixels over 1/255: the sum of every count
  /// The differing pixels' trees on both sides: the part of the frames' work the error map
  /// accounts for.
  TreeWork trees;
  bool trees_whole =
      true;            ///< every tree was traced to its end and summed to its pixel (no Unknown)
  double seconds = 0;  ///< wall time of the attribution
};

/// A count in which the machine's frame differs from the reference's, and how much of the
/// difference is in the differing pixels' trees: the rest is in pixels that agree within 1/255.
struct CountGap {
  CountDifference count;   ///< a: the machine's, b: the reference's
  int64_t in_trees = 0;    ///< machine − reference over the differing pixels' trees
  bool explained = false;  ///< the whole difference is in them (every tree traced whole)
  int64_t difference() const { return int64_t(count.a) - int64_t(count.b); }
};
/// Each count that differs (count_differences' order), with its part in e's trees.
std::vector<CountGap> count_gaps(const TraceCounts& machine, const TraceCounts& reference,
                                 const ErrorCauses& e);

/// Explains every pixel where the machine's image differs from the reference's, re-tracing the
/// machine's trees with a PE's units under config (error/pe_tracer.h).
ErrorCauses explain_errors(const Scene& s, const Grid& g, const MachineConfig& config,
                           const Image& machine, const Image& reference);

}  // namespace rtm
