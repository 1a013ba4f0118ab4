// The frame of the PEs' arithmetic: the grid's own coordinates, x' = (x − lo) / L with lo the
// grid's corner and L its longest edge, so every position a PE holds lies in [0, 1]³ (the eye and
// lights may lie outside) whatever the world coordinates were. The host forms it in fp64 before
// anything is sent (docs/numerics.md, "Where the scene is").
#pragma once

#include "scene/scene.h"

namespace rtm {

/// World (the scene as written, as in the paper) or grid (the grid's frame above).
enum class PeFrame { World, Grid };
const char* to_string(PeFrame f);

struct GridFrame {
  Vec3 origin{0, 0, 0};  ///< the grid's corner, in world coordinates
  double scale = 1;      ///< frame units per world unit: 1 / the grid's longest edge

  Vec3 point(const Vec3& p) const { return (p - origin) * scale; }
};

/// The frame of the object space `box` (a grid's box).
GridFrame grid_frame(const Aabb& box);

/// The same surface, clips and bounds in the frame; the quadric from the primitive's local form
/// when it has one, multiplied by scale² so its quadratic terms keep their size.
Primitive in_frame(const Primitive& p, const GridFrame& f);
/// Every primitive, the camera and the lights in the frame; directions, colours and materials
/// are the same, and the spawn offset is relative to the frame's positions.
Scene in_frame(const Scene& s, const GridFrame& f);
/// The same voxels and lists, the box and voxel edges in the frame (the corner exactly 0).
Grid in_frame(const Grid& g, const GridFrame& f);

/// A scene and its grid as the PEs receive them.
struct FramedScene {
  Scene scene;
  Grid grid;
};
/// In the grid's frame (PeFrame::Grid), or copies as they are (World).
FramedScene framed(const Scene& s, const Grid& g, PeFrame frame);

}  // namespace rtm
