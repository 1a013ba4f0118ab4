// Any simple planar polygon as the machine can test it: convex pieces, each a plane quadric
// clipped by one half-space per edge (docs/scene-format.md, "Polygons").
#pragma once

#include <array>
#include <vector>

#include "geom/quadric.h"

namespace rtm {

using Point2 = std::array<double, 2>;

/// Splits a simple polygon, counter-clockwise in the plane, into convex pieces that meet only
/// along diagonals between its vertices: an ear-clipping triangulation whose diagonals are then
/// removed wherever the two pieces on either side stay convex (Hertel & Mehlhorn, 1983: at most
/// four times the fewest pieces, and never more than twice the reflex vertices plus one). Three
/// orders of removal are tried and the fewest pieces kept. Each piece lists indices into `outline`,
/// counter-clockwise. Throws std::invalid_argument if the outline is not simple (edges that cross
/// or touch, as a hole joined by a slit does) or not counter-clockwise.
std::vector<std::vector<int>> convex_pieces(const std::vector<Point2>& outline);

/// Is the simple polygon convex (no reflex corner; straight corners allowed)?
bool is_convex(const std::vector<Point2>& outline);

/// The most corners a polygon may have. Splitting a concave polygon takes time quadratic in its
/// corners, or worse (a zigzag of 3,000 corners took 0.08 s, of 30,000 corners 36 s; of 1024,
/// 17 ms); SPD's largest face has 144.
constexpr size_t kMaxPolygonCorners = 1024;

/// The primitives of a planar polygon, vertices counter-clockwise seen from the front. A convex
/// polygon is one primitive, exactly make_polygon's. A concave one is split (convex_pieces): every
/// piece has the whole polygon's plane, and the two pieces beside a diagonal have exactly opposite
/// half-spaces, so no ray passes between them. Each piece records its number and the count, and
/// piece 0 the whole outline (Primitive::outline). Throws DegenerateShape for fewer than 3 distinct
/// vertices or a zero area, std::invalid_argument for more than kMaxPolygonCorners vertices,
/// vertices that are not coplanar or an outline that crosses or touches itself.
std::vector<Primitive> make_polygon_pieces(const std::vector<Vec3>& vertices);

}  // namespace rtm
