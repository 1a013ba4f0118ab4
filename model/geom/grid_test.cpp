// The uniform grid: conservative and tight voxelisation, the interval test, auto resolution.
#include "geom/grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "geom/dda.h"
#include "geom/intersect.h"
#include "geom/test_random.h"

namespace rtm {
namespace {

using namespace rtm::test;

constexpr double kPi = 3.14159265358979323846;

Vec3 random_point(std::mt19937& rng, double scale) {
  return Vec3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * scale;
}

Frame random_frame(std::mt19937& rng, const Vec3& origin) {
  const Frame base = Frame::along(origin, random_unit(rng));
  const double a = uniform(rng, 0, 2 * kPi);
  Frame f = base;
  f.ex = normalize(std::cos(a) * base.ex + std::sin(a) * base.ey);
  f.ey = cross(f.ez, f.ex);
  return f;
}

/// One primitive of a random kind, about `size` across, near `centre`.
Primitive random_primitive(std::mt19937& rng, const Vec3& centre, double size) {
  const Frame f = random_frame(rng, centre);
  switch (rng() % 9) {
    case 0:
      return make_sphere(centre, size * uniform(rng, 0.2, 0.6));
    case 1:
      return make_ellipsoid(f, uniform_zyx(rng, 0.1, 0.6) * size);
    case 2: {
      const Vec3 axis = rng() % 3 ? random_unit(rng) : Vec3{0, 0, 1};  // some axis-aligned
      const double r = size * uniform(rng, 0.05, 0.4);
      return make_cone(centre - 0.5 * size * axis, r, centre + 0.5 * size * axis,
                       rng() % 2 ? r : 0.3 * r);
    }
    // Cases 3 and 4 draw their second argument first (test_random.h says why).
    case 3: {
      const double height = size * uniform(rng, 0.2, 0.8);
      return make_paraboloid(f, size * uniform(rng, 0.2, 1), height);
    }
    case 4: {
      const double c = size * uniform(rng, 0.1, 0.5);
      return make_hyperboloid1(f, size * uniform(rng, 0.1, 0.3), c, size * 0.4);
    }
    case 5: {
      const double c = size * uniform(rng, 0.05, 0.2);
      return make_hyperboloid2(f, size * uniform(rng, 0.1, 0.3), c, c + size * 0.3);
    }
    case 6: {
      const Vec3 h(0.5 * size);
      return make_plane(f.ez, -dot(f.ez, centre), Aabb{centre - h, centre + h});
    }
    case 7: {
      std::vector<Vec3> v;
      const int k = 3 + int(rng() % 3);
      for (int i = 0; i < k; ++i) {
        const double a = 2 * kPi * (i + uniform(rng, -0.3, 0.3)) / k;
        v.push_back(centre + 0.5 * size * (std::cos(a) * f.ex + std::sin(a) * f.ey));
      }
      return make_polygon(v);
    }
    default: {
      // A raw quadric: a saddle z = x y, clipped to a box and a slanted half-space.
      const Vec3 c = centre;
      std::array<double, 10> q{0, 0, 0, 1, 0, 0, -c.y, -c.x, -1, c.x * c.y + c.z};
      const Vec3 h(0.5 * size);
      return make_raw_quadric(
          q, Aabb{c - h, c + h},
          {HalfSpace{normalize(Vec3{1, 1, 0}), -dot(normalize(Vec3{1, 1, 0}), c)}});
    }
  }
}

std::vector<Primitive> random_scene(std::mt19937& rng, int count, double extent,
                                    const Vec3& offset = {0, 0, 0}) {
  std::vector<Primitive> prims;
  for (int i = 0; i < count; ++i) {
    // The size drawn before the centre (test_random.h says why).
    const double size = extent * uniform(rng, 0.1, 0.5);
    prims.push_back(random_primitive(rng, offset + random_point(rng, extent), size));
  }
  return prims;
}

bool lists(const Grid& g, int64_t v, uint32_t id) {
  const uint32_t* b = g.begin(v);
  return std::find(b, b + g.count(v), id) != b + g.count(v);
}

/// Every kept root with t > 0 of the ray on p, in double.
std::vector<double> true_hits(const Primitive& p, const Vec3& o, const Vec3& d) {
  const Abg<double> abg = form_abg(load_latches<double>(d, o), load_ram<double>(p.q));
  const Roots<double> r = solve_quadratic(abg.a, abg.b, abg.g);
  std::vector<double> out;
  for (int k = 0; k < r.n; ++k) {
    const double t = k ? r.t1 : r.t0;
    if (t > 0 && p.inside_clips(o + t * d)) out.push_back(t);
  }
  return out;
}

void check_structure(const Grid& g, size_t prims) {
  ASSERT_EQ(g.start.size(), size_t(g.voxel_count()) + 1);
  EXPECT_EQ(g.start.front(), 0u);
  EXPECT_EQ(g.start.back(), g.items.size());
  for (size_t v = 0; v + 1 < g.start.size(); ++v) ASSERT_LE(g.start[v], g.start[v + 1]);
  for (uint32_t id : g.items) ASSERT_LT(id, prims);
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(g.n[a], 1);
    EXPECT_NEAR(g.cell[a] * g.n[a], g.box.extent()[a], 1e-12 * g.box.extent()[a]);
  }
}

// ---------------------------------------------------------------------------------------------

TEST(GridBuild, ConservativeForRandomRays) {
  // Every true hit point, found by brute force over all primitives, lies in a voxel that lists
  // its primitive, and the 3DDDA visits such a voxel with the hit inside its window.
  std::mt19937 rng(40);
  int checked = 0;
  for (int scene = 0; scene < 24; ++scene) {
    const double extent = std::pow(10.0, uniform(rng, -1, 2));
    const Vec3 offset = random_point(rng, scene % 3 == 0 ? 50 * extent : 0.0);
    // A third of the scenes sit far from the origin (world-space coefficients grow).
    const std::vector<Primitive> prims = random_scene(rng, 8 + int(rng() % 20), extent, offset);
    GridOptions opt;
    if (scene % 2) opt.resolution = {1 + int(rng() % 23), 1 + int(rng() % 23), 1 + int(rng() % 23)};
    const Grid g = build_grid(prims, opt);
    check_structure(g, prims.size());
    for (int ray = 0; ray < 150; ++ray) {
      // Aim at a random primitive's box, so that most rays hit something; some start inside.
      Vec3 o = offset + random_point(rng, 1.5 * extent);
      const Primitive& aim = prims[rng() % prims.size()];
      const Vec3 target = aim.bounds.lo + uniform_zyx(rng, 0, 1) * aim.bounds.extent();
      Vec3 d = length(target - o) > 0 ? normalize(target - o) : random_unit(rng);
      if (ray % 7 == 0) {  // axis-parallel, through the target
        const int axis = int(rng() % 3);
        d = Vec3{0, 0, 0};
        d[axis] = rng() % 2 ? 1.0 : -1.0;
        o = target - 2 * extent * d;
      }
      // The DDA walk, for the second check.
      std::vector<DdaState> visits;
      for (DdaState s = Dda::start(g, o, d, 0, kInf); !s.done; Dda::advance(g, o, d, kInf, s))
        visits.push_back(s);
      for (uint32_t id = 0; id < prims.size(); ++id)
        for (double t : true_hits(prims[id], o, d)) {
          const Vec3 p = o + t * d;
          // (1) Every voxel whose closed box (grown by rounding) holds the point lists it.
          int lo[3], hi[3];
          for (int a = 0; a < 3; ++a) {
            const double u = (p[a] - g.box.lo[a]) / g.cell[a];
            const double slack = 1e-9 * (1 + std::abs(u));
            lo[a] = std::clamp(int(std::floor(u - slack)), 0, g.n[a] - 1);
            hi[a] = std::clamp(int(std::floor(u + slack)), 0, g.n[a] - 1);
            ASSERT_GE(u, -1e-6) << "hit outside the grid box";
            ASSERT_LE(u, g.n[a] + 1e-6) << "hit outside the grid box";
          }
          for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
              for (int x = lo[0]; x <= hi[0]; ++x)
                ASSERT_TRUE(lists(g, g.index(x, y, z), id))
                    << "scene " << scene << " ray " << ray << " primitive " << id << " ("
                    << shape_name(prims[id].kind) << ") hit at t = " << t
                    << " not listed in voxel (" << x << ", " << y << ", " << z << ")";
          // (2) Some visited voxel holds t in its window and lists the primitive.
          bool found = false;
          for (const DdaState& s : visits)
            if (s.t_enter <= t * (1 + 1e-12) && t <= s.t_exit * (1 + 1e-12) &&
                lists(g, g.index(s.cell[0], s.cell[1], s.cell[2]), id))
              found = true;
          ASSERT_TRUE(found) << "scene " << scene << " ray " << ray << " primitive " << id << " t "
                             << t;
          ++checked;
        }
    }
  }
  EXPECT_GT(checked, 2000);
}

TEST(GridBuild, SphereIsTighterThanItsBox) {
  // A sphere is not listed in voxels entirely inside it, nor in the box corners far from its
  // surface; every voxel its surface crosses lists it. Anywhere in space, not just at the origin.
  for (const Vec3& c : {Vec3{0, 0, 0}, Vec3{10.3, -4.7, 7.1}, Vec3{-250.5, 130.25, 1000.125}}) {
    SCOPED_TRACE(::testing::Message() << "centre " << c.x << " " << c.y << " " << c.z);
    const double r = 2;
    GridOptions opt;
    opt.resolution = {16, 16, 16};
    const Grid g = build_grid({make_sphere(c, r)}, opt);
    int listed = 0, inside = 0, corner = 0, crossing = 0;
    for (int z = 0; z < 16; ++z)
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
          const Aabb b = g.voxel_box(x, y, z);
          const Vec3 nearest = glm::clamp(c, b.lo, b.hi);
          Vec3 farthest;
          for (int a = 0; a < 3; ++a)
            farthest[a] = std::abs(b.lo[a] - c[a]) > std::abs(b.hi[a] - c[a]) ? b.lo[a] : b.hi[a];
          const double dmin = length(nearest - c), dmax = length(farthest - c);
          const bool l = lists(g, g.index(x, y, z), 0);
          listed += l;
          if (dmax < r * 0.99) {
            ++inside;
            EXPECT_FALSE(l) << "voxel (" << x << ", " << y << ", " << z << ") is inside the sphere";
          } else if (dmin > r * 1.01) {
            ++corner;
            EXPECT_FALSE(l) << "voxel (" << x << ", " << y << ", " << z
                            << ") is outside the sphere";
          } else if (dmin < r * 0.999 && dmax > r * 1.001) {
            ++crossing;
            EXPECT_TRUE(l) << "voxel (" << x << ", " << y << ", " << z
                           << ") is crossed by the surface";
          }
        }
    EXPECT_GT(inside, 500);
    EXPECT_GT(corner, 500);
    EXPECT_GT(crossing, 500);
    EXPECT_LT(listed, 16 * 16 * 16 / 2);
  }
}

