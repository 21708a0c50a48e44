#include "cloth_hair_sim/core/mpm/grid_collider.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/collider_candidates.h"

namespace chs::mpm {

Eigen::Vector3d collideRelativeVelocity(const Eigen::Vector3d& v_rel, const Eigen::Vector3d& n,
                                        ColliderBoundary boundary, double friction) {
  if (boundary == ColliderBoundary::kSticky) return Eigen::Vector3d::Zero();
  const double vn = v_rel.dot(n);
  if (boundary == ColliderBoundary::kSeparating && vn >= 0.0) return v_rel;  // leaving
  const Eigen::Vector3d vt = v_rel - vn * n;
  const double vt_norm = vt.norm();
  // Coulomb: the normal velocity removed, |vn|, buys a tangential impulse of at most mu |vn|.
  const double reduced = vt_norm + friction * std::min(vn, 0.0);
  if (reduced <= 0.0 || vt_norm == 0.0) return Eigen::Vector3d::Zero();
  return vt * (reduced / vt_norm);
}

std::vector<GridCollider> makeGridColliders(const RigidSurfaces& colliders,
                                            const std::vector<SurfaceVelocity>& velocities,
                                            const std::vector<double>& frictions,
                                            ColliderBoundary boundary, double default_friction,
                                            const std::string& who) {
  if (!velocities.empty() && velocities.size() != colliders.size())
    throw InputError(who + ": " + std::to_string(velocities.size()) + " velocities for " +
                     std::to_string(colliders.size()) + " colliders");
  if (!frictions.empty() && frictions.size() != colliders.size())
    throw InputError(who + ": " + std::to_string(frictions.size()) + " frictions for " +
                     std::to_string(colliders.size()) + " colliders");
  std::vector<GridCollider> out;
  for (std::size_t c = 0; c < colliders.size(); ++c) {
    if (!colliders[c]) throw InputError(who + ": collider " + std::to_string(c) + " is null");
    GridCollider g;
    g.surface = colliders[c];
    if (!velocities.empty()) g.velocity = velocities[c];
    g.boundary = boundary;
    g.friction = frictions.empty() ? default_friction : frictions[c];
    if (!(g.friction >= 0.0 && std::isfinite(g.friction)))
      throw InputError(who + ": collider " + std::to_string(c) + " has friction " +
                       std::to_string(g.friction));
    out.push_back(g);
  }
  return out;
}

void applyGridColliders(SparseGrid& grid, const std::vector<GridCollider>& colliders,
                        std::vector<ColliderImpulse>* impulses) {
  if (impulses) impulses->resize(colliders.size());
  // Only the colliders that may hold a node of its block of 4^3 nodes: on the demo's mannequin
  // (18 colliders) every node asked every one, a third of the explicit step.
  const ColliderCandidates near(colliders, 0.0, 0.0, 4.0 * grid.spacing());
  for (int i = 0; i < grid.size(); ++i) {
    if (grid.mass[i] <= 0.0) continue;
    const Eigen::Vector3d x = grid.position(i);
    for (int k : near.near(x)) {
      const GridCollider& c = colliders[k];
      const SurfaceProjection p = c.surface->project(x);
      if (p.gap > 0.0) continue;
      const Eigen::Vector3d vc = c.velocity.at(x);
      const Eigen::Vector3d before = grid.momentum[i];
      grid.velocity[i] =
          vc + collideRelativeVelocity(grid.velocity[i] - vc, p.normal, c.boundary, c.friction);
      grid.momentum[i] = grid.mass[i] * grid.velocity[i];
      if (impulses) (*impulses)[k].add(x, grid.momentum[i] - before);
    }
  }
}

}  // namespace chs::mpm
