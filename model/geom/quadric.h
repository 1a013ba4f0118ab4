// Quadric primitives: the surface the paper's machine intersects, bounded so it can be voxelised.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "geom/vec.h"

namespace rtm {

/// Index of each coefficient in the paper's order:
/// A x² + B y² + C z² + D xy + E yz + F zx + G x + H y + I z + J = 0.
enum Coef : int { kA, kB, kC, kD, kE, kF, kG, kH, kI, kJ };

struct Quadric {
  std::array<double, 10> c{};  ///< A..J

  double value(const Vec3& p) const;
  /// ∇Q; the outward normal for closed surfaces written with Q > 0 outside.
  Vec3 gradient(const Vec3& p) const;
  /// The same surface in coordinates x' = x − c: the quadratic part is unchanged, the linear part
  /// becomes ∇Q(c) and the constant Q(c). Re-centring on a primitive avoids the cancellation in J
  /// (|c|² − r² for a sphere) that ruins float32 far from the origin.
  Quadric translated(const Vec3& c) const;
};

/// The closed half-space n·p + d <= 0 (the side a clipped surface keeps).
struct HalfSpace {
  Vec3 n;
  double d = 0;

  double eval(const Vec3& p) const { return dot(n, p) + d; }
  /// The same half-space in coordinates x' = x − c.
  HalfSpace translated(const Vec3& c) const { return {n, d + dot(n, c)}; }
};

/// What a primitive was made from: kept so exporters can write the native shape.
enum class ShapeKind {
  Sphere,
  Ellipsoid,
  Cylinder,
  Cone,
  Plane,
  Paraboloid,
  Hyperboloid1,
  Hyperboloid2,
  Polygon,
  Raw
};
const char* shape_name(ShapeKind k);

/// A quadric surface kept only where every clip half-space holds, inside a finite box.
/// Coordinates beyond this magnitude are rejected: squared distances must stay finite in double.
constexpr double kMaxCoordinate = 1e150;

struct Primitive {
  Quadric q;  ///< world coefficients
  /// The same quadric in coordinates x' = x − origin, built by the constructor from the shape's
  /// parameters (has_local). Far from the world origin the world constant term J cancels
  /// (|c|² − r² for a sphere loses r² once r² < 2⁻⁵² |c|²); this form does not, and re-centring,
  /// refinement and normals start from it. Without it (raw quadrics, hand-made primitives) they
  /// start from q.
  Quadric local;
  Vec3 origin{0, 0, 0};
  bool has_local = false;
  std::vector<HalfSpace> clips;
  Aabb bounds;  ///< finite; the surface lies inside it
  ShapeKind kind = ShapeKind::Raw;
  int material = 0;

  // The shape's own parameters, for exporters (which fields are used depends on kind).
  Vec3 p0{}, p1{};             ///< centre / base centre; apex centre
  double r0 = 0, r1 = 0;       ///< radius / base radius; apex radius
  std::vector<Vec3> vertices;  ///< polygon corners
  /// A triangle's unit vertex normals, one per corner (NFF pp, a mesh file's); empty: none, the
  /// plane's normal. Shading may weight them by the hit's barycentric coordinates (render/shade.h).
  std::vector<Vec3> normals;
  /// A concave polygon is several convex primitives (geom/polygon.h): this one's number among
  /// them and their count; piece 0 also keeps the whole polygon's corners, for exporters.
  int piece = 0, pieces = 1;
  std::vector<Vec3> outline;

  /// The quadric in coordinates x' = x − c (from the local form when there is one).
  Quadric about(const Vec3& c) const {
    return has_local ? local.translated(c - origin) : q.translated(c);
  }
  /// Q(p) and ∇Q(p) at a world point, from the local form when there is one.
  double value_at(const Vec3& p) const { return has_local ? local.value(p - origin) : q.value(p); }
  Vec3 gradient_at(const Vec3& p) const {
    return has_local ? local.gradient(p - origin) : q.gradient(p);
  }

  bool inside_clips(const Vec3& p) const {
    for (const HalfSpace& h : clips)
      if (h.eval(p) > 0) return false;
    return true;
  }
};

/// An orthonormal frame placing a shape's local z axis in the world.
struct Frame {
  Vec3 origin{0, 0, 0};
  Vec3 ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};

  /// Frame with local z along `axis`; x and y are any perpendicular pair.
  static Frame along(const Vec3& origin, const Vec3& axis);
};

/// A shape that is well formed but has no surface to render: a zero radius, a zero length, a
/// polygon of zero area. Readers of files from the wild may skip it with a warning instead of
/// rejecting the file (docs/scene-format.md, "Skipped records").
class DegenerateShape : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Shape constructors. Each validates its arguments and throws std::invalid_argument with a
// message a user can act on (non-finite values, non-positive radii, degenerate axes, ...), and
// DegenerateShape where the shape is merely empty.
Primitive make_sphere(const Vec3& centre, double radius);
Primitive make_ellipsoid(const Frame& f, const Vec3& radii);
/// NFF `c`: a cone or cylinder (equal radii) without caps, between two centres, any axis.
Primitive make_cone(const Vec3& base, double base_radius, const Vec3& apex, double apex_radius);
/// x² + y² = k z in the frame, 0 <= z <= height.
Primitive make_paraboloid(const Frame& f, double k, double height);
/// x²/a² + y²/a² − z²/c² = 1 in the frame, |z| <= half_height.
Primitive make_hyperboloid1(const Frame& f, double a, double c, double half_height);
/// x²/a² + y²/a² − z²/c² = −1 in the frame (both sheets), |z| <= half_height (> c).
Primitive make_hyperboloid2(const Frame& f, double a, double c, double half_height);
/// The plane n·p + d = 0 clipped to a box.
Primitive make_plane(const Vec3& n, double d, const Aabb& box);
/// A convex planar polygon; vertices counter-clockwise seen from the front.
Primitive make_polygon(const std::vector<Vec3>& vertices);

/// A polygon's outline as make_polygon and the convex split (geom/polygon.h) both read it:
/// repeated consecutive vertices (and a closing copy of the first) dropped, Newell's normal
/// (unnormalised: its length is twice the area) and the box around it. Throws DegenerateShape
/// when fewer than 3 distinct vertices are left.
struct PolygonOutline {
  std::vector<Vec3> v;
  Vec3 newell;
  Aabb box;
  double size() const { return length(box.extent()); }  ///< the scale of its tolerances
};
PolygonOutline polygon_outline(const std::vector<Vec3>& vertices);
/// Vertex normals as `triangle` keeps them (Primitive::normals): each made unit length; empty
/// (the plane's normal, flat) when any is zero or not finite, or when they do not all lie strictly
/// on one side of the face, where their blend can vanish or turn edge-on inside the triangle
/// (POV-Ray drops such a smooth_triangle as degenerate).
std::vector<Vec3> vertex_normals(const Primitive& triangle, const std::vector<Vec3>& normals);
/// What a reader says of a triangle whose normals vertex_normals() left out.
constexpr const char* kFlatNormalsReason =
    "a normal is zero, or they are not all on one side of the face: shaded flat";
/// Raw coefficients, clipped to `box` and the given half-spaces.
Primitive make_raw_quadric(const std::array<double, 10>& coef, const Aabb& box,
                           std::vector<HalfSpace> clips);

/// Throws std::invalid_argument unless every coefficient, clip and bound is finite and the
/// quadric is not identically zero. Called by every constructor; callable on loaded data.
void validate(const Primitive& p);

}  // namespace rtm
