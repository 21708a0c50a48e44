#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/mpm/support_nodes.h"

namespace chs::rod {

// For each vertex, the share of the grid mass around it that other strands bring:
// 1 - sum_i w_ip m_i^own / sum_i w_ip m_i, with m_i^own the node's mass from the vertex's own
// strand. 0 for a strand alone (the grid then holds nothing but the strand itself; shares below
// 1e-9 are the rounding of its own masses summed in another order, and count as 0), towards 1
// inside a dense bulk of hair. Strand k's vertices are offsets[k] .. offsets[k + 1] - 1 of
// `positions` and `masses`, transferred to `grid` with `support` (mpm::particleToGrid).
std::vector<double> otherStrandsShare(const mpm::SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& positions,
                                      const std::vector<double>& masses,
                                      const std::vector<int>& offsets, int degree,
                                      const mpm::SupportNodes& support);

}  // namespace chs::rod
