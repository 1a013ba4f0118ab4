#include "geom/quadric.h"

#include <limits>
#include <stdexcept>

namespace rtm {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

// The messages are built only on failure: these run for every primitive of a scene.
void require_finite(const Vec3& v, const char* what) {
  if (!all_finite(v)) throw std::invalid_argument(std::string(what) + " is not finite");
}

void require_positive(double x, const char* what) {
  if (!(std::isfinite(x) && x > 0))
    throw std::invalid_argument(std::string(what) + " must be a finite positive number");
}

void require_finite_coefficients(const Quadric& q, const char* which) {
  for (int i = 0; i < 10; ++i)
    if (!std::isfinite(q.c[i]))
      throw std::invalid_argument(std::string(which) + " coefficient " + "ABCDEFGHIJ"[i] +
                                  " is not finite");
}

/// Symmetric 4x4 matrix S with Q(p) = [p 1]ᵀ S [p 1].
using Sym4 = std::array<std::array<double, 4>, 4>;

Quadric from_sym(const Sym4& s) {
  Quadric q;
  q.c = {s[0][0],     s[1][1],     s[2][2],     2 * s[0][1], 2 * s[1][2],
         2 * s[0][2], 2 * s[0][3], 2 * s[1][3], 2 * s[2][3], s[3][3]};
  return q;
}

/// The world quadric of a quadric written in frame f's local coordinates: Mᵀ S M, where M maps
/// world to local (l = Rᵀ (p − o)).
Quadric to_world(const Frame& f, const Sym4& local) {
  const Vec3 e[3] = {f.ex, f.ey, f.ez};
  double m[4][4] = {};
  for (int i = 0; i < 3; ++i) {
    m[i][0] = e[i].x;
    m[i][1] = e[i].y;
    m[i][2] = e[i].z;
    m[i][3] = -dot(e[i], f.origin);
  }
  m[3][3] = 1;
  Sym4 w{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      double sum = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) sum += m[i][r] * local[i][j] * m[j][c];
      w[r][c] = sum;
    }
  return from_sym(w);
}

/// Sets both forms of a quadric written in frame f's local coordinates: the world one and the
/// one about the frame's origin (same axes, no translation, so no cancellation).
void set_quadric(Primitive& p, const Frame& f, const Sym4& local) {
  p.q = to_world(f, local);
  Frame at_zero = f;
  at_zero.origin = Vec3{0, 0, 0};
  p.local = to_world(at_zero, local);
  p.origin = f.origin;
  p.has_local = true;
}

/// Box of a disc of radius r centred at c with unit normal a.
Aabb disc_box(const Vec3& c, const Vec3& a, double r) {
  const Vec3 half{r * std::sqrt(std::max(0.0, 1 - a.x * a.x)),
                  r * std::sqrt(std::max(0.0, 1 - a.y * a.y)),
                  r * std::sqrt(std::max(0.0, 1 - a.z * a.z))};
  return Aabb{c - half, c + half};
}

/// Keep local z within [z0, z1] of frame f.
void clip_z(Primitive& p, const Frame& f, double z0, double z1) {
  const double oz = dot(f.ez, f.origin);
  p.clips.push_back({-f.ez, oz + z0});  // z >= z0
  p.clips.push_back({f.ez, -oz - z1});  // z <= z1
}

void check_frame(const Frame& f) {
  require_finite(f.origin, "frame origin");
  for (const Vec3& e : {f.ex, f.ey, f.ez}) {
    require_finite(e, "frame axis");
    require(std::abs(length(e) - 1) < 1e-9, "frame axes must be unit vectors");
  }
  require(std::abs(dot(f.ex, f.ey)) < 1e-9 && std::abs(dot(f.ey, f.ez)) < 1e-9 &&
              std::abs(dot(f.ez, f.ex)) < 1e-9,
          "frame axes must be orthogonal");
}

