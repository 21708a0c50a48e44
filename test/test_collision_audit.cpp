// Collision audits: the exact triangle-triangle intersection count (hand-built pairs, exactness at
// the limit of double precision, a grid folded through itself with a count known by hand, random
// soups against brute force) and the deepest penetration into rigid colliders.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <CGAL/MP_Float.h>
#include <CGAL/Quotient.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/collision/penetration_depth.h"
#include "cloth_hair_sim/core/collision/triangle_intersections.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {
namespace {

// The reference for the audit: CGAL's generic geometry over exact rationals (no filters, no
// floating point), independent of the audit's filtered kernel.
using Exact = CGAL::Simple_cartesian<CGAL::Quotient<CGAL::MP_Float>>;

Exact::Point_3 exact(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

struct TriMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

TriangleIntersections audit(const TriMesh& m, bool check_neighbours = true) {
  TriangleIntersectionOptions options;
  options.check_neighbours = check_neighbours;
  return countTriangleIntersections(m.vertices, m.triangles, options);
}

// Two unconnected triangles.
TriMesh pairOf(const std::array<Eigen::Vector3d, 3>& a, const std::array<Eigen::Vector3d, 3>& b) {
  return {{a[0], a[1], a[2], b[0], b[1], b[2]}, {{0, 1, 2}, {3, 4, 5}}};
}

// n x n cells of unit size, vertex (i, j) placed at place(i, j), each cell split along its
// diagonal (i, j)-(i+1, j+1) into a lower and an upper triangle.
TriMesh grid(int n, const std::function<Eigen::Vector3d(int, int)>& place) {
  TriMesh m;
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back(place(i, j));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

// Orientation of d against the plane of (a, b, c) in plain double arithmetic, as an inexact test
// would compute it.
double naiveOrientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a);
}

TEST(TriangleIntersections, CrossingPairCountsOne) {
  const auto r = audit(pairOf({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                              {{{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}}));
  std::printf("[figure] crossing pair: count %zu, candidates %zu\n", r.count, r.candidate_pairs);
  EXPECT_EQ(r.count, 1u);
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_EQ(r.pairs[0], (std::array<int, 2>{0, 1}));
  EXPECT_EQ(r.neighbour_count, 0u);
}

TEST(TriangleIntersections, ParallelOrSeparatePairsCountZero) {
  const std::array<Eigen::Vector3d, 3> base{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  const Eigen::Vector3d up(0, 0, 0.5), aside(1.5, 0, 0);
  const auto parallel = audit(pairOf(base, {{base[0] + up, base[1] + up, base[2] + up}}));
  const auto coplanar = audit(pairOf(base, {{base[0] + aside, base[1] + aside, base[2] + aside}}));
  // Boxes overlap, triangles do not: the broad phase passes the pair on, the exact test rejects it.
  const auto skew = audit(pairOf(base, {{{0.6, 0.6, -1}, {0.6, 0.6, 1}, {1, 1, 0}}}));
  std::printf(
      "[figure] parallel %zu, coplanar apart %zu, skew past the hypotenuse %zu (%zu cand.)\n",
      parallel.count, coplanar.count, skew.count, skew.candidate_pairs);
  EXPECT_EQ(parallel.count, 0u);
  EXPECT_EQ(coplanar.count, 0u);
  EXPECT_EQ(skew.count, 0u);
  EXPECT_EQ(skew.candidate_pairs, 1u);
}

TEST(TriangleIntersections, EdgeNeighboursAreExcludedUnlessFoldedFlat) {
  // Coplanar neighbours on both sides of their shared edge 0-1: they touch along it only.
  const TriMesh flat{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, -1, 0}}, {{0, 1, 2}, {1, 0, 3}}};
  // Bent neighbours (dihedral angle 90 degrees).
  const TriMesh bent{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 1}}, {{0, 1, 2}, {1, 0, 3}}};
  // Folded flat: the second triangle lies on the same side of edge 0-1, in the same plane.
  const TriMesh folded{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0.5, 0}}, {{0, 1, 2}, {1, 0, 3}}};
  const auto f = audit(flat), b = audit(bent), fo = audit(folded), fo_off = audit(folded, false);
  std::printf("[figure] edge neighbours: flat %zu, bent %zu, folded flat %zu (unchecked %zu)\n",
              f.count, b.count, fo.count, fo_off.count);
  EXPECT_EQ(f.count, 0u);
  EXPECT_EQ(b.count, 0u);
  EXPECT_EQ(fo.count, 1u);
  EXPECT_EQ(fo.neighbour_count, 1u);
  EXPECT_EQ(fo_off.count, 0u);
  EXPECT_EQ(fo_off.candidate_pairs, 0u);
}

