#include "geom/polygon.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "geom/test_random.h"

namespace rtm {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Even-odd point-in-polygon in the xy plane: the reference the pieces must reproduce.
bool inside_outline(const std::vector<Point2>& p, double x, double y) {
  bool in = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    if ((p[i][1] > y) != (p[j][1] > y) &&
        x < (p[j][0] - p[i][0]) * (y - p[i][1]) / (p[j][1] - p[i][1]) + p[i][0])
      in = !in;
  }
  return in;
}

int reflex_corners(const std::vector<Point2>& p) {
  int r = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Point2 &a = p[(i + p.size() - 1) % p.size()], &b = p[i], &c = p[(i + 1) % p.size()];
    r += (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < 0;
  }
  return r;
}

std::vector<Point2> star(int points, double outer, double inner) {
  std::vector<Point2> p;
  for (int i = 0; i < 2 * points; ++i) {
    const double a = kPi * i / points, r = i % 2 ? inner : outer;
    p.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return p;
}

/// The first gear face of SPD gears-1 (line 21: 144 vertices, 36 teeth), in its z = 1 plane.
std::vector<Point2> gear_face() {
  std::ifstream f(RTM_SOURCE_DIR "/scenes/spd-corpus/gears-1.nff");
  std::string line;
  for (int n = 1; n < 21 && std::getline(f, line); ++n) {
  }
  std::getline(f, line);
  EXPECT_EQ(line, "p 144");
  std::vector<Point2> p;
  for (int i = 0; i < 144 && std::getline(f, line); ++i) {
    std::istringstream s(line);
    double x, y, z;
    s >> x >> y >> z;
    p.push_back({x, y});
  }
  return p;
}

std::vector<Vec3> in_space(const std::vector<Point2>& p, double z = 0) {
  std::vector<Vec3> v;
  for (const Point2& q : p) v.push_back({q[0], q[1], z});
  return v;
}

/// Every piece is convex and counter-clockwise, and a point lies in some piece exactly when it
/// lies in the outline (away from the edges, where rounding decides), in at most one piece.
void expect_exact_cover(const std::vector<Point2>& outline,
                        const std::vector<std::vector<int>>& pieces) {
  for (const auto& piece : pieces) {
    std::vector<Point2> q;
    for (int i : piece) q.push_back(outline[size_t(i)]);
    EXPECT_TRUE(is_convex(q));
  }
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const Point2& q : outline)
    for (int a = 0; a < 2; ++a)
      lo[a] = std::min(lo[a], q[size_t(a)]), hi[a] = std::max(hi[a], q[size_t(a)]);
  std::mt19937 rng(7);
  int covered = 0, wrong = 0;
  for (int k = 0; k < 4000; ++k) {
    const double x = test::uniform(rng, lo[0], hi[0]), y = test::uniform(rng, lo[1], hi[1]);
    int in_pieces = 0;
    for (const auto& piece : pieces) {
      std::vector<Point2> q;
      for (int i : piece) q.push_back(outline[size_t(i)]);
      in_pieces += inside_outline(q, x, y);
    }
    const bool in = inside_outline(outline, x, y);
    covered += in;
    wrong += in_pieces != (in ? 1 : 0);
  }
  EXPECT_GT(covered, 100);
  EXPECT_EQ(wrong, 0);
}

TEST(ConvexPieces, LShapeIsTwoPieces) {
  const std::vector<Point2> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const auto pieces = convex_pieces(l);
  EXPECT_EQ(pieces.size(), 2u);
  expect_exact_cover(l, pieces);
}

TEST(ConvexPieces, StarsNeedFewPieces) {
  for (int points : {5, 6, 12}) {
    SCOPED_TRACE(points);
    const std::vector<Point2> s = star(points, 1, 0.4);
    const auto pieces = convex_pieces(s);
    // A star with r reflex corners needs at least ceil(r/2) + 1 pieces (each diagonal ends at two
    // corners at most); Hertel–Mehlhorn's bound is 2r + 1. Here it stays within r + 1.
    const int r = reflex_corners(s);
    EXPECT_EQ(r, points);
    EXPECT_GE(int(pieces.size()), (r + 1) / 2 + 1);
    EXPECT_LE(int(pieces.size()), r + 1);
    expect_exact_cover(s, pieces);
  }
}

TEST(ConvexPieces, GearFaceIsTheFewestPossible) {
  const std::vector<Point2> g = gear_face();
  ASSERT_EQ(g.size(), 144u);
  const auto pieces = convex_pieces(g);
  const int r = reflex_corners(g);
  EXPECT_EQ(r, 72);
  // 36 teeth on a convex hub: ceil(72 / 2) + 1 is the lower bound, and it is met.
  EXPECT_EQ(int(pieces.size()), r / 2 + 1);
  expect_exact_cover(g, pieces);
}

