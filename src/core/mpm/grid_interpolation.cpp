#include "cloth_hair_sim/core/mpm/grid_interpolation.h"

#include <string>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {
namespace {

template <int D>
void interpolate(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& u,
                 const std::vector<Eigen::Vector3d>& x, const SupportNodes& support,
                 std::vector<Eigen::Vector3d>* values, std::vector<Eigen::Matrix3d>* gradients) {
  constexpr int n = ParticleStencil<D>::kSupport;
  tbb::parallel_for(0, static_cast<int>(x.size()), [&](int p) {
    const ParticleStencil<D> s(x[p], grid.spacing());
    const int* nodes = support.of(p);
    Eigen::Vector3d value = Eigen::Vector3d::Zero();
    Eigen::Matrix3d gradient = Eigen::Matrix3d::Zero();
    for (int i = 0, m = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k, ++m) {
          const Eigen::Vector3d& ui = u[nodes[m]];
          if (values) value += s.weight(i, j, k) * ui;
          if (gradients) gradient += ui * s.gradient(i, j, k).transpose();
        }
    if (values) (*values)[p] = value;
    if (gradients) (*gradients)[p] = gradient;
  });
}

}  // namespace

void interpolateNodeField(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& node_values,
                          const std::vector<Eigen::Vector3d>& positions, int degree,
                          const SupportNodes& support, std::vector<Eigen::Vector3d>* values,
                          std::vector<Eigen::Matrix3d>* gradients) {
  if (static_cast<int>(node_values.size()) != grid.size())
    throw InputError("grid interpolation: " + std::to_string(node_values.size()) +
                     " node values for " + std::to_string(grid.size()) + " active nodes");
  if (degree != 2 && degree != 3)
    throw InputError("grid interpolation: B-spline degree must be 2 or 3");
  support.check(static_cast<int>(positions.size()), degree);
  if (values) values->resize(positions.size());
  if (gradients) gradients->resize(positions.size());
  if (degree == 2)
    interpolate<2>(grid, node_values, positions, support, values, gradients);
  else
    interpolate<3>(grid, node_values, positions, support, values, gradients);
}

}  // namespace chs::mpm
