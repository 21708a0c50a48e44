#include "cloth_hair_sim/core/rod/parallel_transport.h"

#include <cmath>

#include <Eigen/Geometry>

namespace chs::rod {

Eigen::Vector3d parallelTransport(const Eigen::Vector3d& u, const Eigen::Vector3d& t1,
                                  const Eigen::Vector3d& t2) {
  const Eigen::Vector3d b = t1.cross(t2);
  const double c = t1.dot(t2);
  // Rotation about b / |b| by the angle between t1 and t2, written without normalising b:
  // R u = c u + b x u + (b . u) b / (1 + c).
  return c * u + b.cross(u) + (b.dot(u) / (1.0 + c)) * b;
}

double signedAngle(const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  const Eigen::Vector3d w = u.cross(v);
  return std::atan2(w.dot(n), u.dot(v));
}

Eigen::Vector3d rotateAbout(const Eigen::Vector3d& u, const Eigen::Vector3d& n, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return c * u + s * n.cross(u) + (1.0 - c) * n.dot(u) * n;
}

Eigen::Vector3d anyNormal(const Eigen::Vector3d& t) {
  const Eigen::Vector3d a =
      std::abs(t.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return t.cross(a).normalized();
}

}  // namespace chs::rod