TEST(ConvexPieces, RandomStarShapedPolygons) {
  std::mt19937 rng(11);
  for (int k = 0; k < 30; ++k) {
    const int n = 3 + int(rng() % 40);
    std::vector<Point2> p;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * (i + test::uniform(rng, 0.1, 0.9)) / n,
                   r = test::uniform(rng, 0.2, 1);
      p.push_back({r * std::cos(a), r * std::sin(a)});
    }
    const auto pieces = convex_pieces(p);
    EXPECT_LE(int(pieces.size()), 2 * reflex_corners(p) + 1);
    expect_exact_cover(p, pieces);
  }
}

TEST(ConvexPieces, SpiralsAndCombsThatNoPointSeesWhole) {
  // A spiral strip three turns long and a comb of random teeth: not star-shaped, so no fan from
  // any point triangulates them.
  std::vector<Point2> outer, inner;
  for (int i = 0; i < 150; ++i) {
    const double t = 6 * kPi * i / 150, r = 1 + t;
    outer.push_back({r * std::cos(t), r * std::sin(t)});
    inner.push_back({(r - 0.5) * std::cos(t), (r - 0.5) * std::sin(t)});
  }
  std::vector<Point2> spiral = outer;
  spiral.insert(spiral.end(), inner.rbegin(),
                inner.rend());  // out along the outer edge, back along the inner: counter-clockwise
  auto pieces = convex_pieces(spiral);
  EXPECT_LE(int(pieces.size()), 2 * reflex_corners(spiral) + 1);
  expect_exact_cover(spiral, pieces);

  std::mt19937 rng(13);
  std::vector<Point2> comb = {{0, 0}, {20, 0}};
  for (int i = 9; i >= 0; --i) {
    const double h = test::uniform(rng, 1.5, 6);
    comb.push_back({2.0 * i + 2, h});
    comb.push_back({2.0 * i + 1, h});
    comb.push_back({2.0 * i + 1, 1});
    comb.push_back({2.0 * i, 1});  // the last is the outline's corner (0, 1)
  }
  pieces = convex_pieces(comb);
  EXPECT_LE(int(pieces.size()), 2 * reflex_corners(comb) + 1);
  expect_exact_cover(comb, pieces);
}