/// A surface of revolution about the frame's z axis between z0 and z1, radius at most r.
Aabb revolution_box(const Frame& f, double z0, double r0, double z1, double r1) {
  Aabb b = disc_box(f.origin + z0 * f.ez, f.ez, r0);
  b.extend(disc_box(f.origin + z1 * f.ez, f.ez, r1));
  return b;
}

/// Box of x² + y² = k z, 0 <= z <= h, in frame f. Along world axis i the circle at height z
/// reaches o_i + a z ± sqrt(k z) s (a = ez_i, s = sqrt(1 − a²)); with w = sqrt(z) that is a
/// parabola in w whose extreme can lie between the vertex and the rim (a tilted, shallow bowl
/// bulges past its rim), so the box of the vertex and the rim disc alone does not hold it.
Aabb paraboloid_box(const Frame& f, double k, double h) {
  const double wmax = std::sqrt(h);
  // max of a w² + b w over [0, wmax], for b >= 0.
  const auto reach = [wmax](double a, double b) {
    double m = std::max(0.0, (a * wmax + b) * wmax);
    if (a < 0 && -b / (2 * a) < wmax) m = std::max(m, -b * b / (4 * a));
    return m;
  };
  Aabb box;
  for (int i = 0; i < 3; ++i) {
    const double a = f.ez[i], b = std::sqrt(k) * std::sqrt(std::max(0.0, 1 - a * a));
    box.lo[i] = f.origin[i] - reach(-a, b);
    box.hi[i] = f.origin[i] + reach(a, b);
  }
  return box;
}

Primitive finish(Primitive p) {
  validate(p);
  return p;
}

}  // namespace

const char* shape_name(ShapeKind k) {
  switch (k) {
    case ShapeKind::Sphere:
      return "sphere";
    case ShapeKind::Ellipsoid:
      return "ellipsoid";
    case ShapeKind::Cylinder:
      return "cylinder";
    case ShapeKind::Cone:
      return "cone";
    case ShapeKind::Plane:
      return "plane";
    case ShapeKind::Paraboloid:
      return "paraboloid";
    case ShapeKind::Hyperboloid1:
      return "hyperboloid1";
    case ShapeKind::Hyperboloid2:
      return "hyperboloid2";
    case ShapeKind::Polygon:
      return "polygon";
    case ShapeKind::Raw:
      return "quadric";
  }
  return "?";
}

double Quadric::value(const Vec3& p) const {
  return c[kA] * p.x * p.x + c[kB] * p.y * p.y + c[kC] * p.z * p.z + c[kD] * p.x * p.y +
         c[kE] * p.y * p.z + c[kF] * p.z * p.x + c[kG] * p.x + c[kH] * p.y + c[kI] * p.z + c[kJ];
}

Vec3 Quadric::gradient(const Vec3& p) const {
  return {2 * c[kA] * p.x + c[kD] * p.y + c[kF] * p.z + c[kG],
          2 * c[kB] * p.y + c[kD] * p.x + c[kE] * p.z + c[kH],
          2 * c[kC] * p.z + c[kE] * p.y + c[kF] * p.x + c[kI]};
}

Quadric Quadric::translated(const Vec3& p) const {
  Quadric q = *this;
  const Vec3 g = gradient(p);
  q.c[kG] = g.x;
  q.c[kH] = g.y;
  q.c[kI] = g.z;
  q.c[kJ] = value(p);
  return q;
}

