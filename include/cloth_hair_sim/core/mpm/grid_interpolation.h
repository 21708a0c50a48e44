#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// Interpolates a field given on the grid's nodes (one value per active node, e.g. the trial
// velocities of an implicit step) to the particles at `positions`, through their supports
// recorded by the particle-to-grid transfer: u_p = sum_i w_ip u_i as in Han (3.13), and, if
// `gradients` is given, (grad u)_p = sum_i u_i (x) grad w_ip as in (3.17). Either output may be
// null. `degree` is the B-spline degree, 2 or 3.
void interpolateNodeField(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& node_values,
                          const std::vector<Eigen::Vector3d>& positions, int degree,
                          const SupportNodes& support, std::vector<Eigen::Vector3d>* values,
                          std::vector<Eigen::Matrix3d>* gradients);

}  // namespace chs::mpm
