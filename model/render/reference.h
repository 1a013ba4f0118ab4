// The golden reference renderer: the paper's algorithm, untimed, in double precision.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "geom/grid.h"
#include "render/ray.h"
#include "render/ray_result.h"
#include "scene/grid_frame.h"
#include "scene/scene.h"

namespace rtm {

/// Counters every renderer of the algorithm reports (the reference and the machine alike).
struct TraceCounts {
  std::array<uint64_t, kRayKinds> rays{};  ///< by RayKind
  uint64_t voxel_steps = 0;                ///< voxels visited, over all rays
  uint64_t intersection_tests = 0;         ///< ray/primitive tests (one MAC schedule each)
  uint64_t clip_tests = 0;                 ///< half-space evaluations

  void add(const TraceCounts& o);
  uint64_t total_rays() const { return rays[0] + rays[1] + rays[2] + rays[3]; }
};

/// One count in which two renders of a frame differ.
struct CountDifference {
  std::string what;  ///< "shadow rays", "voxel steps", "intersection tests", "clip tests"
  uint64_t a = 0, b = 0;
};
/// Each count in which a and b differ, the rays by kind first; empty: they did the same work.
std::vector<CountDifference> count_differences(const TraceCounts& a, const TraceCounts& b);

/// A rendered frame: linear RGB and the primitive each primary ray hit (-1: background).
struct Image {
  int width = 0, height = 0;
  std::vector<Vec3> rgb;
  std::vector<int32_t> ids;

  Image() = default;
  Image(int w, int h)
      : width(w), height(h), rgb(size_t(w) * size_t(h), Vec3(0)), ids(size_t(w) * size_t(h), -1) {}
};

struct ReferenceResult {
  Image image;
  TraceCounts counts;
  double wall_seconds = 0;
};

/// Identifies the build of the reference renderer (for caches of its images).
const char* reference_build_id();

/// What watches a reference render while it runs, as the machine's monitor watches a simulation:
/// a tree that never ends (a glass sphere among mirrors at threshold 0) holds little memory, since
/// each pixel's tree is traced depth first, but its rays go on.
struct ReferenceWatch {
  bool progress = false;  ///< redraw a progress line on stderr (the caller checks it is a terminal)
  uint64_t max_memory = 0;  ///< stop once the process holds more bytes; 0: no limit
  uint64_t max_rays = 0;    ///< stop once more rays than this are traced; 0: no limit
};

/// A render its watch stopped, over its memory or work budget; the message says which, where.
struct BudgetExceeded : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Renders the whole frame, computing in `frame` (the machine's pe_frame: the two then round
/// alike). threads <= 0: all hardware threads. Throws BudgetExceeded when the watch's budget is
/// passed.
ReferenceResult render_reference(const Scene& s, const Grid& g, int threads,
                                 const ReferenceWatch& watch = {}, PeFrame frame = PeFrame::Grid);

/// The reference renderer one ray at a time, for a caller that follows a pixel's tree itself (the
/// error attribution re-traces only the pixels that differ): the same walk and shading as
/// render_reference, so a tree traced through it sums to the reference image's pixel exactly.
/// Its scene and rays are in the frame the caller chose (framed()).
class ReferenceTracer : public RayTracer {
 public:
  ReferenceTracer(const Scene& s, const Grid& g);  ///< both must outlive the tracer
  ~ReferenceTracer() override;
  void trace(const Ray& ray, RayResult& out) override;
  /// The counts of every ray traced so far.
  const TraceCounts& counts() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace rtm
