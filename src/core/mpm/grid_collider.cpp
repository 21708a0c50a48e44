#include "cloth_hair_sim/core/mpm/grid_collider.h"

#include <algorithm>

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

void applyGridColliders(SparseGrid& grid, const std::vector<GridCollider>& colliders,
                        std::vector<ColliderImpulse>* impulses) {
  if (impulses) impulses->resize(colliders.size());
  for (int i = 0; i < grid.size(); ++i) {
    if (grid.mass[i] <= 0.0) continue;
    const Eigen::Vector3d x = grid.position(i);
    for (std::size_t k = 0; k < colliders.size(); ++k) {
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
