#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace chs::rod {

// The geometric strand-strand collision impulses of Han section 4.2.4, applied to the vertices'
// velocities before positions move (4.13), following Bridson, Fedkiw and Anderson 2002
// ("Robust treatment of collisions, contact and friction for cloth animation") for segments:
//   broad phase  a uniform grid of cells ("pads") over the segments' boxes swept over the step
//                and grown by the thickness; a pair is reported by the one cell holding the
//                low corner of its boxes' overlap, so once (Han: pads extended by delta);
//   proximity    pairs closer than the thickness at the step's start and approaching get an
//                inelastic impulse along the closest points' normal that also undoes a share of
//                the overlap, and Coulomb friction (Bridson section 7.1), in passes until none
//                is needed or max_iterations;
//   collisions   continuous detection over the straight paths x^n + t dt v (the coplanarity
//                cubic of the four points, then the distance at its roots and extrema), an
//                inelastic impulse with friction for each colliding pair; passes (pairs found
//                in parallel, impulses Gauss-Seidel or Jacobi with Bridson's averaging, see
//                `jacobi`) repeated until no pair collides or max_iterations;
//   fail-safe    rigid impact zones (Provot 1997, Bridson section 7.4): the strands (or only
//                the vertices, whole_strand_zones) of pairs still colliding are merged into
//                zones that take the rigid velocity of their linear and angular momentum (an
//                affine map, so nothing inside a zone crosses), merged again while zones
//                collide. A zone holding a clamped vertex translates with the mean velocity of
//                its clamped vertices (exact when they move alike: a zone on a still scalp
//                stops for the step).
// Impulses are distributed to the four vertices by the closest points' barycentric weights and
// inverse masses; a vertex of inverse mass 0 (a clamp) does not move. Every impulse is an equal
// and opposite pair, so linear momentum is kept (zones also keep angular momentum).
struct StrandCollisionSettings {
  // Off by default for now: in a pile the impact zones fire in most steps and hold the pile
  // still for them, the strands' Newton solves take ~10 times longer, and a lock lifted by the
  // node's grasp read its weight 2.36e-4 N off (weight 1.28e-4 N) with them on
  // (docs/VALIDATION.md).
  bool enabled = false;
  // Contact distance between centrelines [m]; <= 0: twice the largest strand radius.
  double thickness = 0.0;
  double friction = 0.3;  // Coulomb mu between strands
  // Share of a proximity overlap (thickness - distance) undone per step by the repulsion.
  double repulsion = 0.1;
  // A pair whose centrelines come within this share of the thickness at a root of the
  // coplanarity cubic collides (a margin: the audit counts only actual crossings).
  double collision_margin = 0.01;
  // A collision's impulse leaves the contact points this share of the thickness apart along the
  // normal at the step's end (at least 2 margins).
  double collision_gap = 0.5;
  // Passes of proximity, then of collision impulses before impact zones (Han: five).
  int max_iterations = 5;
  // How a pass applies its pairs' impulses: Jacobi with Bridson's averaging as Han (each from
  // the same velocities, divided by the most pairs on one of its vertices), else Gauss-Seidel
  // (in turn, each from the velocities the previous left; both keep momentum). In a stack
  // Jacobi's averaging gives each pair a share of its impulse per pass and converges slowly.
  bool jacobi = false;
  // Impact zones take the whole strands of their colliding pairs (else only the pairs'
  // vertices, as Bridson's cloth).
  bool whole_strand_zones = true;
};

struct StrandCollisionStats {
  int segments = 0;
  int candidate_pairs = 0;     // broad phase of the first pass
  int proximity_impulses = 0;  // over the proximity passes
  int collision_passes = 0;    // Jacobi passes that found colliding pairs
  int collision_impulses = 0;  // over those passes
  int zone_passes = 0;         // impact-zone passes
  int zone_vertices = 0;       // vertices in impact zones at the end
  int full_searches = 0;       // broad-phase cell searches over all segments
  int partial_searches = 0;    // searches of the few segments that left their Verlet boxes
  bool resolved = true;        // no pair left colliding
  double seconds = 0.0;        // wall time of the stage
};

// When two moving segments collide: segment a = (x[0], x[1]) and b = (x[2], x[3]) at the step's
// start, their ends moving by d[k] over the step. Returns the earliest time t in [0, 1] at which
// the segments come within `margin` of each other at a root or extremum of the coplanarity
// cubic det(x1 - x0, x2 - x0, x3 - x0)(t) (or at a sampled time when the four points stay
// coplanar throughout), with the closest points' parameters on a and b, provided the pair does
// not end the step at least `margin` apart on the side of the normal it started on.
struct SegmentContact {
  double time = 0.0;
  double s = 0.0, u = 0.0;  // a(s) = (1 - s) x0 + s x1, b(u) = (1 - u) x2 + u x3
  // Unit, across both edges at `time` (along the separation if parallel), pointing from a to b
  // as they were at the start; start_gap: b(u) - a(s) along it at the start (>= 0).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double start_gap = 0.0;
};
std::optional<SegmentContact> segmentCollision(const std::array<Eigen::Vector3d, 4>& x,
                                               const std::array<Eigen::Vector3d, 4>& d,
                                               double margin);