TEST(GridBuild, ClippedShapesSkipVoxelsOutsideTheirClips) {
  // A triangle on a diagonal plane: a voxel wholly outside one edge's half-space is skipped even
  // though the plane crosses it; a voxel the plane misses is skipped; the triangle's voxels stay.
  const Vec3 a{1, 0.5, 0.2}, b{9, 1.5, 3}, c{2, 8.5, 9.7};
  const Primitive tri = make_polygon({a, b, c});
  GridOptions opt;
  opt.resolution = {20, 20, 20};
  const Grid g = build_grid({tri}, opt);
  int outside_edge = 0, off_plane = 0, on_triangle = 0;
  std::mt19937 rng(43);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 20; ++y)
      for (int x = 0; x < 20; ++x) {
        const Aabb vb = g.voxel_box(x, y, z);
        const double margin = 0.01 * length(vb.extent());
        // Evaluate at the 8 corners: extremes of a linear function over a box.
        double plane_lo = kInf, plane_hi = -kInf, edge_min[3] = {kInf, kInf, kInf};
        for (int k = 0; k < 8; ++k) {
          const Vec3 p{k & 1 ? vb.hi.x : vb.lo.x, k & 2 ? vb.hi.y : vb.lo.y,
                       k & 4 ? vb.hi.z : vb.lo.z};
          plane_lo = std::min(plane_lo, tri.q.value(p));
          plane_hi = std::max(plane_hi, tri.q.value(p));
          for (int e = 0; e < 3; ++e)
            edge_min[e] = std::min(edge_min[e], tri.clips[size_t(e)].eval(p));
        }
        const bool l = lists(g, g.index(x, y, z), 0);
        const bool crosses_plane = plane_lo < -margin && plane_hi > margin;
        if (crosses_plane && std::max({edge_min[0], edge_min[1], edge_min[2]}) > margin) {
          ++outside_edge;
          EXPECT_FALSE(l) << "voxel (" << x << ", " << y << ", " << z << ") is outside an edge";
        }
        if (plane_lo > margin || plane_hi < -margin) {
          ++off_plane;
          EXPECT_FALSE(l) << "voxel (" << x << ", " << y << ", " << z << ") is off the plane";
        }
      }
  // Every voxel holding a point of the triangle lists it.
  for (int i = 0; i < 5000; ++i) {
    double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 p = a + u * (b - a) + v * (c - a);
    const int x = std::min(19, int((p.x - g.box.lo.x) / g.cell.x)),
              y = std::min(19, int((p.y - g.box.lo.y) / g.cell.y)),
              z = std::min(19, int((p.z - g.box.lo.z) / g.cell.z));
    if (lists(g, g.index(x, y, z), 0)) ++on_triangle;
  }
  EXPECT_EQ(on_triangle, 5000);
  EXPECT_GT(outside_edge, 50);
  EXPECT_GT(off_plane, 1000);
}

