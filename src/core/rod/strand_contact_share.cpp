#include "cloth_hair_sim/core/rod/strand_contact_share.h"

#include <algorithm>
#include <utility>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::rod {
namespace {

template <int D>
void share(const mpm::SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
           const std::vector<double>& m, const std::vector<int>& offsets,
           const mpm::SupportNodes& support, std::vector<double>& out) {
  using Stencil = mpm::ParticleStencil<D>;
  constexpr int n = Stencil::kSupport;
  tbb::parallel_for(0, static_cast<int>(offsets.size()) - 1, [&](int k) {
    // The strand's own mass per node, as sorted (node, mass) pairs.
    std::vector<std::pair<int, double>> own;
    for (int p = offsets[k]; p < offsets[k + 1]; ++p) {
      const Stencil s(x[p], grid.spacing());
      const int* nodes = support.of(p);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int l = 0; l < n; ++l)
            own.emplace_back(nodes[(i * n + j) * n + l], s.weight(i, j, l) * m[p]);
    }
    std::sort(own.begin(), own.end());
    std::vector<std::pair<int, double>> merged;
    for (const auto& e : own)
      if (!merged.empty() && merged.back().first == e.first)
        merged.back().second += e.second;
      else
        merged.push_back(e);
    for (int p = offsets[k]; p < offsets[k + 1]; ++p) {
      const Stencil s(x[p], grid.spacing());
      const int* nodes = support.of(p);
      double mine = 0.0, all = 0.0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int l = 0; l < n; ++l) {
            const int node = nodes[(i * n + j) * n + l];
            const double w = s.weight(i, j, l);
            all += w * grid.mass[node];
            const auto it =
                std::lower_bound(merged.begin(), merged.end(), std::make_pair(node, -1.0));
            mine += w * it->second;
          }
      // Below 1e-9 (as transferToGrid drops nodes below 1e-9 of a vertex's mass) it is the
      // rounding of a strand alone, whose own masses summed in another order than the grid's.
      const double other = all > 0.0 ? std::clamp(1.0 - mine / all, 0.0, 1.0) : 0.0;
      out[p] = other > 1e-9 ? other : 0.0;
    }
  });
}

}  // namespace

std::vector<double> otherStrandsShare(const mpm::SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& positions,
                                      const std::vector<double>& masses,
                                      const std::vector<int>& offsets, int degree,
                                      const mpm::SupportNodes& support) {
  std::vector<double> out(positions.size(), 0.0);
  if (degree == 2)
    share<2>(grid, positions, masses, offsets, support, out);
  else
    share<3>(grid, positions, masses, offsets, support, out);
  return out;
}

}  // namespace chs::rod
