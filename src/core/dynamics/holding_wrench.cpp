#include "cloth_hair_sim/core/dynamics/holding_wrench.h"

namespace chs {

HoldingWrench holdingWrench(const ClothDynamics& dynamics, const std::vector<int>& vertices,
                            const Eigen::Vector3d& origin,
                            const std::vector<Eigen::Vector3d>& accelerations) {
  const std::vector<Eigen::Vector3d> r = dynamics.holdingForces(vertices, accelerations);
  HoldingWrench w;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    w.force += r[k];
    w.torque += (dynamics.positions()[vertices[k]] - origin).cross(r[k]);
  }
  return w;
}

}  // namespace chs
