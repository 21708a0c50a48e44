#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/mpm_particles.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// The stages of an explicit MPM step (Han chapter 3), each a function over the particles and
// the grid; `degree` is the B-spline degree, 2 (quadratic) or 3 (cubic).

// Han (3.1)-(3.2): APIC particle-to-grid transfer of mass and momentum. Clears the grid and
// activates the nodes the particles touch. Threads accumulate into private arrays that are
// summed afterwards, so the scatter has no races.
void particleToGrid(const Particles& particles, SparseGrid& grid, int degree);
// The same for several particle sets sharing one grid (e.g. shell control points and contact
// particles). With `supports`, it is resized to the sets and records each particle's support
// nodes for the stages that follow at the same positions (grid forces, grid-to-particle).
void particleToGrid(const std::vector<const Particles*>& sets, SparseGrid& grid, int degree,
                    std::vector<SupportNodes>* supports = nullptr);

// Han (5.40) with (3.10), symplectic Euler: p_i = m_i v_i + dt (f_i + m_i g), v_i = p_i / m_i,
// with f_i = grid.force (zero unless a model scattered its internal forces there).
void updateGridVelocity(SparseGrid& grid, const Eigen::Vector3d& gravity, double dt);

// Han (3.13)-(3.17): grid-to-particle velocity and affine velocity (APIC), RPIC damping nu in
// [0, 1] (3.15), then positions (3.16) and deformation gradients (3.17).
// With `support` (recorded by particleToGrid at the particles' current positions) the nodes are
// indexed directly; without, they are looked up and nodes that are not active count as at rest.
// Without deformation_gradients F is left as it is (for particles that carry none: the velocity
// gradient is a third of the transfer's work).
void gridToParticle(const SparseGrid& grid, Particles& particles, int degree, double rpic_damping,
                    double dt, const SupportNodes* support = nullptr,
                    bool deformation_gradients = true);

// CFL-limited time step: no particle crosses more than `cfl` cells, and at most dt_max.
double cflTimeStep(const Particles& particles, double dx, double cfl, double dt_max);

}  // namespace chs::mpm
