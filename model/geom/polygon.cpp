#include "geom/polygon.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

namespace rtm {
namespace {

/// Twice the signed area of triangle abc: > 0 when it turns left (counter-clockwise).
double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Is p inside or on the boundary of the counter-clockwise triangle abc?
bool in_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

bool on_segment(const Point2& p, const Point2& a, const Point2& b) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
         std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
}

/// Do the closed segments ab and cd have a point in common?
bool segments_meet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return (o1 == 0 && on_segment(c, a, b)) || (o2 == 0 && on_segment(d, a, b)) ||
         (o3 == 0 && on_segment(a, c, d)) || (o4 == 0 && on_segment(b, c, d));
}

std::string edge_name(int i, int n) {
  return std::to_string(i + 1) + "-" + std::to_string((i + 1) % n + 1);
}

/// Throws unless the closed outline is simple: no two edges meet except neighbours at their
/// shared corner, and no corner folds an edge back onto the one before it.
void require_simple(const std::vector<Point2>& p) {
  const int n = int(p.size());
  for (int i = 0; i < n; ++i) {
    const Point2 &a = p[size_t(i)], &b = p[size_t((i + 1) % n)], &c = p[size_t((i + 2) % n)];
    // Neighbours meet only at b: folding back along the same line is a touch too.
    if (orient(a, b, c) == 0 && (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) < 0)
      throw std::invalid_argument("polygon is not simple: edges " + edge_name(i, n) + " and " +
                                  edge_name((i + 1) % n, n) + " fold back on each other");
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours across the closing corner
      if (segments_meet(p[size_t(i)], p[size_t((i + 1) % n)], p[size_t(j)], p[size_t((j + 1) % n)]))
        throw std::invalid_argument(
            "polygon is not simple: edges " + edge_name(i, n) + " and " + edge_name(j, n) +
            " (vertex numbers) cross or touch; holes and self-intersections are not supported");
    }
}

/// Ear clipping: triangles of indices into p (counter-clockwise, simple), in the order clipped.
std::vector<std::array<int, 3>> triangulate(const std::vector<Point2>& p) {
  std::vector<int> ring(p.size());
  std::iota(ring.begin(), ring.end(), 0);
  std::vector<std::array<int, 3>> tris;
  size_t i = 0, tries = 0;
  while (ring.size() > 3) {
    const size_t m = ring.size();
    const int a = ring[(i + m - 1) % m], b = ring[i % m], c = ring[(i + 1) % m];
    bool ear = orient(p[size_t(a)], p[size_t(b)], p[size_t(c)]) > 0;
    for (size_t k = 0; ear && k < m; ++k) {
      const int w = ring[k];
      if (w == a || w == b || w == c) continue;
      // A corner on the diagonal ac or inside abc would be cut off: not an ear.
      ear = !in_triangle(p[size_t(w)], p[size_t(a)], p[size_t(b)], p[size_t(c)]);
    }
    if (ear) {
      tris.push_back({a, b, c});
      ring.erase(ring.begin() + std::ptrdiff_t(i % m));
      tries = 0;
      i = i % ring.size();
    } else {
      i = (i + 1) % m;
      // A simple polygon always has an ear (Meisters' two-ears theorem); none in a whole round
      // means rounding has made the outline non-simple.
      if (++tries > m)
        throw std::invalid_argument(
            "polygon could not be triangulated (is it nearly self-touching?)");
    }
  }
  tris.push_back({ring[0], ring[1], ring[2]});
  return tris;
}

struct Diagonal {
  int a, b;
  double length2;
};

