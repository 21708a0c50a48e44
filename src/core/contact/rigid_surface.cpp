#include "cloth_hair_sim/core/contact/rigid_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {
// Projection onto a convex solid whose closest outside point is c: distance d = |x - c|,
// normal n = (x - c)/d and dn/dx = (I - n n^T - sum_k t_k t_k^T)/d, where t_k span the
// directions along which c slides with x (the face or edge directions at c).
// A surface offset by `offset` from the solid has the same normal field and gap d - offset.
SurfaceProjection fromClosestPoint(const Eigen::Vector3d& x, const Eigen::Vector3d& c,
                                   const Eigen::Matrix3d& sliding_projector, double offset = 0.0) {
  SurfaceProjection p;
  const Eigen::Vector3d d = x - c;
  const double dist = d.norm();
  p.gap = dist - offset;
  p.normal = d / dist;
  p.normal_gradient =
      (Eigen::Matrix3d::Identity() - p.normal * p.normal.transpose() - sliding_projector) / dist;
  return p;
}

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}
}  // namespace

PlaneSurface::PlaneSurface(const Eigen::Vector3d& point, const Eigen::Vector3d& normal)
    : point_(point), normal_(normal) {
  if (!(normal.norm() > 0.0) || !point.allFinite())
    throw InputError("plane: needs a finite point and a non-zero normal");
  normal_.normalize();
}

SurfaceProjection PlaneSurface::project(const Eigen::Vector3d& x) const {
  SurfaceProjection p;
  p.gap = (x - point_).dot(normal_);
  p.normal = normal_;
  return p;
}

std::string PlaneSurface::describe() const {
  return "plane through " + vec(point_);
}

BoxSurface::BoxSurface(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                       double edge_radius)
    : lo_(min_corner),
      hi_(max_corner - Eigen::Vector3d(0.0, 0.0, edge_radius)),
      radius_(edge_radius) {
  if (!min_corner.allFinite() || !max_corner.allFinite() ||
      (max_corner.array() <= min_corner.array()).any())
    throw InputError("box: max corner must exceed min corner in x, y and z");
  if (!(edge_radius >= 0.0) || (hi_.array() < lo_.array()).any())
    throw InputError("box: edge radius must be >= 0 and at most half the smallest side");
}

SurfaceProjection BoxSurface::project(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d c = x.cwiseMax(lo_).cwiseMin(hi_);
  if (c != x) {
    // Outside: the clamped axes are those where the closest point is pinned to a face.
    Eigen::Matrix3d sliding = Eigen::Matrix3d::Zero();
    int pinned = 0;
    for (int k = 0; k < 3; ++k) {
      if (c[k] == x[k])
        sliding(k, k) = 1.0;
      else
        ++pinned;
    }
    if (pinned == 1) {  // over a face: flat
      SurfaceProjection p = fromClosestPoint(x, c, sliding, radius_);
      p.normal_gradient.setZero();
      return p;
    }
    return fromClosestPoint(x, c, sliding, radius_);
  }
  // Inside the inner box: the nearest face decides.
  SurfaceProjection p;
  p.gap = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double below = lo_[k] - x[k], above = x[k] - hi_[k];  // both <= 0 inside
    if (below > p.gap) {
      p.gap = below;
      p.normal = -Eigen::Vector3d::Unit(k);
    }
    if (above > p.gap) {
      p.gap = above;
      p.normal = Eigen::Vector3d::Unit(k);
    }
  }
  p.gap -= radius_;
  return p;
}

std::string BoxSurface::describe() const {
  return "box " + vec(lo_) + " - " + vec(hi_ + Eigen::Vector3d(0, 0, radius_)) + " edge radius " +
         std::to_string(radius_);
}

CylinderSurface::CylinderSurface(const Eigen::Vector2d& center_xy, double radius, double z_bottom,
                                 double z_top, double edge_radius)
    : c_(center_xy), r_(radius), zb_(z_bottom), zt_(z_top - edge_radius), edge_(edge_radius) {
  if (!(radius > 0.0) || !(z_top > z_bottom) || !center_xy.allFinite())
    throw InputError("cylinder: needs radius > 0 and z_top > z_bottom");
  if (!(edge_radius >= 0.0) || zt_ <= zb_)
    throw InputError("cylinder: edge radius must be >= 0 and below the height");
}

SurfaceProjection CylinderSurface::project(const Eigen::Vector3d& x) const {
  const Eigen::Vector2d radial = x.head<2>() - c_;
  const double rho = radial.norm();
  const Eigen::Vector2d er = rho > 0.0 ? Eigen::Vector2d(radial / rho) : Eigen::Vector2d::UnitX();
  const double zc = std::clamp(x.z(), zb_, zt_);
  const double rc = std::min(rho, r_);
  const Eigen::Vector3d c(c_.x() + rc * er.x(), c_.y() + rc * er.y(), zc);
  if ((x - c).norm() > 0.0) {
    // Outside. Over a cap the closest point slides in the cap plane (curvature 0); beside the
    // side wall it slides vertically and around the rim (curvature 1/rho in the hoop direction).
    if (rho <= r_) {
      SurfaceProjection p;
      p.gap = (x.z() > zt_ ? x.z() - zt_ : zb_ - x.z()) - edge_;
      p.normal = Eigen::Vector3d(0.0, 0.0, x.z() > zt_ ? 1.0 : -1.0);
      return p;
    }
    Eigen::Matrix3d sliding = Eigen::Matrix3d::Zero();
    const Eigen::Vector3d hoop(-er.y(), er.x(), 0.0);
    // The rim point moves around the hoop at rate r/rho per unit tangential motion of x.
    sliding += (r_ / rho) * hoop * hoop.transpose();
    if (zc == x.z()) sliding(2, 2) = 1.0;
    return fromClosestPoint(x, c, sliding, edge_);
  }
  // Inside: nearest of top, bottom and side.
  SurfaceProjection p;
  p.gap = x.z() - zt_;
  p.normal = Eigen::Vector3d::UnitZ();
  if (zb_ - x.z() > p.gap) {
    p.gap = zb_ - x.z();
    p.normal = -Eigen::Vector3d::UnitZ();
  }
  if (rho - r_ > p.gap) {
    p.gap = rho - r_;
    p.normal = Eigen::Vector3d(er.x(), er.y(), 0.0);
  }
  p.gap -= edge_;
  return p;
}

std::string CylinderSurface::describe() const {
  std::ostringstream s;
  s << "cylinder r=" << r_ << " z=[" << zb_ << ", " << zt_ + edge_ << "] edge radius " << edge_;
  return s.str();
}

SphereSurface::SphereSurface(const Eigen::Vector3d& center, double radius)
    : c_(center), r_(radius) {
  if (!(radius > 0.0) || !center.allFinite()) throw InputError("sphere: needs radius > 0");
}

SurfaceProjection SphereSurface::project(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d d = x - c_;
  const double rho = d.norm();
  SurfaceProjection p;
  p.normal = rho > 0.0 ? Eigen::Vector3d(d / rho) : Eigen::Vector3d::UnitZ();
  p.gap = rho - r_;
  if (rho > 0.0)
    p.normal_gradient = (Eigen::Matrix3d::Identity() - p.normal * p.normal.transpose()) / rho;
  return p;
}

std::string SphereSurface::describe() const {
  std::ostringstream s;
  s << "sphere r=" << r_ << " at " << vec(c_);
  return s.str();
}

}  // namespace chs
