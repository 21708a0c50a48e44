#pragma once
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// The deepest point of a point set inside a set of rigid colliders.
struct DeepestPenetration {
  double depth = 0.0;  // -gap of the deepest point, >= 0; 0 when no point is inside
  int point = -1;      // index of that point, -1 when no point is inside
  int collider = -1;   // index of that collider, -1 when no point is inside
};

// Audits contact after a run: the largest depth -RigidSurface::project(x).gap over all points and
// colliders. A point exactly on a surface (gap = 0) is not inside. Throws InputError for a
// non-finite point or a null collider.
DeepestPenetration deepestPenetration(const std::vector<Eigen::Vector3d>& points,
                                      const RigidSurfaces& colliders);
// The same, asking each point only the colliders `candidates` lists for it (indices into
// colliders, e.g. mpm::ColliderCandidates' with reach 0): those that may contain it.
DeepestPenetration deepestPenetration(
    const std::vector<Eigen::Vector3d>& points, const RigidSurfaces& colliders,
    const std::function<const std::vector<int>&(const Eigen::Vector3d&)>& candidates);

}  // namespace chs
