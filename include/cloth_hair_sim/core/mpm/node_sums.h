#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::mpm {

// out_i += sum_p w_ip value_p over particles at x with their supports recorded at x (B-splines of
// the given degree, 2 or 3): a particle quantity spread onto the grid with the transfer's weights
// (a first moment of mass with value_p = m_p x_p, a normal field with value_p = n_p). out is
// resized to the grid with zeros if it is smaller. Throws InputError for supports that do not
// match.
void sumOverSupports(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
                     const std::vector<Eigen::Vector3d>& value, const SupportNodes& support,
                     int degree, std::vector<Eigen::Vector3d>& out);

}  // namespace chs::mpm
