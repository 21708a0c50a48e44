#pragma once
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// A rigid surface defined in its own frame and placed in the world by a rigid transform: the
// core surfaces are axis-aligned, while colliders that follow robot links turn arbitrarily.
// The gap is invariant under the transform; the normal and its gradient are rotated.
class PosedSurface : public RigidSurface {
 public:
  // Throws InputError for a null surface or a transform that is not finite and rigid.
  PosedSurface(std::shared_ptr<const RigidSurface> local,
               const Eigen::Isometry3d& world_from_local);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;
  const Eigen::Isometry3d& pose() const { return pose_; }

 private:
  std::shared_ptr<const RigidSurface> local_;
  Eigen::Isometry3d pose_, inverse_;
};

}  // namespace chs
