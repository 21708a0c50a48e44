#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"

namespace chs::mpm {

// How a grid node inside a collider moves relative to it (Han section 3.4, after [30]):
// sticky takes the collider's velocity; slip keeps only the tangential relative velocity;
// separating does that only while the node approaches and lets it leave freely. Slip and
// separating apply Coulomb friction with coefficient mu to the tangential part.
enum class ColliderBoundary { kSticky, kSlip, kSeparating };

struct GridCollider {
  std::shared_ptr<const RigidSurface> surface;  // signed distance and normal
  SurfaceVelocity velocity;                     // kinematic: translation and rotation
  ColliderBoundary boundary = ColliderBoundary::kSeparating;
  double friction = 0.0;  // mu
};

// A body's grid colliders from the lists ClothDynamics::setColliders / Body::setColliders take:
// velocities and frictions empty (at rest; default_friction) or one per collider. Throws
// InputError, its message starting with `who`, for lists of other lengths, a null collider or a
// friction that is negative or not finite.
std::vector<GridCollider> makeGridColliders(const RigidSurfaces& colliders,
                                            const std::vector<SurfaceVelocity>& velocities,
                                            const std::vector<double>& frictions,
                                            ColliderBoundary boundary, double default_friction,
                                            const std::string& who);

// The velocity of a node at relative velocity v_rel = v - v_collider against outward normal n,
// in the collider's frame: the projection and Coulomb return mapping (|v_t| reduced by
// mu |v_n|, stopped when that exceeds it).
Eigen::Vector3d collideRelativeVelocity(const Eigen::Vector3d& v_rel, const Eigen::Vector3d& n,
                                        ColliderBoundary boundary, double friction);

// Momentum a collider gave a body (sum of m dv over the nodes or particles it acted on) and its
// moment about the world origin (sum of x x m dv); the collider takes the opposite.
struct ColliderImpulse {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
  void add(const Eigen::Vector3d& x, const Eigen::Vector3d& momentum_change) {
    linear += momentum_change;
    angular += x.cross(momentum_change);
  }
};

// Applies every collider to every grid node with mass whose position lies inside it (signed
// distance <= 0), after the grid velocity update and before grid-to-particle. With `impulses`
// (one per collider) the momentum each collider gives the nodes is added to it.
void applyGridColliders(SparseGrid& grid, const std::vector<GridCollider>& colliders,
                        std::vector<ColliderImpulse>* impulses = nullptr);

}  // namespace chs::mpm