TEST(GridBuild, StructureAndOptions) {
  std::mt19937 rng(41);
  const std::vector<Primitive> prims = random_scene(rng, 30, 5);
  GridOptions opt;
  opt.resolution = {7, 3, 11};
  const Grid g = build_grid(prims, opt);
  EXPECT_EQ(g.n, (std::array<int, 3>{7, 3, 11}));
  check_structure(g, prims.size());
  // The grid box holds every primitive's bounds, strictly (surfaces on the boundary are inside).
  for (const Primitive& p : prims)
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(g.box.lo[a], p.bounds.lo[a]);
      EXPECT_GT(g.box.hi[a], p.bounds.hi[a]);
    }
  // Planes from the index agree with the voxel boxes, without drift.
  for (int i = 0; i <= 7; ++i) EXPECT_DOUBLE_EQ(g.plane(0, i), g.box.lo.x + i * g.cell.x);
  EXPECT_EQ(g.voxel_box(6, 2, 10).hi.z, g.plane(2, 11));
  EXPECT_EQ(g.index(6, 2, 10), (10 * 3 + 2) * 7 + 6);

  // Bad resolutions are rejected.
  for (std::array<int, 3> bad : {std::array<int, 3>{0, 4, 4}, std::array<int, 3>{4, -1, 4},
                                 std::array<int, 3>{2000, 2000, 2000}}) {
    GridOptions o;
    o.resolution = bad;
    EXPECT_THROW(build_grid(prims, o), std::invalid_argument);
  }
  // No primitives: a valid, empty grid.
  const Grid empty = build_grid({}, GridOptions{});
  check_structure(empty, 0);
  EXPECT_TRUE(empty.items.empty());
  EXPECT_FALSE(empty.box.empty());
}