TEST(ConvexPieces, RejectsSelfIntersectionsHolesAndClockwise) {
  EXPECT_THROW(convex_pieces({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), std::invalid_argument);  // bow tie
  // A square with a square hole, joined by a slit walked both ways: the slit's edges touch.
  EXPECT_THROW(convex_pieces({{0, 0},
                              {4, 0},
                              {4, 4},
                              {0, 4},
                              {0, 2},
                              {1, 2},
                              {1, 3},
                              {3, 3},
                              {3, 1},
                              {1, 1},
                              {1, 2},
                              {0, 2}}),
               std::invalid_argument);
  // An edge folding back along itself.
  EXPECT_THROW(convex_pieces({{0, 0}, {2, 0}, {1, 0}, {1, 1}}), std::invalid_argument);
  EXPECT_THROW(convex_pieces({{0, 0}, {0, 1}, {1, 1}, {1, 0}}),
               std::invalid_argument);  // clockwise
}

TEST(PolygonPieces, ConvexPolygonIsMakePolygonExactly) {
  const std::vector<Vec3> v = {{0, 0, 1}, {1, 0, 1.5}, {1, 1, 2}, {0, 1, 1.5}};
  const auto ps = make_polygon_pieces(v);
  ASSERT_EQ(ps.size(), 1u);
  const Primitive one = make_polygon(v);
  EXPECT_EQ(ps[0].q.c, one.q.c);
  ASSERT_EQ(ps[0].clips.size(), one.clips.size());
  for (size_t i = 0; i < one.clips.size(); ++i) {
    EXPECT_EQ(ps[0].clips[i].n, one.clips[i].n);
    EXPECT_EQ(ps[0].clips[i].d, one.clips[i].d);
  }
  EXPECT_EQ(ps[0].pieces, 1);
  EXPECT_TRUE(ps[0].outline.empty());
}

TEST(PolygonPieces, ConcavePiecesShareThePlaneAndCloseEveryGap) {
  // The gear face tilted out of the coordinate planes, both windings.
  const Frame f = Frame::along({3, -2, 5}, {0.3, -0.5, 0.8});
  for (bool reversed : {false, true}) {
    SCOPED_TRACE(reversed);
    std::vector<Vec3> v;
    for (const Point2& q : gear_face()) v.push_back(f.origin + q[0] * f.ex + q[1] * f.ey);
    if (reversed) std::reverse(v.begin(), v.end());
    const auto ps = make_polygon_pieces(v);
    ASSERT_EQ(ps.size(), 37u);
    EXPECT_EQ(ps[0].outline.size(), 144u);
    for (size_t i = 0; i < ps.size(); ++i) {
      EXPECT_EQ(ps[i].q.c, ps[0].q.c);
      EXPECT_EQ(ps[i].piece, int(i));
      EXPECT_EQ(ps[i].pieces, 37);
    }
    // Points of the plane: inside the outline exactly when inside one piece's clips or more (on a
    // diagonal, both pieces hold the point: no gaps).
    std::mt19937 rng(3);
    int wrong = 0, on_diagonals = 0;
    const std::vector<Point2> flat = gear_face();
    for (int k = 0; k < 20000; ++k) {
      const double x = test::uniform(rng, -1.1, 1.1), y = test::uniform(rng, -1.1, 1.1);
      const Vec3 p = f.origin + x * f.ex + y * f.ey;
      int holders = 0;
      for (const Primitive& piece : ps) holders += piece.inside_clips(p);
      wrong += (holders > 0) != inside_outline(flat, x, y);
    }
    EXPECT_EQ(wrong, 0);
    // Points exactly on each diagonal's line, between its ends: some piece holds every one.
    int diagonals = 0;
    for (const Primitive& piece : ps)
      for (size_t e = 0; e < piece.vertices.size(); ++e) {
        const Vec3 a = piece.vertices[e], b = piece.vertices[(e + 1) % piece.vertices.size()];
        bool shared = false;  // another piece has the edge the other way round: a diagonal
        for (const Primitive& other : ps)
          for (size_t k = 0; &other != &piece && k < other.vertices.size(); ++k)
            shared = shared || (other.vertices[k] == b &&
                                other.vertices[(k + 1) % other.vertices.size()] == a);
        if (!shared) continue;
        ++diagonals;
        for (double t : {0.1, 0.37, 0.5, 0.81}) {
          const Vec3 p = a + t * (b - a);
          int holders = 0;
          for (const Primitive& other : ps) holders += other.inside_clips(p);
          on_diagonals += holders == 0;
        }
      }
    EXPECT_EQ(diagonals, 2 * 36);  // each tooth's base, seen from both sides
    EXPECT_EQ(on_diagonals, 0);
  }
}

/// A comb of teeth on a base: concave, with a reflex corner at the foot of every tooth.
std::vector<Point2> comb_outline(int teeth) {
  std::vector<Point2> p = {{0, 0}, {2.0 * teeth, 0}};
  for (int i = teeth; i > 0; --i) {
    p.push_back({2.0 * i - 1, 100});
    p.push_back({2.0 * i - 2, 1});
  }
  return p;
}

TEST(PolygonPieces, TheMostCornersSplitQuicklyAndOneMoreIsRefused) {
  const int teeth = int(kMaxPolygonCorners) / 2 - 1;
  const std::vector<Point2> comb = comb_outline(teeth);
  std::vector<Vec3> v = in_space(comb);
  ASSERT_EQ(v.size(), kMaxPolygonCorners);
  const auto t0 = std::chrono::steady_clock::now();
  const size_t pieces = make_polygon_pieces(v).size();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  EXPECT_GE(pieces, size_t(teeth));  // no convex piece holds two teeth
  EXPECT_LE(pieces, size_t(2 * reflex_corners(comb) + 1));
  v.insert(v.begin() + 1, {1, 0, 0});  // a straight corner on the base: the same polygon
  try {
    make_polygon_pieces(v);
    FAIL() << kMaxPolygonCorners + 1 << " corners were taken";
  } catch (const DegenerateShape&) {
    FAIL() << "too many corners is an error, not degenerate";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("polygon has 1025 vertices, at most 1024"),
              std::string::npos)
        << e.what();
  }
}

TEST(PolygonPieces, DegenerateAndInvalid) {
  EXPECT_THROW(make_polygon_pieces({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}), DegenerateShape);
  EXPECT_THROW(make_polygon_pieces({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}), DegenerateShape);
  EXPECT_THROW(make_polygon_pieces({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}), DegenerateShape);
  try {
    make_polygon_pieces({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}});
    FAIL();
  } catch (const DegenerateShape&) {
    FAIL() << "non-planar is an error, not degenerate";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not coplanar"), std::string::npos);
  }
  try {
    make_polygon_pieces(in_space({{0, 0}, {2, 2}, {2, 0}, {0, 1}}));
    FAIL();
  } catch (const DegenerateShape&) {
    FAIL() << "a bow tie is an error, not degenerate";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not simple"), std::string::npos);
  }
}

}  // namespace
}  // namespace rtm
