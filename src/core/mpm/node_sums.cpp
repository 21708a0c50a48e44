#include "cloth_hair_sim/core/mpm/node_sums.h"

#include <string>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {

namespace {

template <int Degree>
void sum(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
         const std::vector<Eigen::Vector3d>& value, const SupportNodes& support,
         std::vector<Eigen::Vector3d>& out) {
  using Stencil = ParticleStencil<Degree>;
  constexpr int n = Stencil::kSupport;
  for (std::size_t p = 0; p < x.size(); ++p) {
    const Stencil s(x[p], grid.spacing());
    const int* nodes = support.of(static_cast<int>(p));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) out[nodes[(i * n + j) * n + k]] += s.weight(i, j, k) * value[p];
  }
}

}  // namespace

void sumOverSupports(const SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
                     const std::vector<Eigen::Vector3d>& value, const SupportNodes& support,
                     int degree, std::vector<Eigen::Vector3d>& out) {
  if (value.size() != x.size())
    throw InputError("sumOverSupports: " + std::to_string(value.size()) + " values for " +
                     std::to_string(x.size()) + " particles");
  support.check(static_cast<int>(x.size()), degree);
  if (static_cast<int>(out.size()) < grid.size()) out.resize(grid.size(), Eigen::Vector3d::Zero());
  if (degree == 2)
    sum<2>(grid, x, value, support, out);
  else
    sum<3>(grid, x, value, support, out);
}

}  // namespace chs::mpm
