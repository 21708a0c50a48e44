#pragma once
#include <Eigen/Core>

namespace chs {

// Orthonormal frame of a shell node whose third column is the unit director t. The first two
// columns are the 3x2 basis Lambda-bar of seed 000 eqs. (48)-(50): director increments live in
// their span, Delta t = Lambda-bar Delta T-bar. The frame is carried along by the exponential map
// (section 2.2.3 step 4.5) instead of being rebuilt from eq. (7), whose denominator 1 + E.t
// vanishes when the director turns upside down (the moment-loaded beam rolls a full circle).
class DirectorFrame {
 public:
  DirectorFrame() = default;
  // A frame around unit director t (built once, from the reference normal).
  explicit DirectorFrame(const Eigen::Vector3d& t);

  const Eigen::Vector3d director() const { return frame_.col(2); }
  Eigen::Matrix<double, 3, 2> basis() const { return frame_.leftCols<2>(); }

  // t <- cos|dt| t + sin|dt|/|dt| dt with dt = Lambda-bar dT: a rotation of the whole frame about
  // t x dt by |dt|.
  void rotate(const Eigen::Vector2d& dT);

 private:
  Eigen::Matrix3d frame_ = Eigen::Matrix3d::Identity();
};

}  // namespace chs