Frame Frame::along(const Vec3& origin, const Vec3& axis) {
  Frame f;
  f.origin = origin;
  f.ez = normalize(axis);
  // Pick the world axis least aligned with ez, so the cross product is well conditioned.
  const Vec3 a = std::abs(f.ez.x) < 0.6 ? Vec3{1, 0, 0}
                                        : (std::abs(f.ez.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  f.ex = normalize(cross(a, f.ez));
  f.ey = cross(f.ez, f.ex);
  return f;
}

Primitive make_sphere(const Vec3& centre, double radius) {
  require_finite(centre, "sphere centre");
  if (radius == 0) throw DegenerateShape("sphere radius is zero");
  require_positive(radius, "sphere radius");
  if (radius * radius < std::numeric_limits<double>::min())
    throw DegenerateShape("sphere radius is too small: its square underflows");
  Primitive p;
  p.kind = ShapeKind::Sphere;
  p.q.c = {1,
           1,
           1,
           0,
           0,
           0,
           -2 * centre.x,
           -2 * centre.y,
           -2 * centre.z,
           dot(centre, centre) - radius * radius};
  p.local.c = {1, 1, 1, 0, 0, 0, 0, 0, 0, -radius * radius};
  p.origin = centre;
  p.has_local = true;
  p.bounds = Aabb{centre - Vec3(radius), centre + Vec3(radius)};
  p.p0 = centre;
  p.r0 = radius;
  return finish(p);
}

Primitive make_ellipsoid(const Frame& f, const Vec3& radii) {
  check_frame(f);
  require_positive(radii.x, "ellipsoid radius x");
  require_positive(radii.y, "ellipsoid radius y");
  require_positive(radii.z, "ellipsoid radius z");
  Sym4 s{};
  s[0][0] = 1 / (radii.x * radii.x);
  s[1][1] = 1 / (radii.y * radii.y);
  s[2][2] = 1 / (radii.z * radii.z);
  s[3][3] = -1;
  Primitive p;
  p.kind = ShapeKind::Ellipsoid;
  set_quadric(p, f, s);
  // Exact box of a rotated ellipsoid: half-extent along world axis i is |(R diag(r))_i|.
  const Vec3 half{length(Vec3{f.ex.x * radii.x, f.ey.x * radii.y, f.ez.x * radii.z}),
                  length(Vec3{f.ex.y * radii.x, f.ey.y * radii.y, f.ez.y * radii.z}),
                  length(Vec3{f.ex.z * radii.x, f.ey.z * radii.y, f.ez.z * radii.z})};
  p.bounds = Aabb{f.origin - half, f.origin + half};
  p.p0 = f.origin;
  p.p1 = radii;
  return finish(p);
}

Primitive make_cone(const Vec3& base, double base_radius, const Vec3& apex, double apex_radius) {
  require_finite(base, "cone base centre");
  require_finite(apex, "cone apex centre");
  require(std::isfinite(base_radius) && std::isfinite(apex_radius), "cone radii are not finite");
  // NFF: negative radii (both) mean "inside visible only"; the surface is the same.
  const double r0 = std::abs(base_radius), r1 = std::abs(apex_radius);
  if (!(r0 > 0 || r1 > 0)) throw DegenerateShape("cone radii are both zero");
  const double h = length(apex - base);
  if (h == 0) throw DegenerateShape("cone base and apex coincide");
  require(std::isfinite(h), "cone base and apex are too far apart");
  const Frame f = Frame::along(base, apex - base);
  // x² + y² − (r0 + k z)² = 0 with k the radius slope.
  const double k = (r1 - r0) / h;
  Sym4 s{};
  s[0][0] = 1;
  s[1][1] = 1;
  s[2][2] = -k * k;
  s[2][3] = s[3][2] = -r0 * k;
  s[3][3] = -r0 * r0;
  Primitive p;
  p.kind = r0 == r1 ? ShapeKind::Cylinder : ShapeKind::Cone;
  set_quadric(p, f, s);
  clip_z(p, f, 0, h);
  p.bounds = revolution_box(f, 0, r0, h, r1);
  p.p0 = base;
  p.p1 = apex;
  p.r0 = r0;
  p.r1 = r1;
  return finish(p);
}

Primitive make_paraboloid(const Frame& f, double k, double height) {
  check_frame(f);
  require_positive(k, "paraboloid k");
  require_positive(height, "paraboloid height");
  Sym4 s{};
  s[0][0] = 1;
  s[1][1] = 1;
  s[2][3] = s[3][2] = -k / 2;
  Primitive p;
  p.kind = ShapeKind::Paraboloid;
  set_quadric(p, f, s);
  clip_z(p, f, 0, height);
  p.bounds = paraboloid_box(f, k, height);
  p.p0 = f.origin;
  p.r0 = k;
  p.r1 = height;
  return finish(p);
}

namespace {
Primitive hyperboloid(const Frame& f, double a, double c, double half_height, double constant,
                      ShapeKind kind) {
  Sym4 s{};
  s[0][0] = 1 / (a * a);
  s[1][1] = 1 / (a * a);
  s[2][2] = -1 / (c * c);
  s[3][3] = constant;
  // On either surface x² + y² = a² (z²/c² + constant·(−1)), largest at |z| = half_height.
  const double rmax = a * std::sqrt(half_height * half_height / (c * c) - constant);
  Primitive p;
  p.kind = kind;
  set_quadric(p, f, s);
  clip_z(p, f, -half_height, half_height);
  p.bounds = revolution_box(f, -half_height, rmax, half_height, rmax);
  p.p0 = f.origin;
  p.r0 = a;
  p.r1 = c;
  return finish(p);
}
}  // namespace

Primitive make_hyperboloid1(const Frame& f, double a, double c, double half_height) {
  check_frame(f);
  require_positive(a, "hyperboloid a");
  require_positive(c, "hyperboloid c");
  require_positive(half_height, "hyperboloid half height");
  return hyperboloid(f, a, c, half_height, -1, ShapeKind::Hyperboloid1);
}

Primitive make_hyperboloid2(const Frame& f, double a, double c, double half_height) {
  check_frame(f);
  require_positive(a, "hyperboloid a");
  require_positive(c, "hyperboloid c");
  require(std::isfinite(half_height) && half_height > c,
          "two-sheet hyperboloid half height must exceed c");
  return hyperboloid(f, a, c, half_height, 1, ShapeKind::Hyperboloid2);
}

namespace {
void add_box_clips(Primitive& p, const Aabb& box) {
  p.clips.push_back({{-1, 0, 0}, box.lo.x});
  p.clips.push_back({{1, 0, 0}, -box.hi.x});
  p.clips.push_back({{0, -1, 0}, box.lo.y});
  p.clips.push_back({{0, 1, 0}, -box.hi.y});
  p.clips.push_back({{0, 0, -1}, box.lo.z});
  p.clips.push_back({{0, 0, 1}, -box.hi.z});
}

void require_box(const Aabb& box, const char* what) {
  if (!(all_finite(box.lo) && all_finite(box.hi)))
    throw std::invalid_argument(std::string(what) + " box is not finite");
  if (box.empty())
    throw std::invalid_argument(std::string(what) + " box is empty (min must not exceed max)");
}
}  // namespace

Primitive make_plane(const Vec3& n, double d, const Aabb& box) {
  require_finite(n, "plane normal");
  require(std::isfinite(d), "plane offset is not finite");
  require(max_abs(n) > 0, "plane normal is zero");
  require_box(box, "plane");
  // Only n's direction matters: scale it to max |component| = 1 first, so length() can neither
  // underflow (tiny n) nor overflow (huge n).
  const double m = max_abs(n);
  const Vec3 unit = normalize(n / m);
  const double off = d / m / length(n / m);
  Primitive p;
  p.kind = ShapeKind::Plane;
  p.q.c = {0, 0, 0, 0, 0, 0, unit.x, unit.y, unit.z, off};
  add_box_clips(p, box);
  p.bounds = box;
  p.p0 = unit;
  p.r0 = off;
  return finish(p);
}

PolygonOutline polygon_outline(const std::vector<Vec3>& in) {
  // Repeated consecutive vertices make zero-length edges with no outward normal.
  PolygonOutline o;
  for (const Vec3& p : in)
    if (o.v.empty() || p != o.v.back()) o.v.push_back(p);
  if (o.v.size() > 1 && o.v.front() == o.v.back()) o.v.pop_back();
  if (o.v.size() < 3) throw DegenerateShape("a polygon needs at least 3 distinct vertices");
  // Newell's normal: robust for any planar polygon, whichever corner is degenerate.
  o.newell = Vec3{0, 0, 0};
  for (size_t i = 0; i < o.v.size(); ++i) {
    const Vec3& a = o.v[i];
    const Vec3& b = o.v[(i + 1) % o.v.size()];
    o.newell +=
        Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    o.box.extend(a);
  }
  return o;
}

Primitive make_polygon(const std::vector<Vec3>& in) {
  require(in.size() >= 3, "a polygon needs at least 3 vertices");
  for (const Vec3& v : in) require_finite(v, "polygon vertex");
  const PolygonOutline outline = polygon_outline(in);
  const std::vector<Vec3>& v = outline.v;
  Vec3 n = outline.newell;
  const Aabb& box = outline.box;
  const double size = outline.size();
  if (!(length(n) > 1e-12 * size * size)) throw DegenerateShape("polygon has zero area");
  n = normalize(n);
  const double d = -dot(n, v[0]);
  for (const Vec3& p : v)
    require(std::abs(dot(n, p) + d) <= 1e-6 * size, "polygon vertices are not coplanar");

  Primitive p;
  p.kind = ShapeKind::Polygon;
  p.q.c = {0, 0, 0, 0, 0, 0, n.x, n.y, n.z, d};
  p.local.c = {0, 0, 0, 0, 0, 0, n.x, n.y, n.z, 0};  // about the first vertex
  p.origin = v[0];
  p.has_local = true;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3 e = v[(i + 1) % v.size()] - a;
    const Vec3 out = cross(e, n);
    if (length(out) == 0) continue;
    const Vec3 m = normalize(out);
    // Convexity: every other vertex must lie on the inner side of this edge.
    for (const Vec3& w : v)
      require(dot(m, w - a) <= 1e-9 * size,
              "polygon is not convex (only convex polygons are supported)");
    p.clips.push_back({m, -dot(m, a)});
  }
  p.bounds = box;
  p.vertices = v;
  return finish(p);
}

std::vector<Vec3> vertex_normals(const Primitive& triangle, const std::vector<Vec3>& normals) {
  const std::vector<Vec3>& v = triangle.vertices;
  if (v.size() != 3 || normals.size() != 3) return {};
  const Vec3 face = cross(v[1] - v[0], v[2] - v[0]);
  std::vector<Vec3> out;
  int above = 0, below = 0;
  for (const Vec3& n : normals) {
    const double len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return {};
    out.push_back(n / len);
    const double side = dot(face, n);
    above += side > 0;
    below += side < 0;
  }
  if (above != 3 && below != 3) return {};
  return out;
}

Primitive make_raw_quadric(const std::array<double, 10>& coef, const Aabb& box,
                           std::vector<HalfSpace> clips) {
  require_box(box, "quadric");
  Primitive p;
  p.kind = ShapeKind::Raw;
  p.q.c = coef;
  add_box_clips(p, box);
  for (const HalfSpace& h : clips) p.clips.push_back(h);
  p.bounds = box;
  return finish(p);
}

void validate(const Primitive& p) {
  // The bounds first: a shape too far out overflows its coefficients, and this says why.
  require(all_finite(p.bounds.lo) && all_finite(p.bounds.hi) && !p.bounds.empty(),
          "primitive has no finite bound");
  require(max_abs(p.bounds.lo) <= kMaxCoordinate && max_abs(p.bounds.hi) <= kMaxCoordinate,
          "primitive lies too far from the origin: coordinates must be within +-1e150 so squared "
          "distances stay finite");
  require_finite_coefficients(p.q, "quadric");
  bool any = false;
  for (int i = 0; i < kJ; ++i) any = any || p.q.c[i] != 0;
  require(any, "quadric is degenerate: A..I are all zero, so it has no surface");
  for (const HalfSpace& h : p.clips) {
    require(all_finite(h.n) && std::isfinite(h.d), "clip half-space is not finite");
    require(max_abs(h.n) > 0, "clip half-space has a zero normal");
  }
  if (p.has_local) {
    require_finite_coefficients(p.local, "local quadric");
    require(all_finite(p.origin), "primitive origin is not finite");
  }
}

}  // namespace rtm
