#pragma once
#include <string>

#include <Eigen/Core>

#include "cloth_hair_sim/core/contact/rigid_surface.h"

namespace chs {

// Solid capsule: all points within `radius` of the segment [a, b]. Limbs of a mannequin are
// capsules because their distance is closed-form and their normal is continuous everywhere,
// so cloth slides over a shoulder or an elbow without the kinks of a capped cylinder.
class CapsuleSurface : public RigidSurface {
 public:
  // Throws InputError for a non-positive radius or non-finite end points (a == b is a sphere).
  CapsuleSurface(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius);
  SurfaceProjection project(const Eigen::Vector3d& x) const override;
  std::string describe() const override;

 private:
  Eigen::Vector3d a_, b_;
  double r_;
};

}  // namespace chs
