#pragma once
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace chs::rod {

// Parallel transport of a vector u from unit tangent t1 to unit tangent t2: the rotation about
// t1 x t2 that takes t1 to t2, applied to u (Bergou et al. 2008, section 4.1: the frame
// transported along the curve, or in time from one configuration to the next, without twist).
// For t1 = t2 it is the identity; antiparallel tangents have no unique transport (the rod's
// checks refuse a segment folded back onto its neighbour).
// (Inline, as signedAngle: the rod's frame update calls them per edge in every
// line-search trial.)
inline Eigen::Vector3d parallelTransport(const Eigen::Vector3d& u, const Eigen::Vector3d& t1,
                                         const Eigen::Vector3d& t2) {
  const Eigen::Vector3d b = t1.cross(t2);
  const double c = t1.dot(t2);
  // Rotation about b / |b| by the angle between t1 and t2, written without normalising b:
  // R u = c u + b x u + (b . u) b / (1 + c).
  return c * u + b.cross(u) + (b.dot(u) / (1.0 + c)) * b;
}

// The angle [rad] in (-pi, pi] that rotates u to v about the axis n (u, v normal to n).
inline double signedAngle(const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                          const Eigen::Vector3d& n) {
  return std::atan2(u.cross(v).dot(n), u.dot(v));
}

// A unit vector normal to the unit vector t (for a first director when none is given).
Eigen::Vector3d anyNormal(const Eigen::Vector3d& t);

}  // namespace chs::rod
