#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/dynamics/cloth_dynamics.h"

namespace chs {

// Force and moment a support (a gripper, a hook) applies to the cloth through the vertices it
// holds; the cloth pulls on the support with the opposite wrench.
struct HoldingWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // about the origin given
};

// Sum of the dynamics' holding forces on the vertices and their moment about origin at the
// vertices' current positions. Throws InputError for a bad index or size.
HoldingWrench holdingWrench(const ClothDynamics& dynamics, const std::vector<int>& vertices,
                            const Eigen::Vector3d& origin,
                            const std::vector<Eigen::Vector3d>& accelerations = {});

}  // namespace chs