/// Hertel–Mehlhorn: removes the diagonals in `order` wherever the merged piece stays convex.
std::vector<std::vector<int>> merge_pieces(const std::vector<Point2>& p,
                                           const std::vector<std::array<int, 3>>& tris,
                                           const std::vector<Diagonal>& order) {
  std::vector<std::vector<int>> pieces;
  std::map<std::pair<int, int>, int> owner;  // directed edge -> the piece that has it
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) owner[{t[size_t(k)], t[size_t((k + 1) % 3)]}] = int(pieces.size());
    pieces.push_back({t[0], t[1], t[2]});
  }
  std::vector<bool> alive(pieces.size(), true);
  for (const Diagonal& d : order) {
    const auto pa = owner.find({d.a, d.b}), pb = owner.find({d.b, d.a});
    if (pa == owner.end() || pb == owner.end()) continue;
    const int P = pa->second, Q = pb->second;
    if (P == Q) continue;
    // Merged cycle: P from b round to a, then Q from a round to b, without repeating a and b.
    const std::vector<int>&vp = pieces[size_t(P)], &vq = pieces[size_t(Q)];
    const size_t ib = size_t(std::find(vp.begin(), vp.end(), d.b) - vp.begin());
    const size_t ia = size_t(std::find(vq.begin(), vq.end(), d.a) - vq.begin());
    std::vector<int> merged;
    for (size_t k = 0; k < vp.size(); ++k) merged.push_back(vp[(ib + k) % vp.size()]);  // b ... a
    for (size_t k = 1; k + 1 < vq.size(); ++k)
      merged.push_back(vq[(ia + k) % vq.size()]);  // after a ... before b
    // Only the corners at a and b change; each must stay convex (straight is allowed).
    const size_t m = merged.size(), at_a = vp.size() - 1;
    auto corner_ok = [&](size_t k) {
      return orient(p[size_t(merged[(k + m - 1) % m])], p[size_t(merged[k])],
                    p[size_t(merged[(k + 1) % m])]) >= 0;
    };
    if (!corner_ok(0) || !corner_ok(at_a)) continue;
    owner.erase(pa);
    owner.erase(pb);
    for (size_t k = 0; k < vq.size(); ++k) {
      const auto e = owner.find({vq[k], vq[(k + 1) % vq.size()]});
      if (e != owner.end()) e->second = P;
    }
    pieces[size_t(P)] = std::move(merged);
    pieces[size_t(Q)].clear();
    alive[size_t(Q)] = false;
  }
  std::vector<std::vector<int>> out;
  for (size_t k = 0; k < pieces.size(); ++k)
    if (alive[k]) out.push_back(std::move(pieces[k]));
  return out;
}

}  // namespace

bool is_convex(const std::vector<Point2>& p) {
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i)
    if (orient(p[i], p[(i + 1) % n], p[(i + 2) % n]) < 0) return false;
  return true;
}

std::vector<std::vector<int>> convex_pieces(const std::vector<Point2>& p) {
  if (p.size() < 3) throw std::invalid_argument("a polygon needs at least 3 vertices");
  double area2 = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Point2 &a = p[i], &b = p[(i + 1) % p.size()];
    area2 += a[0] * b[1] - a[1] * b[0];
  }
  if (!(area2 > 0)) throw std::invalid_argument("polygon outline is not counter-clockwise");
  require_simple(p);
  const std::vector<std::array<int, 3>> tris = triangulate(p);
  const int n = int(p.size());
  std::vector<Diagonal> diagonals;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      const bool outline_edge = (a + 1) % n == b || (b + 1) % n == a;
      const double dx = p[size_t(a)][0] - p[size_t(b)][0], dy = p[size_t(a)][1] - p[size_t(b)][1];
      if (!outline_edge && a < b) diagonals.push_back({a, b, dx * dx + dy * dy});
    }
  // The order of removal decides how many pieces are left: try the clipping order and both length
  // orders, keep the fewest.
  std::vector<std::vector<int>> best = merge_pieces(p, tris, diagonals);
  for (int longest_first = 0; longest_first < 2; ++longest_first) {
    std::vector<Diagonal> order = diagonals;
    std::stable_sort(order.begin(), order.end(), [&](const Diagonal& x, const Diagonal& y) {
      return longest_first ? x.length2 > y.length2 : x.length2 < y.length2;
    });
    std::vector<std::vector<int>> pieces = merge_pieces(p, tris, order);
    if (pieces.size() < best.size()) best = std::move(pieces);
  }
  return best;
}

