// The routing rules of the search stage (paper §4.2) and the intersection stage (§5.1), as plain
// functions of a ray and what the stage found, so they can be checked without the kernel.
#pragma once

#include "units/machine_ray.h"
#include "render/voxel_test.h"

namespace rtm {

enum class Route {
  Intersect,  ///< occupied voxel: to the intersection stage
  Feedback,   ///< walk on: back to the front buffer
  Shade,  ///< to the shading stage (a hit, a shadow ray that reached its light, a background miss)
  End,    ///< the ray leaves the loop
};

/// One search-unit pass: set the walk up on the ray's first pass, examine the current voxel,
/// step to the next one, and route by the examined voxel's occupancy. Returns whether a voxel
/// was examined (false: the ray misses the grid altogether). The walk's arithmetic is Real's
/// (dda_precision).
template <class Real = double>
bool search_pass(const Grid& g, MachineRay& r);
Route search_route(const Scene& s, const Grid& g, MachineRay& r, bool examined);

/// The intersection stage's routing, given the nearest hit found in the examined voxel.
Route intersection_route(const Scene& s, MachineRay& r, const VoxelHit& h);

}  // namespace rtm
