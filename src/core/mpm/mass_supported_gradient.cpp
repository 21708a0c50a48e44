#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"

#include <algorithm>
#include <string>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {
namespace {

template <int D>
void gradients(const SparseGrid& grid, const Eigen::Vector3d& x, const int* nodes,
               std::vector<Eigen::Vector3d>& g) {
  constexpr int n = ParticleStencil<D>::kSupport;
  const ParticleStencil<D> s(x, grid.spacing());
  g.resize(ParticleStencil<D>::kNodes);
  double W = 0.0;
  Eigen::Vector3d massless = Eigen::Vector3d::Zero();  // sum'' grad w_k
  bool all_carry_mass = true;
  for (int i = 0, m = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++m) {
        g[m] = s.gradient(i, j, k);
        if (grid.mass[nodes[m]] > 0.0) {
          W += s.weight(i, j, k);
        } else {
          massless += g[m];
          all_carry_mass = false;
        }
      }
  if (all_carry_mass) return;  // the common case inside the cloth: g_i = grad w_i
  for (int i = 0, m = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++m) {
        if (grid.mass[nodes[m]] > 0.0 && W > 0.0)
          g[m] += (s.weight(i, j, k) / W) * massless;
        else
          g[m].setZero();
      }
}

}  // namespace

void massSupportedGradients(const SparseGrid& grid, const Eigen::Vector3d& position, int degree,
                            const int* nodes, std::vector<Eigen::Vector3d>& g) {
  if (degree == 2)
    gradients<2>(grid, position, nodes, g);
  else if (degree == 3)
    gradients<3>(grid, position, nodes, g);
  else
    throw InputError("mass-supported gradient: B-spline degree must be 2 or 3, got " +
                     std::to_string(degree));
}

void tabulateMassSupportedGradients(const SparseGrid& grid,
                                    const std::vector<Eigen::Vector3d>& positions, int degree,
                                    const SupportNodes& support,
                                    MassSupportedGradientTable& table) {
  const int np = static_cast<int>(positions.size());
  support.check(np, degree);
  table.per_particle = support.per_particle;
  table.g.resize(static_cast<std::size_t>(np) * support.per_particle);
  tbb::parallel_for(0, np, [&](int p) {
    thread_local std::vector<Eigen::Vector3d> g;
    massSupportedGradients(grid, positions[p], degree, support.of(p), g);
    std::copy(g.begin(), g.end(), table.g.begin() + static_cast<std::ptrdiff_t>(p) * g.size());
  });
}

void interpolateMassSupportedGradient(const SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& node_values,
                                      const std::vector<Eigen::Vector3d>& positions, int degree,
                                      const SupportNodes& support,
                                      std::vector<Eigen::Matrix3d>& result) {
  MassSupportedGradientTable table;
  tabulateMassSupportedGradients(grid, positions, degree, support, table);
  interpolateMassSupportedGradient(grid, node_values, support, table, result);
}

void interpolateMassSupportedGradient(const SparseGrid& grid,
                                      const std::vector<Eigen::Vector3d>& node_values,
                                      const SupportNodes& support,
                                      const MassSupportedGradientTable& table,
                                      std::vector<Eigen::Matrix3d>& result) {
  if (static_cast<int>(node_values.size()) != grid.size())
    throw InputError("mass-supported gradient: " + std::to_string(node_values.size()) +
                     " node values for " + std::to_string(grid.size()) + " active nodes");
  if (table.per_particle != support.per_particle || table.numParticles() != support.numParticles())
    throw InputError("mass-supported gradient: a table of " + std::to_string(table.numParticles()) +
                     " particles for supports of " + std::to_string(support.numParticles()));
  result.resize(table.numParticles());
  tbb::parallel_for(0, table.numParticles(), [&](int p) {
    const int* nodes = support.of(p);
    const Eigen::Vector3d* g = table.of(p);
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
    for (int n = 0; n < support.per_particle; ++n) grad += node_values[nodes[n]] * g[n].transpose();
    result[p] = grad;
  });
}

}  // namespace chs::mpm