std::vector<Primitive> make_polygon_pieces(const std::vector<Vec3>& in) {
  if (in.size() > kMaxPolygonCorners)
    throw std::invalid_argument(
        "polygon has " + std::to_string(in.size()) + " vertices, at most " +
        std::to_string(kMaxPolygonCorners) +
        " (splitting a concave polygon takes time quadratic in its corners)");
  for (const Vec3& p : in)
    if (!all_finite(p)) throw std::invalid_argument("polygon vertex is not finite");
  // The outline and its plane exactly as make_polygon sees them.
  const PolygonOutline outline = polygon_outline(in);
  const std::vector<Vec3>& v = outline.v;
  Vec3 n = outline.newell;
  const double size = outline.size();
  if (!(length(n) > 1e-12 * size * size)) {
    // Nothing to render only if the corners lie on one line; a symmetric bow tie has zero signed
    // area too, but two visible triangles.
    size_t far = 0;
    for (size_t i = 1; i < v.size(); ++i)
      if (length(v[i] - v[0]) > length(v[far] - v[0])) far = i;
    for (const Vec3& p : v)
      if (length(cross(v[far] - v[0], p - v[0])) > 1e-12 * size * size)
        throw std::invalid_argument(
            "polygon is not simple: its edges cross (its signed area is zero)");
    throw DegenerateShape("polygon has zero area");
  }
  n = normalize(n);
  const double d = -dot(n, v[0]);
  for (const Vec3& p : v)
    if (!(std::abs(dot(n, p) + d) <= 1e-6 * size))
      throw std::invalid_argument("polygon vertices are not coplanar");

  // In the plane: drop the normal's largest axis (exact coordinates, no rotation), ordered so the
  // outline runs counter-clockwise.
  const int k = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? 0
                : std::abs(n.y) >= std::abs(n.z)                                 ? 1
                                                                                 : 2;
  const int u = (k + 1) % 3, w = (k + 2) % 3;
  const bool flip = n[k] < 0;
  std::vector<Point2> flat;
  std::vector<int> index;  // flat -> v
  for (size_t i = 0; i < v.size(); ++i) {
    const size_t j = flip ? v.size() - 1 - i : i;
    flat.push_back({v[j][u], v[j][w]});
    index.push_back(int(j));
  }
  // A straight corner (on the line of its neighbours, not folding back) changes nothing.
  for (bool removed = true; removed && flat.size() > 3;) {
    removed = false;
    for (size_t i = 0; i < flat.size() && flat.size() > 3; ++i) {
      const size_t a = (i + flat.size() - 1) % flat.size(), c = (i + 1) % flat.size();
      const Point2 &pa = flat[a], &pb = flat[i], &pc = flat[c];
      if (orient(pa, pb, pc) == 0 &&
          (pb[0] - pa[0]) * (pc[0] - pb[0]) + (pb[1] - pa[1]) * (pc[1] - pb[1]) > 0) {
        flat.erase(flat.begin() + std::ptrdiff_t(i));
        index.erase(index.begin() + std::ptrdiff_t(i));
        removed = true;
      }
    }
  }
  // Convex in every edge's sense (make_polygon's own test): one primitive, exactly as before.
  bool convex = true;
  for (size_t i = 0; convex && i < v.size(); ++i) {
    const Vec3 out = cross(v[(i + 1) % v.size()] - v[i], n);
    if (length(out) == 0) continue;
    const Vec3 m = normalize(out);
    for (const Vec3& q : v) convex = convex && dot(m, q - v[i]) <= 1e-9 * size;
  }
  if (convex) return {make_polygon(in)};

  const std::vector<std::vector<int>> pieces = convex_pieces(flat);
  std::vector<Primitive> out;
  for (const std::vector<int>& piece : pieces) {
    std::vector<int> corners;  // indices into v, counter-clockwise seen from the front
    for (int f : piece) corners.push_back(index[size_t(f)]);
    if (flip) std::reverse(corners.begin(), corners.end());
    Primitive p;
    p.kind = ShapeKind::Polygon;
    p.q.c = {0, 0, 0, 0, 0, 0, n.x, n.y, n.z, d};
    p.local.c = {0, 0, 0, 0, 0, 0, n.x, n.y, n.z, 0};  // about the whole polygon's first vertex
    p.origin = v[0];
    p.has_local = true;
    for (size_t i = 0; i < corners.size(); ++i) {
      const int a = corners[i], b = corners[(i + 1) % corners.size()];
      p.vertices.push_back(v[size_t(a)]);
      p.bounds.extend(v[size_t(a)]);
      const Vec3 out_dir = cross(v[size_t(b)] - v[size_t(a)], n);
      if (length(out_dir) == 0) continue;
      const Vec3 m = normalize(out_dir);
      // Anchored at the edge's lower-numbered end: the piece across a diagonal computes the same
      // products with every sign flipped, so its half-space is exactly the complement's closure.
      p.clips.push_back({m, -dot(m, v[size_t(std::min(a, b))])});
    }
    validate(p);
    out.push_back(std::move(p));
  }
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].piece = int(i);
    out[i].pieces = int(out.size());
  }
  out[0].outline = v;
  return out;
}

}  // namespace rtm