TEST(TriangleIntersections, VertexNeighboursCountOnlyBeyondTheSharedVertex) {
  const Eigen::Vector3d s(0, 0, 0);
  // A fan around s: three triangles meeting only at s.
  const TriMesh fan{{s, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0.5}, {0, -1, 0.5}, {1, -1, -1}},
                    {{0, 1, 2}, {0, 3, 4}, {0, 5, 1}}};
  // Cloth pushed through its neighbour at the node s: the second triangle pierces the first.
  const TriMesh pierced{{s, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1}, {0.4, 0.3, -1}},
                        {{0, 1, 2}, {0, 3, 4}}};
  // Edges from s overlapping along a line, triangles in different planes: they touch along
  // [s, (1, 0, 0)], the shorter edge.
  const TriMesh along{{s, {2, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}, {0, 3, 4}}};
  const auto f = audit(fan), p = audit(pierced), a = audit(along), p_off = audit(pierced, false);
  std::printf(
      "[figure] vertex neighbours: fan %zu, pierced %zu (unchecked %zu), along an edge %zu\n",
      f.count, p.count, p_off.count, a.count);
  EXPECT_EQ(f.count, 0u);
  EXPECT_EQ(p.count, 1u);
  EXPECT_EQ(p.neighbour_count, 1u);
  EXPECT_EQ(p_off.count, 0u);
  EXPECT_EQ(a.count, 1u);
}

// A vertex of the second triangle at the centroid of the first, exactly on its plane, or 1e-300
// off it on either side. The first triangle (a, b, -(a + b)), with a + b exact in binary, has its
// centroid at the origin exactly, and coordinates for which plain double arithmetic misjudges the
// orientation.
TEST(TriangleIntersections, ExactAtTheLimitOfDoublePrecision) {
  const Eigen::Vector3d a(0.1, 0.7, 0.3);
  const Eigen::Vector3d b(-a.x() / 2, a.y(), -2 * a.z());  // a + b is exact (Sterbenz, doubling)
  const Eigen::Vector3d c = -(a + b);
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double side = n.z() > 0 ? 1.0 : -1.0;  // moving along side * z goes towards +n
  const Eigen::Vector3d e = n + Eigen::Vector3d(0.1, 0, 0), f = n + Eigen::Vector3d(0, 0.1, 0);
  // The origin is on the plane and e, f on one side of it, decided in exact rationals.
  const auto side_of = [&](const Eigen::Vector3d& d) {
    return CGAL::orientation(exact(a), exact(b), exact(c), exact(d));
  };
  ASSERT_EQ(side_of(Eigen::Vector3d::Zero()), CGAL::COPLANAR);
  ASSERT_EQ(side_of(e), side_of(f));
  ASSERT_NE(side_of(e), CGAL::COPLANAR);

  const double tiny = 1e-300;
  const Eigen::Vector3d on(0, 0, 0), above(0, 0, side * tiny), below(0, 0, -side * tiny);
  ASSERT_EQ(side_of(above), side_of(e));
  ASSERT_EQ(side_of(below), -side_of(e));
  const auto count = [&](const Eigen::Vector3d& d) {
    return audit(pairOf({{a, b, c}}, {{d, e, f}})).count;
  };
  const std::size_t n_on = count(on), n_above = count(above), n_below = count(below);
  const double o_on = naiveOrientation(a, b, c, on), o_above = naiveOrientation(a, b, c, above),
               o_below = naiveOrientation(a, b, c, below);
  std::printf("[figure] vertex on the plane: count %zu (naive orientation %.3e, exact 0)\n", n_on,
              o_on);
  std::printf(
      "[figure] vertex 1e-300 off, away: count %zu (naive %.3e); through: count %zu "
      "(naive %.3e)\n",
      n_above, o_above, n_below, o_below);
  EXPECT_EQ(n_on, 1u);     // touching counts
  EXPECT_EQ(n_above, 0u);  // lifted off by 1e-300: apart
  EXPECT_EQ(n_below, 1u);  // pushed through by 1e-300: crossing
  // Plain doubles cannot tell the three apart (1e-300 is absorbed in d - a) and do not even find
  // the exactly coplanar vertex on the plane.
  EXPECT_EQ(o_on, o_above);
  EXPECT_EQ(o_on, o_below);
  EXPECT_NE(o_on, 0.0);
}