TEST(GridBuild, FlatSceneOnABoundary) {
  // Every polygon in the plane z = 0: the grid is one voxel thick and lists them all.
  std::vector<Primitive> prims;
  for (int i = 0; i < 10; ++i)
    prims.push_back(make_polygon({{double(i), 0, 0}, {i + 1.0, 0, 0}, {i + 0.5, 1, 0}}));
  const Grid g = build_grid(prims, GridOptions{});
  EXPECT_EQ(g.n[2], 1);
  check_structure(g, prims.size());
  for (int i = 0; i < 10; ++i) {
    const Vec3 centroid{i + 0.5, 1.0 / 3, 0};
    const int x = int((centroid.x - g.box.lo.x) / g.cell.x),
              y = int((centroid.y - g.box.lo.y) / g.cell.y);
    EXPECT_TRUE(lists(g, g.index(x, y, 0), uint32_t(i)));
  }
}

// ---------------------------------------------------------------------------------------------

TEST(GridInterval, QuadricMayVanish) {
  for (const Vec3& c : {Vec3{0, 0, 0}, Vec3{10, 10, 10}, Vec3{-300, 70, 1e3}}) {
    SCOPED_TRACE(c.x);
    const Primitive s = make_sphere(c, 1);
    const auto box = [&](Vec3 lo, Vec3 hi) { return Aabb{c + lo, c + hi}; };
    EXPECT_FALSE(quadric_may_vanish(s.q, box(Vec3(-0.3), Vec3(0.3))));  // inside
    EXPECT_FALSE(quadric_may_vanish(s.q, box({0.2, 0.1, -0.2}, {0.5, 0.4, 0.1})));
    EXPECT_TRUE(quadric_may_vanish(s.q, box(Vec3(0.5), Vec3(0.7))));  // straddles
    EXPECT_TRUE(quadric_may_vanish(s.q, box({0.9, -0.1, -0.1}, {1.1, 0.1, 0.1})));
    EXPECT_FALSE(quadric_may_vanish(s.q, box(Vec3(0.7), Vec3(0.9))));  // corner, outside
    EXPECT_FALSE(quadric_may_vanish(s.q, box({1.2, 1.2, -2}, {2, 2, 2})));
    // A surface point on the box's face.
    EXPECT_TRUE(quadric_may_vanish(s.q, box({1, -0.1, -0.1}, {1.5, 0.1, 0.1})));
    EXPECT_TRUE(quadric_may_vanish(s.q, box({1, 0, 0}, {1, 0, 0})));  // a single point
  }
  // A plane through a box, and beside it.
  const Quadric plane{{0, 0, 0, 0, 0, 0, 1, 1, 1, -1}};
  EXPECT_TRUE(quadric_may_vanish(plane, Aabb{{0, 0, 0}, {1, 1, 1}}));
  EXPECT_FALSE(quadric_may_vanish(plane, Aabb{{0.5, 0.5, 0.5}, {1, 1, 1}}));
  EXPECT_TRUE(quadric_may_vanish(plane, Aabb{{1.0 / 3, 1.0 / 3, 1.0 / 3}, {1, 1, 1}}));
  // Random property: whenever a sampled point of a box has Q of both signs, the box may vanish.
  std::mt19937 rng(42);
  for (int i = 0; i < 3000; ++i) {
    Quadric q;
    for (double& x : q.c) x = uniform(rng, -1, 1);
    const Vec3 lo = random_point(rng, 3), hi = lo + uniform_zyx(rng, 0, 1);
    bool pos = false, neg = false;
    for (int k = 0; k < 27; ++k) {
      const Vec3 p{k % 3 == 0 ? lo.x : (k % 3 == 1 ? hi.x : (lo.x + hi.x) / 2),
                   k / 3 % 3 == 0 ? lo.y : (k / 3 % 3 == 1 ? hi.y : (lo.y + hi.y) / 2),
                   k / 9 == 0 ? lo.z : (k / 9 == 1 ? hi.z : (lo.z + hi.z) / 2)};
      const double v = q.value(p);
      pos |= v >= 0;
      neg |= v <= 0;
    }
    if (pos && neg) {
      ASSERT_TRUE(quadric_may_vanish(q, Aabb{lo, hi})) << i;
    }
  }
}