class StrandCollisions {
 public:
  // Throws InputError for a bad setting.
  explicit StrandCollisions(const StrandCollisionSettings& settings = {});
  const StrandCollisionSettings& settings() const { return settings_; }

  // x: the vertices' step-start positions, strand k holding vertices [offsets[k],
  // offsets[k + 1]) joined by segments; v: their velocities, changed in place; inverse_mass:
  // 0 for a clamped vertex. thickness: the contact distance [m] (> 0). Segments sharing a
  // vertex are not tested against each other. Throws InputError for mismatched sizes or
  // offsets, a non-positive thickness or dt.
  StrandCollisionStats apply(const std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& v,
                             const std::vector<double>& inverse_mass,
                             const std::vector<int>& offsets, double thickness, double dt);

 private:
  StrandCollisionStats resolve(const std::vector<Eigen::Vector3d>& x,
                               std::vector<Eigen::Vector3d>& v,
                               const std::vector<double>& inverse_mass,
                               const std::vector<int>& offsets, double thickness, double dt);
  struct Pair {
    int a = 0, b = 0;  // first vertices of the two segments
  };
  struct Impulse {
    std::array<int, 4> vertex{};
    std::array<double, 4> weight{};  // +-barycentric: a's side negative, b's positive
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    double target = 0.0;      // wanted normal relative velocity (b's from a's) [m/s]
    double min_change = 0.0;  // change of it at least (a collision's push)
  };
  // Fills pairs_ with the segment pairs whose boxes over the step (grown by grow / 2) meet,
  // searching again (with the boxes grown by at least slack more) only for the boxes that have
  // left their last ones, or anew when many have. changed_only: only pairs with a vertex in
  // dirty_ (a collision pass tests no other).
  void candidates(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& v,
                  double grow, double dt, double slack, bool changed_only,
                  StrandCollisionStats& stats);
  // A new cell search over all boxes grown by at least slack (searched_*, the grid).
  void search(const std::vector<Eigen::AlignedBox3d>& boxes, double slack);
  // The boxes `left` (indices into segments_) searched again, grown by at least slack, against
  // the last full search's grid and the boxes searched again since; false (nothing changed)
  // when one of them spans too many of the grid's cells.
  bool searchAgain(const std::vector<Eigen::AlignedBox3d>& boxes, const std::vector<int>& left,
                   double slack);
  Eigen::Array3i cellOf(const Eigen::Vector3d& p) const;
  // Applies the impulses, with Coulomb friction: Jacobi-wise (each from the same velocities,
  // divided by its vertices' largest count) or Gauss-Seidel (in turn, each from the velocities
  // its predecessors left).
  void applyImpulses(const std::vector<Impulse>& impulses, std::vector<Eigen::Vector3d>& v,
                     const std::vector<double>& inverse_mass);
  std::vector<Impulse> collisionImpulses(const std::vector<Eigen::Vector3d>& x,
                                         const std::vector<Eigen::Vector3d>& v,
                                         const std::vector<double>& inverse_mass, double thickness,
                                         double dt) const;

  StrandCollisionSettings settings_;
  std::vector<int> segments_;  // first vertex of each segment
  std::vector<Pair> pairs_;    // the current broad phase's candidates
  // The last cell search: its segments, their boxes with the slack, the pairs those meet in,
  // and each segment's index by its first vertex.
  std::vector<int> searched_segments_;
  std::vector<Eigen::AlignedBox3d> searched_boxes_;
  std::vector<Pair> searched_pairs_;
  std::vector<char> keep_;  // scratch of candidates(): which of searched_pairs_ meet now
  // Each segment's box over the step grown by boxes_grow_ / 2, as candidates() last made it,
  // and whether that call made it again.
  std::vector<Eigen::AlignedBox3d> boxes_;
  double boxes_grow_ = 0.0;
  std::vector<char> remade_;
  std::vector<int> segment_index_;
  // The last full search's uniform grid: cell size, corner, and its entries by cell key.
  struct CellEntry {
    std::uint64_t cell = 0;
    int k = 0;  // index into segments_
  };
  double cell_size_ = 1.0;
  Eigen::Vector3d grid_corner_ = Eigen::Vector3d::Zero();
  std::vector<CellEntry> grid_;
  // Segments searched again since the full search (their entries in grid_ stale), and a flag
  // per segment.
  std::vector<int> searched_again_;
  std::vector<char> is_searched_again_;
  std::vector<int> count_;      // impulses per vertex in a pass
  std::vector<int> strand_of_;  // each vertex's strand
  std::vector<char> dirty_;     // vertices whose velocity the last pass changed
};

}  // namespace chs::rod
