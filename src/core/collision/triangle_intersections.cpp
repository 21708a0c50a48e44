// Exact triangle-triangle intersection audit. The only CGAL translation unit of the audit: the
// exact-predicates kernel decides every orientation exactly (interval filter, exact fallback), so
// the count does not depend on a tolerance.
#include "cloth_hair_sim/core/collision/triangle_intersections.h"

#include <algorithm>
#include <cstdint>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;

void checkInput(const std::vector<Eigen::Vector3d>& vertices,
                const std::vector<std::array<int, 3>>& triangles) {
  for (std::size_t v = 0; v < vertices.size(); ++v)
    if (!vertices[v].allFinite())
      throw InputError("triangle intersections: vertex " + std::to_string(v) +
                       " has a non-finite coordinate");
  const int n = static_cast<int>(vertices.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& c = triangles[t];
    for (int k = 0; k < 3; ++k)
      if (c[k] < 0 || c[k] >= n)
        throw InputError("triangle intersections: triangle " + std::to_string(t) +
                         " names vertex " + std::to_string(c[k]) + ", outside 0.." +
                         std::to_string(n - 1));
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0])
      throw InputError("triangle intersections: triangle " + std::to_string(t) +
                       " repeats vertex index");
  }
}

// Corners of triangle i reordered so that the corners shared with triangle j come first, in
// matching order on both; returns how many are shared.
int alignSharedCorners(std::array<int, 3>& a, std::array<int, 3>& b) {
  int shared = 0;
  for (int p = 0; p < 3; ++p)
    for (int q = shared; q < 3; ++q)
      if (a[p] == b[q]) {
        std::swap(a[shared], a[p]);
        std::swap(b[shared], b[q]);
        ++shared;
        break;
      }
  return shared;
}

// Triangles (s, a, b) and (s, c, d) sharing corner s. Their intersection is convex and contains
// s; if it holds another point it has a vertex q != s, and q lies on an edge of one triangle inside
// the other. On a far edge (a b or c d, which miss s) a segment test finds it. On an edge s x the
// part inside the other triangle is a segment [s, t]: t = x puts x, an end of a far edge, inside;
// t on the other far edge is found from there; t on an edge s y makes s x and s y overlap, and the
// shorter one's far end then lies on the longer one. So two segment tests decide the pair.
bool overlapBeyondSharedVertex(const Point& s, const Point& a, const Point& b, const Point& c,
                               const Point& d) {
  return CGAL::do_intersect(Segment(a, b), Triangle(s, c, d)) ||
         CGAL::do_intersect(Segment(c, d), Triangle(s, a, b));
}

// Triangles (s, t, a) and (s, t, b) sharing edge s t: off a common plane they meet only along
// s t; in one plane they overlap iff a and b lie on the same side of s t (folded flat).
bool overlapBeyondSharedEdge(const Point& s, const Point& t, const Point& a, const Point& b) {
  return CGAL::coplanar(s, t, a, b) && CGAL::coplanar_orientation(s, t, a, b) == CGAL::POSITIVE;
}

// 0: disjoint, 1: intersecting non-neighbours, 2: neighbours overlapping beyond what they share.
std::uint8_t pairVerdict(const std::vector<Point>& points, std::array<int, 3> a,
                         std::array<int, 3> b) {
  const int shared = alignSharedCorners(a, b);
  const auto P = [&](int v) -> const Point& { return points[v]; };
  if (shared == 0)
    return CGAL::do_intersect(Triangle(P(a[0]), P(a[1]), P(a[2])),
                              Triangle(P(b[0]), P(b[1]), P(b[2])))
               ? 1
               : 0;
  if (shared == 1)
    return overlapBeyondSharedVertex(P(a[0]), P(a[1]), P(a[2]), P(b[1]), P(b[2])) ? 2 : 0;
  return overlapBeyondSharedEdge(P(a[0]), P(a[1]), P(a[2]), P(b[2])) ? 2 : 0;
}

}  // namespace

TriangleIntersections countTriangleIntersections(const std::vector<Eigen::Vector3d>& vertices,
                                                 const std::vector<std::array<int, 3>>& triangles,
                                                 const TriangleIntersectionOptions& options) {
  checkInput(vertices, triangles);
  TriangleIntersections result;

  std::vector<Point> points;
  points.reserve(vertices.size());
  for (const auto& v : vertices) points.emplace_back(v.x(), v.y(), v.z());

  // Broad phase: closed bounding boxes of the double coordinates are exact, so no pair that
  // touches can be missed.
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Point& p = points[triangles[t][0]];
    const Point& q = points[triangles[t][1]];
    const Point& r = points[triangles[t][2]];
    if (CGAL::collinear(p, q, r)) {
      ++result.degenerate_triangles;
      continue;
    }
    boxes.emplace_back(p.bbox() + q.bbox() + r.bbox(), static_cast<int>(t));
  }
  std::vector<std::array<int, 2>> candidates;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    std::array<int, 2> pair{std::min(a.info(), b.info()), std::max(a.info(), b.info())};
    std::array<int, 3> ca = triangles[pair[0]], cb = triangles[pair[1]];
    const int shared = alignSharedCorners(ca, cb);
    if (shared == 3)
      throw InputError("triangle intersections: triangles " + std::to_string(pair[0]) + " and " +
                       std::to_string(pair[1]) + " have the same three corners");
    if (shared == 0 || options.check_neighbours) candidates.push_back(pair);
  });
  result.candidate_pairs = candidates.size();

  // Narrow phase: independent exact tests, one verdict per candidate.
  std::vector<std::uint8_t> verdict(candidates.size(), 0);  // 1 intersects, 2 neighbours overlap
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k)
                        verdict[k] = pairVerdict(points, triangles[candidates[k][0]],
                                                 triangles[candidates[k][1]]);
                    });

  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (verdict[k] == 0) continue;
    ++result.count;
    if (verdict[k] == 2) ++result.neighbour_count;
    result.pairs.push_back(candidates[k]);
  }
  std::sort(result.pairs.begin(), result.pairs.end());
  if (result.pairs.size() > options.max_reported_pairs)
    result.pairs.resize(options.max_reported_pairs);
  return result;
}

}  // namespace chs
