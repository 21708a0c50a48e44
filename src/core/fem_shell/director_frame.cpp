#include "cloth_hair_sim/core/fem_shell/director_frame.h"

#include <cmath>

#include <Eigen/Geometry>

namespace chs {

DirectorFrame::DirectorFrame(const Eigen::Vector3d& t) {
  const Eigen::Vector3d e3 = t.normalized();
  // Seed 000 eq. (7) with E = e_z, except near E.t = -1 where a 180-degree turn about e_x is used.
  const Eigen::Quaterniond q =
      e3.z() > -0.9 ? Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), e3)
                    : Eigen::Quaterniond::FromTwoVectors(-Eigen::Vector3d::UnitZ(), e3) *
                          Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0);
  frame_ = q.toRotationMatrix();
}

void DirectorFrame::rotate(const Eigen::Vector2d& dT) {
  const Eigen::Vector3d dt = basis() * dT;
  const double angle = dt.norm();
  if (angle == 0.0) return;
  const Eigen::Vector3d axis = director().cross(dt) / angle;
  frame_ = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * frame_;
  // Re-orthonormalise against round-off drift over many increments.
  Eigen::HouseholderQR<Eigen::Matrix3d> qr(frame_);
  Eigen::Matrix3d q = qr.householderQ();
  for (int k = 0; k < 3; ++k)
    if (q.col(k).dot(frame_.col(k)) < 0.0) q.col(k) *= -1.0;
  frame_ = q;
}

}  // namespace chs
