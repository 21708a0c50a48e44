#pragma once
#include <Eigen/Core>

namespace chs::rod {

// Parallel transport of a vector u from unit tangent t1 to unit tangent t2: the rotation about
// t1 x t2 that takes t1 to t2, applied to u (Bergou et al. 2008, section 4.1: the frame
// transported along the curve, or in time from one configuration to the next, without twist).
// For t1 = t2 it is the identity; antiparallel tangents have no unique transport (the rod's
// checks refuse a segment folded back onto its neighbour).
Eigen::Vector3d parallelTransport(const Eigen::Vector3d& u, const Eigen::Vector3d& t1,
                                  const Eigen::Vector3d& t2);

// The angle [rad] in (-pi, pi] that rotates u to v about the axis n (u, v normal to n).
double signedAngle(const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& n);

// u rotated by angle about the unit axis n (Rodrigues' formula).
Eigen::Vector3d rotateAbout(const Eigen::Vector3d& u, const Eigen::Vector3d& n, double angle);

// A unit vector normal to the unit vector t (for a first director when none is given).
Eigen::Vector3d anyNormal(const Eigen::Vector3d& t);

}  // namespace chs::rod