TEST(GridInterval, BoxTouchesHalfspace) {
  const Aabb b{{0, 0, 0}, {1, 1, 1}};
  EXPECT_TRUE(box_touches_halfspace(b, {{1, 0, 0}, -0.5}));   // x <= 0.5 cuts the box
  EXPECT_TRUE(box_touches_halfspace(b, {{1, 0, 0}, 0}));      // x <= 0 touches the face
  EXPECT_FALSE(box_touches_halfspace(b, {{1, 0, 0}, 0.01}));  // x <= −0.01 misses
  EXPECT_TRUE(box_touches_halfspace(b, {{-1, 0, 0}, 1}));     // x >= 1 touches
  EXPECT_FALSE(box_touches_halfspace(b, {{-1, 0, 0}, 1.01}));
  const Vec3 n = normalize(Vec3{1, 1, 1});
  EXPECT_TRUE(box_touches_halfspace(b, {n, 0}));  // only the corner (0,0,0)
  EXPECT_FALSE(box_touches_halfspace(b, {n, 1e-9}));
  // −n·p + d <= 0 is n·p >= d: the box reaches n·p = √3 at (1,1,1).
  EXPECT_FALSE(box_touches_halfspace(b, {-n, std::sqrt(3.0) + 1e-9}));
  EXPECT_TRUE(box_touches_halfspace(b, {-n, std::sqrt(3.0) - 1e-9}));
}

