#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// Internal forces onto the grid (Han section 5.5.2), accumulated into grid.force = -dPsi/dx_i.
// The nodes must be active (particle-to-grid from the same positions activates them); `degree`
// is the B-spline degree, 2 or 3. With `support` (recorded by that particle-to-grid transfer)
// the nodes are indexed directly instead of looked up. Threads sum into private arrays: no races.

// Han (5.48): forces f_p on points whose motion is interpolated from the grid, (5.45)
// x_p = sum_i x_i w_ip, reach node i as w_ip f_p (the subdivision control points).
void scatterPointForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& positions,
                        const std::vector<Eigen::Vector3d>& forces, int degree,
                        const SupportNodes* support = nullptr);

// Han (5.49), second term: a material fibre a^tr = (sum_i x_i (x) g_ip) a^n (5.44) that the
// grid motion stretches. With t_p = -V_p dchi/da (the force conjugate to the fibre), node i
// receives (g_ip . a^n_p) t_p, with g the weight gradients restricted to the nodes that carry
// mass (mass_supported_gradient.h): the fibres' particles carry none, and a force on a massless
// node would be lost. `gradients` holds the particles' g_ip (tabulateMassSupportedGradients).
void scatterFibreForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& fibres,
                        const std::vector<Eigen::Vector3d>& fibre_forces,
                        const SupportNodes& support, const MassSupportedGradientTable& gradients);

// Han (3.9) for a continuum discretised by particles (type (i)): with V_p^0 the initial volume and
// P(F_p) the first Piola-Kirchhoff stress, -dPsi/dx_i = -sum_p V_p^0 P(F_p) F_p^T grad w_ip.
// The material enters only through volume_stress[p] = V_p^0 P(F_p) F_p^T (the volume-weighted
// Kirchhoff stress), so any constitutive model can share the scatter.
void scatterStressForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& positions,
                         const std::vector<Eigen::Matrix3d>& volume_stress, int degree,
                         const SupportNodes* support = nullptr);

}  // namespace chs::mpm
