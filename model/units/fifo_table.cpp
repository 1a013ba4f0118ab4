#include "units/fifo_table.h"

namespace rtm {

const std::array<FifoSpec, kFifoCount>& fifo_table() {
  using U = UnitKind;
  using M = MachineConfig;
  static const std::array<FifoSpec, kFifoCount> table = {{
      {FifoId::Search, "search_fifo", "search", Payload::Ray, "search_fifo_depth", &M::search_fifo_depth,
       {U::FrontBuffer}, {U::Search}, false, false, false, "front buffer -> search units (shared by all of them)"},
      {FifoId::Intersect, "intersect_fifo", "intersect", Payload::Ray, "intersect_fifo_depth", &M::intersect_fifo_depth,
       {U::Search}, {U::Mac}, false, false, false, "occupied voxels: search -> intersection units"},
      {FifoId::Shade, "shade_fifo", "shade", Payload::Ray, "shade_fifo_depth", &M::shade_fifo_depth,
       {U::Search, U::Root}, {U::Shading}, false, false, false, "hits, lights reached and background misses -> shading"},
      {FifoId::FeedbackSearch, "feedback_search_fifo", "feedback", Payload::Ray, "feedback_fifo_depth",
       &M::feedback_fifo_depth, {U::Search}, {U::FrontBuffer}, false, false, true, "empty voxel: walk on"},
      {FifoId::FeedbackIntersect, "feedback_intersect_fifo", "feedback", Payload::Ray, "feedback_fifo_depth",
       &M::feedback_fifo_depth, {U::Root}, {U::FrontBuffer}, false, false, true, "no hit in the voxel: walk on"},
      {FifoId::Spawn, "spawn_fifo", "spawn", Payload::Ray, "feedback_fifo_depth", &M::feedback_fifo_depth,
       {U::Shading}, {U::FrontBuffer}, false, true, false, "shadow and branch rays shading spawned"},
      {FifoId::Root, "root_fifo", "root", Payload::MacResult, "root_fifo_depth", &M::root_fifo_depth, {U::Mac},
       {U::Root}, true, false, false, "alpha, beta, gamma per primitive: MAC -> root unit and sort"},
      {FifoId::Ends, "ends_fifo", "ends", Payload::End, "feedback_fifo_depth", &M::feedback_fifo_depth,
       {U::Search, U::Root, U::Shading}, {U::FrontBuffer}, false, false, true,
       "a ray left the loop: its credit back to the front buffer"},
  }};
  return table;
}

}  // namespace rtm
