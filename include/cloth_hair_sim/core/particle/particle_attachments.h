#pragma once
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross

#include "cloth_hair_sim/core/particle/particle_dynamics.h"

namespace chs {

// Force and moment a support (a gripper, a hook) applies to the cloth through the vertices it
// holds; the cloth pulls on the support with the opposite wrench.
struct HoldingWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // about the origin given
};

// Constraint reaction on each held vertex: the force that keeps it on its prescribed motion,
// r_i = m_i a_i - f_i, with f the applied forces of the dynamics now (internal, weight, loads,
// damping) and a_i the vertex's prescribed acceleration (accelerations empty: held still).
// Contacts of the held vertices are not split off: a support pressing a held vertex onto an
// obstacle carries that share too. Throws InputError for a bad index or size.
std::vector<Eigen::Vector3d> holdingForces(const ParticleDynamics& dynamics,
                                           const std::vector<int>& vertices,
                                           const std::vector<Eigen::Vector3d>& accelerations = {});

// Sum of holdingForces and their moment about origin at the vertices' current positions.
HoldingWrench holdingWrench(const ParticleDynamics& dynamics, const std::vector<int>& vertices,
                            const Eigen::Vector3d& origin,
                            const std::vector<Eigen::Vector3d>& accelerations = {});

}  // namespace chs
