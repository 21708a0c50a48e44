#pragma once
#include <vector>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"

namespace chs {

// A rigid obstacle's motion given in a scene file instead of by tf: at rest, at constant linear
// and angular velocity (the angular one about the obstacle's own origin as it moves), or through
// keyframes of pose over time, linearly interpolated (rotations by slerp) and held before the
// first and after the last. Times in s, lengths in m, angles in rad.
struct ScriptedMotion {
  enum class Kind { kStatic, kVelocity, kKeyframes };
  struct Keyframe {
    double time = 0.0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  };
  Kind kind = Kind::kStatic;
  Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
  std::vector<Keyframe> keyframes;  // strictly increasing times

  bool moves() const { return kind != Kind::kStatic; }
  // The pose at time t of an obstacle at `start` at t = 0 (keyframes ignore start).
  Eigen::Isometry3d pose(const Eigen::Isometry3d& start, double t) const;
  // The rigid velocity that carries the obstacle from its pose at t0 to its pose at t1 (one
  // substep), about the origin of the pose at t1, where the substep places it: the grid then
  // sees the obstacle sweep, not jump.
  SurfaceVelocity velocity(const Eigen::Isometry3d& start, double t0, double t1) const;
};

}  // namespace chs
