#include "cloth_hair_sim/core/mpm/collider_candidates.h"

#include <cmath>

namespace chs::mpm {

namespace {

constexpr double kCellRange = 1 << 20;  // cells per axis each side of the origin

}  // namespace

ColliderCandidates::ColliderCandidates(const std::vector<GridCollider>& colliders, double dt,
                                       double reach, double cell)
    : colliders_(colliders), dt_(dt), reach_(reach), cell_(cell) {
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    lipschitz_.push_back(1.0 + dt * colliders[k].velocity.angular.norm());
    all_.push_back(static_cast<int>(k));
  }
  listing_ = colliders.size() > 2 && std::isfinite(reach) && reach >= 0.0 && cell > 0.0;
}

const std::vector<int>& ColliderCandidates::near(const Eigen::Vector3d& x) const {
  if (!listing_) return all_;
  const Eigen::Array3d c = (x / cell_).array().floor();
  if (!c.allFinite() || (c.abs() >= kCellRange - 1.0).any()) return all_;
  const std::int64_t key = (static_cast<std::int64_t>(c.x() + kCellRange) << 42) |
                           (static_cast<std::int64_t>(c.y() + kCellRange) << 21) |
                           static_cast<std::int64_t>(c.z() + kCellRange);
  const auto [it, fresh] = cells_.local().try_emplace(key);
  if (fresh) {
    const Eigen::Vector3d centre = cell_ * (c.matrix() + Eigen::Vector3d::Constant(0.5));
    const double r = 0.5 * std::sqrt(3.0) * cell_;
    for (std::size_t k = 0; k < colliders_.size(); ++k) {
      const GridCollider& g = colliders_[k];
      const double gap = g.surface->project(centre - dt_ * g.velocity.at(centre)).gap;
      if (!(gap >= reach_ + 1.01 * lipschitz_[k] * r)) it->second.push_back(static_cast<int>(k));
    }
  }
  return it->second;
}

}  // namespace chs::mpm