TEST(TriangleIntersections, FlatGridHasNone) {
  const TriMesh m = grid(20, [](int i, int j) { return Eigen::Vector3d(i, j, 0); });
  const auto r = audit(m);
  std::printf("[figure] flat grid: %zu triangles, %zu candidate pairs (neighbours), count %zu\n",
              m.triangles.size(), r.candidate_pairs, r.count);
  EXPECT_EQ(m.triangles.size(), 800u);
  EXPECT_EQ(r.count, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
}

// The sheet lies flat for 0 <= x <= 10, rises vertically to z = 0.75 over the next column, then
// runs back over itself sloping down by 1/2 per cell, crossing z = 0 at x = 8.5 (between its
// columns 12 and 13) and continuing below. Both the flat base (cells 8..9) and the fold (cells
// 12..13) meet the line x = 8.5, z = 0 in intervals [k/2, k/2 + 1/2], k = 0..39, their diagonals
// splitting every cell at mid-height. Closed intervals k and m meet iff |k - m| <= 1:
// 40 crossings + 2 x 39 contacts at a point = 118 pairs. Shifting the fold by a quarter cell in y
// interleaves the intervals: each base interval overlaps two fold intervals, the first only one,
// 1 + 2 x 39 = 79 pairs, with no contact at a point.
TriMesh foldedGrid(double shift_y) {
  return grid(20, [shift_y](int i, int j) {
    if (i <= 10) return Eigen::Vector3d(i, j, 0);
    return Eigen::Vector3d(21 - i, j + shift_y, 0.75 - 0.5 * (i - 11));
  });
}

TEST(TriangleIntersections, FoldPushedThroughTheSheetHasTheCountedCrossings) {
  const auto on_lines = audit(foldedGrid(0.0));
  const auto shifted = audit(foldedGrid(0.25));
  std::printf("[figure] folded grid: count %zu (expected 118), neighbours %zu, candidates %zu\n",
              on_lines.count, on_lines.neighbour_count, on_lines.candidate_pairs);
  std::printf("[figure] folded grid shifted by 1/4 cell: count %zu (expected 79)\n", shifted.count);
  EXPECT_EQ(on_lines.count, 118u);
  EXPECT_EQ(on_lines.neighbour_count, 0u);
  EXPECT_EQ(shifted.count, 79u);
  // Every reported pair is a base triangle (cells 8..9) and a fold triangle (cells 12..13).
  const auto column = [](int t) { return (t / 2) % 20; };
  for (const auto& p : on_lines.pairs)
    EXPECT_EQ(std::set<int>({column(p[0]), column(p[1])}), std::set<int>({8, 12}))
        << p[0] << " " << p[1];
}

// Independent reference: every pair, in exact rationals. Neighbours count when their
// intersection (computed exactly) is more than the shared vertex or edge. Pairs whose bounding
// boxes are apart are skipped first, a comparison of doubles that is exact.
std::size_t bruteForceCount(const TriMesh& m) {
  std::vector<Exact::Triangle_3> tris;
  std::vector<Eigen::AlignedBox3d> boxes;
  std::vector<bool> degenerate;
  for (const auto& t : m.triangles) {
    tris.emplace_back(exact(m.vertices[t[0]]), exact(m.vertices[t[1]]), exact(m.vertices[t[2]]));
    degenerate.push_back(tris.back().is_degenerate());
    boxes.emplace_back(m.vertices[t[0]]);
    boxes.back().extend(m.vertices[t[1]]).extend(m.vertices[t[2]]);
  }
  std::size_t count = 0;
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (std::size_t j = i + 1; j < tris.size(); ++j) {
      if (degenerate[i] || degenerate[j]) continue;
      if (!boxes[i].intersects(boxes[j])) continue;
      std::vector<int> shared;
      for (int u : m.triangles[i])
        for (int v : m.triangles[j])
          if (u == v) shared.push_back(u);
      if (shared.empty()) {
        count += CGAL::do_intersect(tris[i], tris[j]) ? 1 : 0;
        continue;
      }
      const auto x = CGAL::intersection(tris[i], tris[j]);  // holds the shared part at least
      if (shared.size() == 1) {
        const auto* p = boost::get<Exact::Point_3>(&*x);
        count += (p && *p == exact(m.vertices[shared[0]])) ? 0 : 1;
      } else {
        const auto* seg = boost::get<Exact::Segment_3>(&*x);
        const Exact::Segment_3 edge(exact(m.vertices[shared[0]]), exact(m.vertices[shared[1]]));
        count += (seg && (*seg == edge || *seg == edge.opposite())) ? 0 : 1;
      }
    }
  return count;
}

TEST(TriangleIntersections, RandomSoupMatchesBruteForce) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0), jitter(-0.04, 0.04);
  TriMesh soup;
  for (int t = 0; t < 3000; ++t) {
    const Eigen::Vector3d c(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k)
      soup.vertices.push_back(c + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
    soup.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const auto r = audit(soup);
  const std::size_t brute = bruteForceCount(soup);
  std::printf(
      "[figure] random soup of 3000 triangles: count %zu, brute force %zu, candidates %zu\n",
      r.count, brute, r.candidate_pairs);
  EXPECT_EQ(r.count, brute);
  EXPECT_GT(r.count, 0u);
}

// Triangles on a small integer lattice share vertices, lie in common planes, touch at points and
// along edges, and some are degenerate: the hard cases for the neighbour rules and the exact tests.
TEST(TriangleIntersections, LatticeSoupWithNeighboursMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> vertex(0, 63);
  TriMesh soup;
  for (int v = 0; v < 64; ++v) soup.vertices.emplace_back(v % 4, (v / 4) % 4, v / 16);
  std::set<std::array<int, 3>> used;
  while (soup.triangles.size() < 300) {
    std::array<int, 3> t{vertex(rng), vertex(rng), vertex(rng)};
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    std::array<int, 3> key = t;
    std::sort(key.begin(), key.end());
    if (used.insert(key).second) soup.triangles.push_back(t);
  }
  const auto r = audit(soup);
  const std::size_t brute = bruteForceCount(soup);
  std::printf(
      "[figure] lattice soup of 300 triangles: count %zu (neighbours %zu), brute force %zu, "
      "degenerate %zu\n",
      r.count, r.neighbour_count, brute, r.degenerate_triangles);
  EXPECT_EQ(r.count, brute);
  EXPECT_GT(r.neighbour_count, 0u);
  EXPECT_GT(r.degenerate_triangles, 0u);
}

TEST(TriangleIntersections, HundredThousandTrianglesTiming) {
  const int n = 224;  // 2 x 224 x 224 = 100352 triangles
  const TriMesh m = grid(n, [](int i, int j) {
    return Eigen::Vector3d(0.01 * i, 0.01 * j, 0.05 * std::sin(0.1 * i) * std::cos(0.13 * j));
  });
  const auto start = std::chrono::steady_clock::now();
  const auto r = audit(m);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "[figure] wavy sheet of %zu triangles: count %zu, %zu candidate pairs, %.3f s "
      "(information)\n",
      m.triangles.size(), r.count, r.candidate_pairs, seconds);
  EXPECT_EQ(r.count, 0u);
}

