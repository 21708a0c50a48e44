#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace chs {

// The audit of strands passing through each other over a step (Han's missed-collision count,
// Fig. 4.7): every vertex moves on the straight line from its start to its end position, and a
// pair of segments crosses when they have a common point at some time of the step. Written
// apart from the collision impulses (rod/strand_collisions.h) so that it checks them: long
// double arithmetic, the coplanarity cubic det(a1 - a0, b0 - a0, b1 - a0)(t) interpolated from
// four of its values, its roots isolated between the extrema and bisected, and at each root the
// segments tested for a common point in their plane by 2D orientations (not by a distance).

// Whether a = (x0[0], x0[1]) and b = (x0[2], x0[3]), their ends moving to x1[k], have a common
// point at some t in [0, 1] (touching counts, to a relative tolerance of 1e-12 of their size).
// `time`, if given, gets the first such t. Four points coplanar over the whole step (a measure-
// zero case in 3D) are tested at 257 sampled times and flagged in `coplanar`.
bool segmentsCrossDuringStep(const std::array<Eigen::Vector3d, 4>& x0,
                             const std::array<Eigen::Vector3d, 4>& x1, double* time = nullptr,
                             bool* coplanar = nullptr);

struct SegmentCrossings {
  std::size_t count = 0;                  // crossing pairs
  std::size_t candidate_pairs = 0;        // pairs whose swept boxes overlap
  std::size_t coplanar_pairs = 0;         // candidates coplanar throughout (sampled, see above)
  std::vector<std::array<int, 2>> pairs;  // the first crossing pairs (first vertices), a < b
};

// Counts the crossing pairs of segments of polylines (strands) over one step: strand k holds
// vertices [offsets[k], offsets[k + 1]) of x0 (start) and x1 (end). Segments sharing a vertex
// are not pairs. Broad phase: sweep and prune of the segments' swept boxes along their widest
// axis. Throws InputError for mismatched sizes, bad offsets or non-finite positions.
SegmentCrossings countSegmentCrossings(const std::vector<Eigen::Vector3d>& x0,
                                       const std::vector<Eigen::Vector3d>& x1,
                                       const std::vector<int>& offsets,
                                       std::size_t max_reported_pairs = 100);

}  // namespace chs
