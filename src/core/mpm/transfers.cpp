#include "cloth_hair_sim/core/mpm/transfers.h"

#include <algorithm>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {

namespace {

// Calls f(node offset (i, j, k), node coordinate) over a particle's support.
template <int D, class F>
void forSupport(const ParticleStencil<D>& s, F&& f) {
  constexpr int n = ParticleStencil<D>::kSupport;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) f(i, j, k, Eigen::Vector3i(s.base + Eigen::Vector3i(i, j, k)));
}

template <int D>
void particleToGridImpl(const std::vector<const Particles*>& sets, SparseGrid& grid) {
  const double dx = grid.spacing();
  grid.clear();
  // Node activation is serial (the hash map), then each particle's support is looked up once.
  std::vector<std::vector<std::array<int, ParticleStencil<D>::kNodes>>> nodes(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const Particles& p = *sets[s];
    nodes[s].resize(p.size());
    for (int q = 0; q < p.size(); ++q) {
      const ParticleStencil<D> st(p.x[q], dx);
      int n = 0;
      forSupport(st, [&](int, int, int, const Eigen::Vector3i& c) {
        nodes[s][q][n++] = grid.activate(c);
      });
    }
  }
  struct Accumulator {
    std::vector<double> m;
    std::vector<Eigen::Vector3d> mv;
  };
  const int nn = grid.size();
  tbb::enumerable_thread_specific<Accumulator> local([nn] {
    return Accumulator{std::vector<double>(nn, 0.0),
                       std::vector<Eigen::Vector3d>(nn, Eigen::Vector3d::Zero())};
  });
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const Particles& p = *sets[s];
    tbb::parallel_for(0, p.size(), [&](int q) {
      Accumulator& acc = local.local();
      const ParticleStencil<D> st(p.x[q], dx);
      int n = 0;
      forSupport(st, [&](int i, int j, int k, const Eigen::Vector3i&) {
        const int node = nodes[s][q][n++];
        const double w = st.weight(i, j, k);
        acc.m[node] += w * p.mass[q];  // (3.1)
        acc.mv[node] +=
            w * p.mass[q] * (p.v[q] + p.C[q] * (grid.position(node) - p.x[q]));  // (3.2)
      });
    });
  }
  for (const Accumulator& acc : local)
    for (int i = 0; i < nn; ++i) {
      grid.mass[i] += acc.m[i];
      grid.momentum[i] += acc.mv[i];
    }
  for (int i = 0; i < nn; ++i)
    grid.velocity[i] = grid.mass[i] > 0.0 ? Eigen::Vector3d(grid.momentum[i] / grid.mass[i])
                                          : Eigen::Vector3d::Zero();
}

template <int D>
void gridToParticleImpl(const SparseGrid& grid, Particles& p, double nu, double dt) {
  const double dx = grid.spacing(), d_inv = ParticleStencil<D>::inverseInertia(dx);
  tbb::parallel_for(0, p.size(), [&](int q) {
    const ParticleStencil<D> s(p.x[q], dx);
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero(), gradv = Eigen::Matrix3d::Zero();
    forSupport(s, [&](int i, int j, int k, const Eigen::Vector3i& c) {
      const int node = grid.find(c);
      if (node < 0) return;  // outside the transferred region: zero velocity
      const double w = s.weight(i, j, k);
      const Eigen::Vector3d& vi = grid.velocity[node];
      v += w * vi;                                               // (3.13)
      B += w * vi * (grid.position(node) - p.x[q]).transpose();  // (3.14)
      gradv += vi * s.gradient(i, j, k).transpose();             // (3.17)
    });
    const Eigen::Matrix3d Ct = d_inv * B;
    p.C[q] = (1.0 - nu) * Ct + 0.5 * nu * (Ct - Ct.transpose());  // (3.15)
    p.v[q] = v;
    p.F[q] = (Eigen::Matrix3d::Identity() + dt * gradv) * p.F[q];  // (3.17)
    p.x[q] += dt * v;                                              // (3.16)
  });
}

void checkDegree(int degree) {
  if (degree != 2 && degree != 3)
    throw InputError("MPM B-spline degree must be 2 or 3, got " + std::to_string(degree));
}

}  // namespace

void particleToGrid(const Particles& particles, SparseGrid& grid, int degree) {
  particleToGrid(std::vector<const Particles*>{&particles}, grid, degree);
}

void particleToGrid(const std::vector<const Particles*>& sets, SparseGrid& grid, int degree) {
  checkDegree(degree);
  if (degree == 2)
    particleToGridImpl<2>(sets, grid);
  else
    particleToGridImpl<3>(sets, grid);
}

void updateGridVelocity(SparseGrid& grid, const Eigen::Vector3d& gravity, double dt) {
  for (int i = 0; i < grid.size(); ++i) {
    if (grid.mass[i] <= 0.0) continue;
    grid.momentum[i] += dt * (grid.force[i] + grid.mass[i] * gravity);  // (5.40)
    grid.velocity[i] = grid.momentum[i] / grid.mass[i];                 // (3.10)
  }
}

void gridToParticle(const SparseGrid& grid, Particles& particles, int degree, double rpic_damping,
                    double dt) {
  checkDegree(degree);
  if (!(rpic_damping >= 0.0 && rpic_damping <= 1.0))
    throw InputError("RPIC damping must lie in [0, 1]");
  if (degree == 2)
    gridToParticleImpl<2>(grid, particles, rpic_damping, dt);
  else
    gridToParticleImpl<3>(grid, particles, rpic_damping, dt);
}

double cflTimeStep(const Particles& particles, double dx, double cfl, double dt_max) {
  double vmax = 0.0;
  for (const auto& v : particles.v) vmax = std::max(vmax, v.norm());
  return vmax > 0.0 ? std::min(dt_max, cfl * dx / vmax) : dt_max;
}

}  // namespace chs::mpm