// ---------------------------------------------------------------------------------------------
// auto_resolution: the cube-root rule documented in grid.h.

int64_t total(const std::array<int, 3>& n) { return int64_t(n[0]) * n[1] * n[2]; }

TEST(GridAutoResolution, CubeRootRule) {
  GridOptions opt;
  const Aabb cube{{0, 0, 0}, {1, 1, 1}};
  for (size_t prims : {1, 10, 100, 1000, 10000, 100000}) {
    const std::array<int, 3> n = auto_resolution(cube, prims, opt);
    EXPECT_EQ(n[0], n[1]);
    EXPECT_EQ(n[1], n[2]);
    const double target = opt.voxels_per_primitive * double(prims);
    EXPECT_GE(double(total(n)), target / 2) << prims;
    EXPECT_LE(double(total(n)), target * 2) << prims;
  }
  // Voxels are near-cubes on an elongated box, and the total follows the target.
  const Aabb slab{{-2, 0, 5}, {6, 1, 7}};
  for (size_t prims : {50, 500, 5000}) {
    const std::array<int, 3> n = auto_resolution(slab, prims, opt);
    const Vec3 e = slab.extent();
    const Vec3 cell{e.x / n[0], e.y / n[1], e.z / n[2]};
    const double lo = std::min({cell.x, cell.y, cell.z}), hi = std::max({cell.x, cell.y, cell.z});
    EXPECT_LE(hi / lo, 1.5) << prims;
    const double target = opt.voxels_per_primitive * double(prims);
    EXPECT_GE(double(total(n)), target / 2) << prims;
    EXPECT_LE(double(total(n)), target * 2) << prims;
  }
  // voxels_per_primitive scales the total.
  GridOptions dense = opt;
  dense.voxels_per_primitive = 32;
  EXPECT_EQ(auto_resolution(cube, 1000, dense), (std::array<int, 3>{32, 32, 32}));
}

TEST(GridAutoResolution, ClampedToOneAndMaxAxis) {
  GridOptions opt;
  const Aabb cube{{0, 0, 0}, {1, 1, 1}};
  EXPECT_EQ(auto_resolution(cube, size_t(1) << 40, opt), (std::array<int, 3>{128, 128, 128}));
  opt.max_auto_axis = 10;
  EXPECT_EQ(auto_resolution(cube, 100000, opt), (std::array<int, 3>{10, 10, 10}));
  opt.max_auto_axis = 128;
  const std::array<int, 3> none = auto_resolution(cube, 0, opt);  // treated as one primitive
  for (int a = 0; a < 3; ++a) EXPECT_GE(none[a], 1);
  EXPECT_LE(total(none), 8);
  // A long thin box: at least one voxel across the thin axes.
  const std::array<int, 3> rod = auto_resolution(Aabb{{0, 0, 0}, {100, 0.01, 0.01}}, 10, opt);
  EXPECT_EQ(rod[1], 1);
  EXPECT_EQ(rod[2], 1);
  EXPECT_GE(rod[0], 20);
  EXPECT_LE(rod[0], 80);
}

TEST(GridAutoResolution, FlatScenesStillAimAtTheTarget) {
  // A scene with no (or almost no) thickness: one voxel across it, and the voxel budget spent on
  // the other two axes, about voxels_per_primitive per primitive.
  GridOptions opt;
  for (double thickness : {0.0, 1e-9, 1e-4, 1e-3}) {
    for (size_t prims : {100, 1000}) {
      SCOPED_TRACE(::testing::Message() << "thickness " << thickness << " primitives " << prims);
      const std::array<int, 3> n = auto_resolution(Aabb{{0, 0, 0}, {2, 1, thickness}}, prims, opt);
      EXPECT_EQ(n[2], 1);
      const double target = opt.voxels_per_primitive * double(prims);
      EXPECT_GE(double(total(n)), target / 2);
      EXPECT_LE(double(total(n)), target * 2);
      EXPECT_NEAR(double(n[0]) / n[1], 2.0, 0.2);  // square voxels in the plane
    }
  }
  // Two flat axes: a line of voxels.
  const std::array<int, 3> line = auto_resolution(Aabb{{0, 0, 0}, {1, 0, 0}}, 50, opt);
  EXPECT_EQ(line[1], 1);
  EXPECT_EQ(line[2], 1);
  EXPECT_GE(line[0], 100);
  EXPECT_LE(line[0], 128);
}

}  // namespace
}  // namespace rtm

