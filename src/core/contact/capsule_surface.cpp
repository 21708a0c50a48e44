#include "cloth_hair_sim/core/contact/capsule_surface.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

CapsuleSurface::CapsuleSurface(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius)
    : a_(a), b_(b), r_(radius) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !a.allFinite() || !b.allFinite())
    throw InputError("capsule: needs finite end points and a radius > 0");
}

SurfaceProjection CapsuleSurface::project(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d axis = b_ - a_;
  const double len2 = axis.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((x - a_).dot(axis) / len2, 0.0, 1.0) : 0.0;
  const bool on_side = t > 0.0 && t < 1.0;
  const Eigen::Vector3d d = x - (a_ + t * axis);
  const double rho = d.norm();
  SurfaceProjection p;
  p.gap = rho - r_;
  // Rounding leaves a point on the axis a tiny axial offset: treat it as on the axis.
  if (rho > 1e-12 * r_) {
    p.normal = d / rho;
    // Along the side the closest point slides with x, so the normal does not turn along the
    // axis; on the end caps it turns as on a sphere.
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity() - p.normal * p.normal.transpose();
    if (on_side) h -= axis * axis.transpose() / len2;
    p.normal_gradient = h / rho;
  } else {
    // On the axis: any direction across it is a closest one; pick one, deterministically.
    const Eigen::Vector3d u =
        len2 > 0.0 ? Eigen::Vector3d(axis / std::sqrt(len2)) : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d seed =
        std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    p.normal = (seed - seed.dot(u) * u).normalized();
  }
  return p;
}

std::string CapsuleSurface::describe() const {
  std::ostringstream s;
  s << "capsule r=" << r_ << " from (" << a_.transpose() << ") to (" << b_.transpose() << ")";
  return s.str();
}

}  // namespace chs
