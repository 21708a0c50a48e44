#include "cloth_hair_sim/core/rod/parallel_transport.h"

#include <Eigen/Geometry>

namespace chs::rod {

Eigen::Vector3d anyNormal(const Eigen::Vector3d& t) {
  const Eigen::Vector3d a =
      std::abs(t.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return t.cross(a).normalized();
}

}  // namespace chs::rod
