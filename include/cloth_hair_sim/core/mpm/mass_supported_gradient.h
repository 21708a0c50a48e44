#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// Weight gradients of a massless particle's support restricted to the nodes that carry mass
// (grid.mass > 0). A massless particle (the shell's contact particles) can reach nodes that no
// mass-carrying particle does; those stay at rest, so a fibre reading their zero velocity sees
// strain in a rigid motion, and a force scattered to them is dropped by the grid update. The
// massless nodes are instead given the particle's mean velocity over the nodes with mass,
// u_bar = sum' w_i u_i / W with W = sum' w_i (sum' over nodes with mass), so
//   sum_i u_i (x) grad w_i  ->  sum' u_i (x) g_i,   g_i = grad w_i + (w_i / W) sum'' grad w_k
// (sum'' over the massless nodes). The g_i sum to zero (a uniform velocity is no strain, and
// forces (g_i . a) t conserve momentum); with every node carrying mass g_i = grad w_i.
// `gradients` receives one g per support node (zero for massless nodes; all zero if no node
// of the support carries mass). `nodes` is the particle's support as recorded by particleToGrid.
void massSupportedGradients(const SparseGrid& grid, const Eigen::Vector3d& position, int degree,
                            const int* nodes, std::vector<Eigen::Vector3d>& gradients);

// The g_ip of every particle of a set, per_particle per particle in its support's node order.
// They depend only on the positions and the grid's masses, which hold still from the transfer to
// the grid to the transfer back: an implicit contact solve evaluates its forces 5-15 times a
// step with one table.
struct MassSupportedGradientTable {
  int per_particle = 0;
  std::vector<Eigen::Vector3d> g;
  const Eigen::Vector3d* of(int particle) const { return g.data() + per_particle * particle; }
  int numParticles() const {
    return per_particle > 0 ? static_cast<int>(g.size()) / per_particle : 0;
  }
};
void tabulateMassSupportedGradients(const SparseGrid& grid,
                                    const std::vector<Eigen::Vector3d>& positions, int degree,
                                    const SupportNodes& support, MassSupportedGradientTable& table);

// (grad u)_p = sum' u_i (x) g_ip for the particles at `positions` (e.g. the velocity gradient
// that moves the contact fibres, Han (5.44)), one matrix per particle.
void interpolateMassSupportedGradient(const SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& node_values,
                                      const std::vector<Eigen::Vector3d>& positions, int degree,
                                      const SupportNodes& support,
                                      std::vector<Eigen::Matrix3d>& gradients);
// The same from a table of the particles' g_ip.
void interpolateMassSupportedGradient(const SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& node_values,
                                      const SupportNodes& support,
                                      const MassSupportedGradientTable& table,
                                      std::vector<Eigen::Matrix3d>& gradients);

}  // namespace chs::mpm
