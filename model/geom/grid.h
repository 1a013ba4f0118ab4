// The uniform grid ("voxel data"): which primitives each equal-sized voxel holds.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "geom/quadric.h"

namespace rtm {

struct GridOptions {
  /// Voxels per axis; all zero means automatic (see auto_resolution).
  std::array<int, 3> resolution{0, 0, 0};
  /// Automatic resolution aims at this many voxels per primitive.
  double voxels_per_primitive = 4.0;
  /// Automatic resolution never exceeds this many voxels on an axis. The machine's 128 keeps
  /// small the voxel data every PE receives (and walks one voxel per pass).
  int max_auto_axis = 128;
  /// With a budget (> 0), the cap on an axis is the largest (up to max_auto_axis) that keeps the
  /// automatic grid within this many voxels (never below the plain rule over the whole box).
  int64_t max_auto_cells = 0;
  /// With a limit (> 0), no voxel edge is shorter than 1/max_auto_aspect of the longest: where
  /// the cap lengthens some axes' voxels (a teapot in a stadium), the others coarsen with them.
  double max_auto_aspect = 0;
  /// With a limit (> 0), the automatic grid is coarsened (every axis by the same factor) until
  /// the references it is estimated to hold are at most this many per primitive, or at most twice
  /// its voxels (estimated_references): large primitives that span many voxels (SPD shells'
  /// overlapping spheres) must not make the build dominate the render.
  double max_refs_per_primitive = 0;
  /// Spheres are registered with the exact sphere–box test (the surface meets the box exactly
  /// when the nearest point of the box is inside the sphere and the farthest outside) instead of
  /// the interval bound. Both are conservative; the exact one is cheaper and lists no voxel the
  /// sphere misses. The machine keeps the interval bound, so its voxel data is unchanged.
  bool exact_spheres = false;
};

/// The automatic grid of the reference renderer run on its own: a CPU that crosses empty space in
/// large steps can afford more voxels than a PE; SPD tree-11 traces fastest with voxels at most
/// 3:1 (docs/benchmarks.md, "The reference renderer's grid").
inline void size_for_cpu(GridOptions& g) {
  g.max_auto_axis = 1024;
  g.max_auto_cells = 6'000'000;
  g.max_auto_aspect = 3;
  g.max_refs_per_primitive = 256;  // binds on SPD shells only (docs/benchmarks.md)
  g.exact_spheres = true;
}

struct Grid {
  Aabb box;                       ///< the object space; voxels tile it exactly
  std::array<int, 3> n{1, 1, 1};  ///< voxels per axis
  Vec3 cell{1, 1, 1};             ///< voxel edge lengths
  /// Compressed rows: voxel v holds items[start[v] .. start[v+1]).
  std::vector<uint32_t> start;
  std::vector<uint32_t> items;

  int64_t voxel_count() const { return int64_t(n[0]) * n[1] * n[2]; }
  int64_t index(int x, int y, int z) const { return (int64_t(z) * n[1] + y) * n[0] + x; }
  uint32_t count(int64_t v) const { return start[v + 1] - start[v]; }
  const uint32_t* begin(int64_t v) const { return items.data() + start[v]; }
  Aabb voxel_box(int x, int y, int z) const;
  /// Position of a voxel boundary plane on an axis, computed from the index (no accumulated drift).
  double plane(int axis, int i) const { return box.lo[axis] + i * cell[axis]; }
};

/// Automatic resolution: voxels of equal size in every direction, about voxels_per_primitive
/// voxels per primitive (Cleary & Wyvill / Woo's cube-root rule), clamped to [1, max_auto_axis].
/// An axis thinner than one such voxel (a flat scene) gets one voxel and the budget goes to the
/// other axes (square-root rule in 2D). Throws std::invalid_argument unless voxels_per_primitive
/// is finite and positive.
std::array<int, 3> auto_resolution(const Aabb& box, size_t primitives, const GridOptions& opt);

/// The automatic resolution for a scene: cubic voxels sized by auto_resolution over the scene's
/// dense core (the box spanned by the central 90% of primitive centres on each axis, grown by the
/// median primitive size, and the primitives centred in it), then laid over the whole object
/// space and capped per axis (GridOptions: max_auto_axis, max_auto_cells, max_auto_aspect). A
/// scene whose objects sit on a huge floor ("a teapot in a stadium": SPD balls and tree) gets
/// voxels fitted to its objects, not to the floor.
std::array<int, 3> density_resolution(const std::vector<Primitive>& prims, const Aabb& box,
                                      const GridOptions& opt);
/// The automatic resolution: density_resolution, then coarsened to GridOptions::
/// max_refs_per_primitive when that is set.
std::array<int, 3> scene_resolution(const std::vector<Primitive>& prims, const Aabb& box,
                                    const GridOptions& opt);

/// Told how a long step of the host's work goes, for a progress line (render/progress.h,
/// StepLine): the step's name, what it counts, how many of how many (total 0: not counted).
/// Called from one thread at a time, often: it must be cheap when nothing is shown.
using StepProgress =
    std::function<void(const char* step, const char* item, uint64_t done, uint64_t total)>;

/// Conservative voxelisation: a primitive is listed in every voxel its clipped surface may touch.
/// Tighter than its bounding box: a voxel entirely outside one clip half-space is skipped, and
/// so is a voxel over which interval arithmetic proves the quadric has no zero.
/// threads <= 0: all hardware threads. The result does not depend on the number of threads.
/// `progress` hears of the steps "grid build" (choosing the resolution, sorting the references)
/// and "voxelisation" (the primitives listed).
Grid build_grid(const std::vector<Primitive>& prims, const GridOptions& opt, int threads = 0,
                const StepProgress& progress = {});

/// The references a grid of n voxels over box is expected to hold: per primitive the voxels its
/// bounding box spans on average (width in voxels + 1 on each axis), for a sphere scaled by the
/// share of them its surface can touch (min(1, 2.4 c / r) for voxel edge c: surface voxels ~
/// 4πr²·1.5/c² against (2r/c)³). Cheap (no voxel is tested), for choosing a resolution.
double estimated_references(const std::vector<Primitive>& prims, const Aabb& box,
                            const std::array<int, 3>& n);

/// Can a sphere's surface meet the box? Exact up to rounding, and conservative.
bool sphere_touches_box(const Vec3& centre, double radius, const Aabb& box);

/// Interval bound check used by the voxeliser: can Q be zero somewhere in the box? Conservative
/// (never false where Q has a zero); evaluated centred on the box, so it stays tight far from the
/// origin (exact range for spheres), not only near it.
bool quadric_may_vanish(const Quadric& q, const Aabb& box);
/// Can the box hold a point with n·p + d <= 0?
bool box_touches_halfspace(const Aabb& box, const HalfSpace& h);

}  // namespace rtm
