#include "cloth_hair_sim/core/contact/posed_surface.h"

#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

PosedSurface::PosedSurface(std::shared_ptr<const RigidSurface> local,
                           const Eigen::Isometry3d& world_from_local)
    : local_(std::move(local)), pose_(world_from_local) {
  if (!local_) throw InputError("posed surface: no surface");
  const Eigen::Matrix3d r = pose_.linear();
  if (!pose_.matrix().allFinite() || !(r.transpose() * r).isIdentity(1e-6) ||
      !(r.determinant() > 0.0))
    throw InputError("posed surface: the pose must be finite with a proper rotation");
  inverse_ = pose_.inverse(Eigen::Isometry);
}

SurfaceProjection PosedSurface::project(const Eigen::Vector3d& x) const {
  SurfaceProjection p = local_->project(inverse_ * x);
  const Eigen::Matrix3d r = pose_.linear();
  p.normal = r * p.normal;
  p.normal_gradient = r * p.normal_gradient * r.transpose();
  return p;
}

std::string PosedSurface::describe() const {
  std::ostringstream s;
  const Eigen::AngleAxisd aa(pose_.linear());
  s << local_->describe() << " (local frame), placed at [" << pose_.translation().transpose()
    << "] turned by " << aa.angle() << " rad about [" << aa.axis().transpose() << "]";
  return s.str();
}

}  // namespace chs
