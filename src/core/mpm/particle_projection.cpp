#include "cloth_hair_sim/core/mpm/particle_projection.h"

#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {
namespace {

template <int D>
void project(const SparseGrid& grid, const std::vector<MassCarriers>& carriers,
             const std::vector<Eigen::Vector3d>& u, std::vector<Eigen::Vector3d>& momentum) {
  constexpr int n = ParticleStencil<D>::kSupport;
  const double dx = grid.spacing(), d_inv = ParticleStencil<D>::inverseInertia(dx);
  const int nn = grid.size();
  // Threads scatter into private arrays summed afterwards: no races.
  tbb::enumerable_thread_specific<std::vector<Eigen::Vector3d>> local(
      [nn] { return std::vector<Eigen::Vector3d>(nn, Eigen::Vector3d::Zero()); });
  for (const MassCarriers& set : carriers) {
    const std::vector<Eigen::Vector3d>& x = *set.positions;
    const std::vector<double>& m = *set.masses;
    tbb::parallel_for(0, static_cast<int>(x.size()), [&](int q) {
      if (m[q] <= 0.0) return;
      const ParticleStencil<D> s(x[q], dx);
      const auto d = s.nodeOffsets(x[q], dx);
      const int* nodes = set.support->of(q);
      Eigen::Vector3d up = Eigen::Vector3d::Zero();
      Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
      for (int i = 0, k = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int l = 0; l < n; ++l, ++k) {
            const double w = s.weight(i, j, l);
            const Eigen::Vector3d& ui = u[nodes[k]];
            up += w * ui;
            B += w * ui * Eigen::RowVector3d(d[0][i], d[1][j], d[2][l]);
          }
      const Eigen::Matrix3d C = d_inv * B;
      std::vector<Eigen::Vector3d>& acc = local.local();
      for (int i = 0, k = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int l = 0; l < n; ++l, ++k)
            acc[nodes[k]] +=
                s.weight(i, j, l) * m[q] * (up + C * Eigen::Vector3d(d[0][i], d[1][j], d[2][l]));
    });
  }
  momentum.assign(nn, Eigen::Vector3d::Zero());
  for (const auto& acc : local)
    for (int i = 0; i < nn; ++i) momentum[i] += acc[i];
}

}  // namespace

void projectThroughParticles(const SparseGrid& grid, const std::vector<MassCarriers>& carriers,
                             int degree, const std::vector<Eigen::Vector3d>& u,
                             std::vector<Eigen::Vector3d>& momentum) {
  if (static_cast<int>(u.size()) != grid.size())
    throw InputError("particle projection: " + std::to_string(u.size()) + " node values for " +
                     std::to_string(grid.size()) + " active nodes");
  if (degree != 2 && degree != 3)
    throw InputError("particle projection: B-spline degree must be 2 or 3");
  for (const MassCarriers& set : carriers) {
    if (!set.positions || !set.masses || !set.support)
      throw InputError("particle projection: a carrier set lacks positions, masses or supports");
    if (set.positions->size() != set.masses->size())
      throw InputError("particle projection: " + std::to_string(set.masses->size()) +
                       " masses for " + std::to_string(set.positions->size()) + " particles");
    set.support->check(static_cast<int>(set.positions->size()), degree);
  }
  if (degree == 2)
    project<2>(grid, carriers, u, momentum);
  else
    project<3>(grid, carriers, u, momentum);
}

}  // namespace chs::mpm
