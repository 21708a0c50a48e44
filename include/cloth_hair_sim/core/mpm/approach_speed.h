#pragma once
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/grid_collider.h"

namespace chs::mpm {

// The particles of one body for the step bound below: positions and velocities now. self: the
// body's own field carries forces between its particles (a shell's contact with itself, the hair
// continuum), so its particles' approach on each other counts too, not only on other groups'.
struct MotionGroup {
  std::vector<Eigen::Vector3d> x, v;
  bool self = false;
  // With self, where the field carries forces only between layers (a shell's fibres with
  // contact_between_layers_only): whether particles p and q, `distance` apart now, lie on one
  // layer. Such a pair is kept apart by the body's elasticity, not by the grid, so only the speed
  // at which it closes in counts, not its whole relative speed: a lone sheet turning or sliding
  // past itself steps at the rate its obstacles and its other layers ask for. Unset: every
  // pair's relative speed counts.
  std::function<bool(int p, int q, double distance)> one_layer;
};

// The speed at which things that may meet on the grid within a step close on each other: the CFL
// condition's speed when the grid is where things meet (the obstacles' conditions, contact
// between and within bodies) and the elasticity is Lagrangian (Han sections 4.2 and 6.1.1). A
// step must keep two things that may meet from closing by more than a fraction of dx, or they
// cross before any node sees both. A field that moves as a whole carries no such risk: hair
// swinging with the head it grows on, a garment carried by the arm it lies on; the APIC transfers
// are exact for an affine velocity (Jiang et al. 2015), and a rigid motion keeps every distance.
// So this takes, rather than the fastest particle's speed:
//  - a particle's speed relative to an obstacle whose surface it may reach within the longest
//    step (its signed distance below `support` plus what both move in that step);
//  - two particles' relative speed where they may meet within the longest step: particles of
//    different groups, or of one group with `self`. Particles are binned in cells that hold every
//    such pair in neighbouring cells (`support` plus twice the fastest particle's travel), and the
//    bound is the diagonal of the velocities' bounding box over two neighbouring cells (at least
//    the largest relative speed there, at most sqrt 3 times it). Within a group with `one_layer`,
//    where that box could raise the bound, its pairs count one by one instead, those that come
//    within `support` of each other in the longest step, each moving on at its velocity: on two
//    layers by their relative speed, on one by the speed at which they close in.
// support: the distance at which two particles' kernels overlap ((degree + 1) dx). Zero when
// nothing approaches anything.
double approachSpeed(const std::vector<MotionGroup>& groups,
                     const std::vector<GridCollider>& colliders, double support,
                     double longest_step);

// The longest step up to longest_step in which nothing closes on what it may meet by more than
// `travel` (cfl dx): min(longest_step, travel / approachSpeed(..., longest_step)), lengthened
// where the speed over the shorter step's reach (smaller cells, fewer obstacles in reach) allows.
double motionTimeStep(const std::vector<MotionGroup>& groups,
                      const std::vector<GridCollider>& colliders, double support, double travel,
                      double longest_step);

}  // namespace chs::mpm
