#pragma once
#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// The collision algorithm of seed 000 section 3.2.2 for one particle against rigid obstacles.

// Index of the surface the point touches or penetrates (gap <= tolerance), the deepest if
// several; -1 if none. normal receives that surface's outward normal.
int touchingSurface(const RigidSurfaces& surfaces, const Eigen::Vector3d& x, double tolerance,
                    Eigen::Vector3d* normal);

// Adds the repulsion that cancels the inward normal component of the resultant f (so the node
// can slide and lift off but not push in) and returns it: the contact reaction.
Eigen::Vector3d cancelInwardComponent(const Eigen::Vector3d& normal, Eigen::Vector3d& f);

// Moves x back onto the surface of every obstacle it penetrates (a few passes for corners where
// two obstacles meet). Returns true if it moved.
bool projectOutOfSurfaces(const RigidSurfaces& surfaces, Eigen::Vector3d& x);

}  // namespace chs
