#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace chs {

// Which pairs of mesh neighbours (triangles sharing corner indices) the audit examines.
struct TriangleIntersectionOptions {
  // Neighbours touch by construction, so a neighbour pair counts only when it overlaps beyond what
  // it shares: a pair sharing one vertex when the triangles have any other common point (cloth
  // folded through its neighbour at a node), a pair sharing an edge only when both lie in one
  // plane on the same side of that edge (folded flat onto each other). false: all neighbour pairs
  // are skipped.
  bool check_neighbours = true;
  std::size_t max_reported_pairs = 1000;  // length cap of TriangleIntersections::pairs
};

// Result of the exact triangle-triangle intersection audit of a triangle mesh.
struct TriangleIntersections {
  // Pairs of closed triangles with a common point (touching counts), neighbours as in
  // TriangleIntersectionOptions.
  std::size_t count = 0;
  std::size_t neighbour_count = 0;  // of count, the neighbour pairs (share one vertex or an edge)
  // The intersecting pairs {i, j}, i < j, in ascending order, the first max_reported_pairs of them.
  std::vector<std::array<int, 2>> pairs;
  // Zero-area triangles (three collinear corners, decided exactly) have no plane and are left out
  // of the audit; a caller who needs every triangle checked asserts this is 0.
  std::size_t degenerate_triangles = 0;
  std::size_t candidate_pairs = 0;  // pairs whose bounding boxes overlap (broad phase)
};

// Counts the intersecting pairs of triangles of a mesh with exact predicates (CGAL's
// exact-predicates kernel), with a box-intersection broad phase (CGAL::box_self_intersection_d,
// O(n log^3 n + k) at worst for k candidate pairs) and a parallel narrow phase. The verdict of
// every pair is exact for the given double coordinates: a vertex exactly on another triangle
// counts, one 1e-300 off it does not. Neighbours are recognised by shared corner indices only, so
// the mesh must be welded: two copies of a vertex at one position (an unwelded seam) make their
// triangles touch and count. Throws InputError for non-finite coordinates, corner indices out of
// range, and a triangle repeating a corner index or the three corners of another (non-degenerate)
// triangle.
TriangleIntersections countTriangleIntersections(const std::vector<Eigen::Vector3d>& vertices,
                                                 const std::vector<std::array<int, 3>>& triangles,
                                                 const TriangleIntersectionOptions& options = {});

}  // namespace chs