namespace rtm {
namespace {

// A teapot in a stadium: 500 small spheres in a unit cube on a 100 x 100 floor. The plain rule
// over the whole box would give voxels far larger than the spheres; the scene rule sizes them
// by the cluster and caps the count per axis.
TEST(GridSceneResolution, FitsVoxelsToTheClusterNotTheFloor) {
  std::vector<Primitive> prims;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 500; ++i) prims.push_back(make_sphere({u(rng), u(rng), u(rng)}, 0.02));
  prims.push_back(make_polygon({{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}}));
  Aabb box;
  for (const Primitive& p : prims) box.extend(p.bounds);
  GridOptions opt;
  const std::array<int, 3> plain = auto_resolution(box, prims.size(), opt);
  const std::array<int, 3> fitted = scene_resolution(prims, box, opt);
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(fitted[a], plain[a]);
    EXPECT_LE(fitted[a], opt.max_auto_axis);
  }
  // The cluster (about 1 unit wide) spans several voxels, where the plain rule gives it one.
  const double cell_x = box.extent().x / fitted[0];
  EXPECT_LT(cell_x, 1.0);
  EXPECT_GT(box.extent().x / plain[0], 1.0);
  // A uniform cloud gets the plain rule.
  std::vector<Primitive> cloud(prims.begin(), prims.end() - 1);
  Aabb cbox;
  for (const Primitive& p : cloud) cbox.extend(p.bounds);
  const std::array<int, 3> a = auto_resolution(cbox, cloud.size(), opt),
                           b = scene_resolution(cloud, cbox, opt);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(b[k], a[k], 0.25 * a[k] + 1);
}

// The same stadium under a voxel budget and an aspect limit: the long axes' cap is the largest the
// budget allows, and the short axis coarsens with them to keep voxels within the aspect.
TEST(GridSceneResolution, BudgetAndAspectLimitShapeTheStadiumsVoxels) {
  std::vector<Primitive> prims;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 4000; ++i) prims.push_back(make_sphere({u(rng), u(rng), 2 * u(rng)}, 0.01));
  prims.push_back(make_polygon({{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}}));
  Aabb box;
  for (const Primitive& p : prims) box.extend(p.bounds);
  GridOptions capped;
  capped.max_auto_axis = 1024;
  const std::array<int, 3> free = scene_resolution(prims, box, capped);
  GridOptions opt = capped;
  opt.max_auto_cells = 2'000'000;
  opt.max_auto_aspect = 3;
  const std::array<int, 3> n = scene_resolution(prims, box, opt);
  auto cells = [](const std::array<int, 3>& r) { return double(r[0]) * r[1] * r[2]; };
  ASSERT_GT(cells(free), 2e6);  // the case under test: the budget binds
  EXPECT_LE(cells(n), 2e6);
  EXPECT_GT(cells(n), 0.8 * 2e6);  // and is spent
  EXPECT_EQ(n[0], n[1]);
  const Vec3 edge = box.extent() / Vec3(n[0], n[1], n[2]);
  EXPECT_LE(edge.x / edge.z, 3 * 1.05);  // within rounding of the limit
  EXPECT_GT(edge.x / edge.z, 3 * 0.95);  // which binds: the cluster alone would want cubes
  EXPECT_LT(n[2], free[2]);

  // Neither binds on a scene that fits: the per-axis rule's grid.
  std::vector<Primitive> cloud(prims.begin(), prims.end() - 1);
  Aabb cbox;
  for (const Primitive& p : cloud) cbox.extend(p.bounds);
  EXPECT_EQ(scene_resolution(cloud, cbox, opt), scene_resolution(cloud, cbox, capped));
  // Without a budget or an aspect limit, nothing changes: GridOptions' defaults are the machine's.
  GridOptions machine;
  EXPECT_EQ(machine.max_auto_cells, 0);
  EXPECT_EQ(machine.max_auto_aspect, 0);
}

}  // namespace
}  // namespace rtm
