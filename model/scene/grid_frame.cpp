#include "scene/grid_frame.h"

#include <algorithm>

namespace rtm {

const char* to_string(PeFrame f) { return f == PeFrame::Grid ? "grid" : "world"; }

GridFrame grid_frame(const Aabb& box) {
  const Vec3 e = box.extent();
  const double longest = std::max({e.x, e.y, e.z});
  GridFrame f;
  f.origin = box.lo;
  f.scale = longest > 0 ? 1.0 / longest : 1.0;
  return f;
}

namespace {

/// Q'(x') = s² Q(x'/s) for the quadric written about the frame's origin.
Quadric scaled(Quadric q, double s) {
  for (int k = kG; k <= kI; ++k) q.c[size_t(k)] *= s;
  q.c[kJ] *= s * s;
  return q;
}

}  // namespace

Primitive in_frame(const Primitive& p, const GridFrame& f) {
  Primitive o = p;
  const double s = f.scale;
  o.q = scaled(p.about(f.origin), s);
  if (p.has_local) {
    o.local = scaled(p.local, s);
    o.origin = f.point(p.origin);
  }
  for (HalfSpace& h : o.clips) h = {h.n, h.translated(f.origin).d * s};
  o.bounds = {f.point(p.bounds.lo), f.point(p.bounds.hi)};
  o.p0 = f.point(p.p0);
  o.p1 = f.point(p.p1);
  o.r0 = p.r0 * s;
  o.r1 = p.r1 * s;
  for (Vec3& v : o.vertices) v = f.point(v);
  for (Vec3& v : o.outline) v = f.point(v);
  return o;
}

Scene in_frame(const Scene& s, const GridFrame& f) {
  Scene o = s;
  o.camera.eye = f.point(s.camera.eye);
  o.camera.look_at = f.point(s.camera.look_at);
  for (Light& l : o.lights) l.position = f.point(l.position);
  for (Primitive& p : o.primitives) p = in_frame(p, f);
  return o;
}

Grid in_frame(const Grid& g, const GridFrame& f) {
  Grid o = g;
  o.box = {Vec3(0), f.point(g.box.hi)};
  o.cell = g.cell * f.scale;
  return o;
}

FramedScene framed(const Scene& s, const Grid& g, PeFrame frame) {
  if (frame == PeFrame::World) return {s, g};
  const GridFrame f = grid_frame(g.box);
  return {in_frame(s, f), in_frame(g, f)};
}

}  // namespace rtm
