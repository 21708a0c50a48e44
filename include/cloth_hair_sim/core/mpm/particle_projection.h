#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// Particles that carry the grid's mass: positions and masses at the step start, and their
// supports as recorded by particleToGrid at those positions. Massless particles are skipped.
struct MassCarriers {
  const std::vector<Eigen::Vector3d>* positions = nullptr;
  const std::vector<double>* masses = nullptr;
  const SupportNodes* support = nullptr;
};

// A node field u passed through the particles and back with the APIC transfers:
//   u_p = sum_i w_ip u_i,  C_p = D^-1 sum_i w_ip u_i (x_i - x_p)^T        (Han (3.13)-(3.14))
//   P(u)_i = sum_p w_ip m_p (u_p + C_p (x_i - x_p))                        (Han (3.1)-(3.2))
// into `momentum` (one entry per active node). With m_i = sum_p w_ip m_p the grid's mass from the
// same particles (particleToGrid), S u = P(u) / m is what the particles can carry of u: affine
// fields pass unchanged, and a node of almost no mass gets the velocity of the particles that give
// it that mass. S is symmetric in the mass inner product, so a force field f enters the grid
// consistently as P(f / m). Throws InputError for sizes that do not match the grid or the supports.
void projectThroughParticles(const SparseGrid& grid, const std::vector<MassCarriers>& carriers,
                             int degree, const std::vector<Eigen::Vector3d>& u,
                             std::vector<Eigen::Vector3d>& momentum);

}  // namespace chs::mpm
