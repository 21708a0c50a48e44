#include "cloth_hair_sim/core/particle/particle_contact.h"

namespace chs {

int touchingSurface(const RigidSurfaces& surfaces, const Eigen::Vector3d& x, double tolerance,
                    Eigen::Vector3d* normal) {
  int best = -1;
  double best_gap = tolerance;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const SurfaceProjection p = surfaces[s]->project(x);
    if (p.gap <= best_gap) {
      best_gap = p.gap;
      best = static_cast<int>(s);
      *normal = p.normal;
    }
  }
  return best;
}

Eigen::Vector3d cancelInwardComponent(const Eigen::Vector3d& normal, Eigen::Vector3d& f) {
  const double fn = f.dot(normal);
  if (fn >= 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d r = -fn * normal;
  f += r;
  return r;
}

bool projectOutOfSurfaces(const RigidSurfaces& surfaces, Eigen::Vector3d& x) {
  bool moved = false;
  for (int pass = 0; pass < 3; ++pass) {
    bool any = false;
    for (const auto& s : surfaces) {
      const SurfaceProjection p = s->project(x);
      if (p.gap < 0.0) {
        x -= p.gap * p.normal;
        any = moved = true;
      }
    }
    if (!any) break;
  }
  return moved;
}

}  // namespace chs
