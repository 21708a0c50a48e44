#include "cloth_hair_sim/core/contact/scripted_motion.h"

#include <algorithm>

namespace chs {

namespace {

Eigen::Isometry3d blend(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() =
      Eigen::Quaterniond(a.linear()).slerp(s, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  out.translation() = (1.0 - s) * a.translation() + s * b.translation();
  return out;
}

}  // namespace

Eigen::Isometry3d ScriptedMotion::pose(const Eigen::Isometry3d& start, double t) const {
  switch (kind) {
    case Kind::kStatic:
      return start;
    case Kind::kVelocity: {
      Eigen::Isometry3d out = start;
      out.translation() += t * linear;
      const double angle = angular.norm() * t;
      if (angle != 0.0)
        out.linear() = Eigen::AngleAxisd(angle, angular.normalized()) * start.linear();
      return out;
    }
    case Kind::kKeyframes:
      break;
  }
  if (keyframes.empty()) return start;
  if (t <= keyframes.front().time) return keyframes.front().pose;
  if (t >= keyframes.back().time) return keyframes.back().pose;
  const auto next = std::upper_bound(keyframes.begin(), keyframes.end(), t,
                                     [](double x, const Keyframe& k) { return x < k.time; });
  const Keyframe& a = *(next - 1);
  return blend(a.pose, next->pose, (t - a.time) / (next->time - a.time));
}

SurfaceVelocity ScriptedMotion::velocity(const Eigen::Isometry3d& start, double t0,
                                         double t1) const {
  const Eigen::Isometry3d a = pose(start, t0), b = pose(start, t1);
  SurfaceVelocity u;
  u.origin = b.translation();
  if (!(t1 > t0)) return u;
  u.linear = (b.translation() - a.translation()) / (t1 - t0);
  const Eigen::AngleAxisd turn(b.linear() * a.linear().transpose());
  u.angular = turn.angle() * turn.axis() / (t1 - t0);
  return u;
}

}  // namespace chs
