#include "cloth_hair_sim/core/mpm/grid_forces.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"
#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"

namespace chs::mpm {
namespace {

// Adds contribution(particle, stencil, i, j, k) to the force of every node in each particle's
// support.
template <int D, class Contribution>
void scatter(SparseGrid& grid, const std::vector<Eigen::Vector3d>& x, const SupportNodes* support,
             Contribution&& contribution) {
  const int nn = grid.size(), n = ParticleStencil<D>::kSupport;
  if (support) support->check(static_cast<int>(x.size()), D);
  tbb::enumerable_thread_specific<std::vector<Eigen::Vector3d>> local(
      [nn] { return std::vector<Eigen::Vector3d>(nn, Eigen::Vector3d::Zero()); });
  tbb::parallel_for(0, static_cast<int>(x.size()), [&](int p) {
    std::vector<Eigen::Vector3d>& f = local.local();
    const ParticleStencil<D> s(x[p], grid.spacing());
    const int* nodes = support ? support->of(p) : nullptr;
    for (int i = 0, m = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k, ++m) {
          const int node = nodes ? nodes[m] : grid.find(s.base + Eigen::Vector3i(i, j, k));
          if (node >= 0) f[node] += contribution(p, s, i, j, k);
        }
  });
  for (const auto& f : local)
    for (int i = 0; i < nn; ++i) grid.force[i] += f[i];
}

void checkSizes(std::size_t a, std::size_t b, const char* what) {
  if (a != b)
    throw InputError(std::string("grid forces: ") + std::to_string(b) + " " + what + " for " +
                     std::to_string(a) + " particles");
}

}  // namespace

void scatterPointForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
                        const std::vector<Eigen::Vector3d>& f, int degree,
                        const SupportNodes* support) {
  checkSizes(x.size(), f.size(), "forces");
  auto c = [&](int p, const auto& s, int i, int j, int k) -> Eigen::Vector3d {
    return s.weight(i, j, k) * f[p];
  };
  if (degree == 2)
    scatter<2>(grid, x, support, c);
  else
    scatter<3>(grid, x, support, c);
}

void scatterFibreForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& fibres,
                        const std::vector<Eigen::Vector3d>& t, const SupportNodes& support,
                        const MassSupportedGradientTable& gradients) {
  checkSizes(fibres.size(), t.size(), "fibre forces");
  const int nn = grid.size(), np = static_cast<int>(fibres.size());
  if (support.numParticles() != np || gradients.numParticles() != np ||
      gradients.per_particle != support.per_particle)
    throw InputError("fibre forces: " + std::to_string(np) + " fibres, supports of " +
                     std::to_string(support.numParticles()) + " and weight gradients of " +
                     std::to_string(gradients.numParticles()) + " particles");
  tbb::enumerable_thread_specific<std::vector<Eigen::Vector3d>> local(
      [nn] { return std::vector<Eigen::Vector3d>(nn, Eigen::Vector3d::Zero()); });
  tbb::parallel_for(0, np, [&](int p) {
    const Eigen::Vector3d* g = gradients.of(p);
    std::vector<Eigen::Vector3d>& f = local.local();
    const int* nodes = support.of(p);
    for (int n = 0; n < support.per_particle; ++n) f[nodes[n]] += g[n].dot(fibres[p]) * t[p];
  });
  for (const auto& f : local)
    for (int i = 0; i < nn; ++i) grid.force[i] += f[i];
}

void scatterStressForces(SparseGrid& grid, const std::vector<Eigen::Vector3d>& x,
                         const std::vector<Eigen::Matrix3d>& volume_stress, int degree,
                         const SupportNodes* support) {
  checkSizes(x.size(), volume_stress.size(), "stresses");
  auto c = [&](int p, const auto& s, int i, int j, int k) -> Eigen::Vector3d {
    return -volume_stress[p] * s.gradient(i, j, k);  // Han (3.9)
  };
  if (degree == 2)
    scatter<2>(grid, x, support, c);
  else
    scatter<3>(grid, x, support, c);
}

}  // namespace chs::mpm