TEST(TriangleIntersections, DegenerateTrianglesAreSkippedAndReported) {
  const TriMesh m{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, -1, 0}, {1, 1, 0}},
                  {{0, 1, 2}, {3, 4, 0}}};  // the sliver 0-1-2 lies across the second triangle
  const auto r = audit(m);
  std::printf("[figure] degenerate: %zu skipped, count %zu\n", r.degenerate_triangles, r.count);
  EXPECT_EQ(r.degenerate_triangles, 1u);
  EXPECT_EQ(r.count, 0u);
}

TEST(TriangleIntersections, BadInputIsRejected) {
  const auto expectRejected = [](const TriMesh& m, const std::string& fragment) {
    try {
      audit(m);
      ADD_FAILURE() << "accepted, expected: " << fragment;
    } catch (const InputError& e) {
      std::printf("  rejected: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::vector<Eigen::Vector3d> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  expectRejected({v, {{0, 1, 4}}}, "vertex 4");
  expectRejected({v, {{0, 1, 1}}}, "repeats");
  expectRejected({v, {{0, 1, 2}, {2, 0, 1}}}, "same three corners");
  auto nan = v;
  nan[3].y() = std::numeric_limits<double>::quiet_NaN();
  expectRejected({nan, {{0, 1, 3}}}, "vertex 3");
}

TEST(PenetrationDepth, DeepestPointIntoSphereAndPlane) {
  const RigidSurfaces colliders{
      std::make_shared<SphereSurface>(Eigen::Vector3d(0, 0, 0), 1.0),
      std::make_shared<PlaneSurface>(Eigen::Vector3d(0, 0, -0.5), Eigen::Vector3d(0, 0, 1))};
  const std::vector<Eigen::Vector3d> points{
      {3, 0, 1}, {0, 0.6, 0}, {2, 0, -0.8}, {0, 0, 0.9}};  // outside, 0.4 in sphere, 0.3 in plane
  const double tol = 1e-12;
  const auto both = deepestPenetration(points, colliders);
  const auto plane_only = deepestPenetration({points[0], points[2]}, colliders);
  const auto none = deepestPenetration({points[0]}, colliders);
  std::printf("[figure] deepest: %.15f (point %d, collider %d), expected 0.4 +- %.0e\n", both.depth,
              both.point, both.collider, tol);
  std::printf("[figure] plane only: %.15f (point %d, collider %d), expected 0.3; none: %.1f\n",
              plane_only.depth, plane_only.point, plane_only.collider, none.depth);
  EXPECT_NEAR(both.depth, 0.4, tol);
  EXPECT_EQ(both.point, 1);
  EXPECT_EQ(both.collider, 0);
  EXPECT_NEAR(plane_only.depth, 0.3, tol);
  EXPECT_EQ(plane_only.point, 1);
  EXPECT_EQ(plane_only.collider, 1);
  EXPECT_EQ(none.depth, 0.0);
  EXPECT_EQ(none.point, -1);
  EXPECT_EQ(none.collider, -1);
}

TEST(PenetrationDepth, BadInputIsRejected) {
  EXPECT_THROW(deepestPenetration({{0, 0, 0}}, {nullptr}), InputError);
  const RigidSurfaces sphere{std::make_shared<SphereSurface>(Eigen::Vector3d(0, 0, 0), 1.0)};
  EXPECT_THROW(deepestPenetration({{0, std::nan(""), 0}}, sphere), InputError);
}

}  // namespace
}  // namespace chs
