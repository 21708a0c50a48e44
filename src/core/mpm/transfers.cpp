#include "cloth_hair_sim/core/mpm/transfers.h"

#include <algorithm>
#include <array>
#include <string>

#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/common/fixed_chunks.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"

namespace chs::mpm {

namespace {

// Calls f(i, j, k, n) over a particle's support: node offset (i, j, k), n its position in the
// support's node list (SupportNodes order).
template <int D, class F>
void forSupport(F&& f) {
  constexpr int n = ParticleStencil<D>::kSupport;
  for (int i = 0, node = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++node) f(i, j, k, node);
}

// Activates every particle's support (serially: the hash is not thread safe) and records the
// node indices. Consecutive particles in one cell (neighbours on the surface) share a support,
// which is then copied instead of looked up.
template <int D>
void activateSupports(const std::vector<const Particles*>& sets, SparseGrid& grid,
                      std::vector<SupportNodes>& supports) {
  constexpr int kNodes = ParticleStencil<D>::kNodes;
  supports.resize(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const Particles& p = *sets[s];
    SupportNodes& sn = supports[s];
    sn.per_particle = kNodes;
    sn.nodes.resize(static_cast<std::size_t>(kNodes) * p.size());
    Eigen::Vector3i previous_base(0, 0, 0);
    for (int q = 0; q < p.size(); ++q) {
      Eigen::Vector3i base;
      for (int a = 0; a < 3; ++a) base[a] = BSpline<D>::base(p.x[q][a] / grid.spacing());
      int* nodes = sn.nodes.data() + static_cast<std::size_t>(kNodes) * q;
      if (q > 0 && base == previous_base) {
        std::copy(nodes - kNodes, nodes, nodes);
        continue;
      }
      forSupport<D>([&](int i, int j, int k, int n) {
        nodes[n] = grid.activate(base + Eigen::Vector3i(i, j, k));
      });
      previous_base = base;
    }
  }
}

template <int D>
void particleToGridImpl(const std::vector<const Particles*>& sets, SparseGrid& grid,
                        std::vector<SupportNodes>& supports) {
  const double dx = grid.spacing();
  grid.clear();
  activateSupports<D>(sets, grid, supports);
  const int nn = grid.size();
  // Each set's mass and momentum (m, m v) summed in fixed chunks (common/fixed_chunks.h); a set
  // without mass (the shell's contact particles, an absent solid) adds nothing and is skipped.
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const Particles& p = *sets[s];
    if (std::none_of(p.mass.begin(), p.mass.end(), [](double m) { return m != 0.0; })) continue;
    const std::vector<Eigen::Vector4d> sum = chunkedSum(
        p.size(), nn, Eigen::Vector4d::Zero().eval(),
        [&](std::vector<Eigen::Vector4d>& acc, int begin, int end) {
          for (int q = begin; q < end; ++q) {
            const double m = p.mass[q];
            if (m == 0.0) continue;  // massless particles (the shell's contact particles)
            const ParticleStencil<D> st(p.x[q], dx);
            const auto d = st.nodeOffsets(p.x[q], dx);
            const int* nodes = supports[s].of(q);
            forSupport<D>([&](int i, int j, int k, int n) {
              const double w = st.weight(i, j, k);
              const Eigen::Vector3d v =
                  p.v[q] + p.C[q] * Eigen::Vector3d(d[0][i], d[1][j], d[2][k]);
              acc[nodes[n]] += w * m * Eigen::Vector4d(1.0, v.x(), v.y(), v.z());  // (3.1), (3.2)
            });
          }
        });
    for (int i = 0; i < nn; ++i) {
      grid.mass[i] += sum[i][0];
      grid.momentum[i] += sum[i].tail<3>();
    }
  }
  for (int i = 0; i < nn; ++i)
    grid.velocity[i] = grid.mass[i] > 0.0 ? Eigen::Vector3d(grid.momentum[i] / grid.mass[i])
                                          : Eigen::Vector3d::Zero();
}

template <int D, bool kDeform>
void gridToParticleImpl(const SparseGrid& grid, Particles& p, double nu, double dt,
                        const SupportNodes* support) {
  const double dx = grid.spacing(), d_inv = ParticleStencil<D>::inverseInertia(dx);
  tbb::parallel_for(0, p.size(), [&](int q) {
    const ParticleStencil<D> s(p.x[q], dx);
    const auto d = s.nodeOffsets(p.x[q], dx);
    const int* nodes = support ? support->of(q) : nullptr;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero(), gradv = Eigen::Matrix3d::Zero();
    forSupport<D>([&](int i, int j, int k, int n) {
      const int node = nodes ? nodes[n] : grid.find(s.base + Eigen::Vector3i(i, j, k));
      if (node < 0) return;  // outside the transferred region: zero velocity
      const double w = s.weight(i, j, k);
      const Eigen::Vector3d& vi = grid.velocity[node];
      v += w * vi;                                                           // (3.13)
      B += w * vi * Eigen::RowVector3d(d[0][i], d[1][j], d[2][k]);           // (3.14)
      if constexpr (kDeform) gradv += vi * s.gradient(i, j, k).transpose();  // (3.17)
    });
    const Eigen::Matrix3d Ct = d_inv * B;
    p.C[q] = (1.0 - nu) * Ct + 0.5 * nu * (Ct - Ct.transpose());  // (3.15)
    p.v[q] = v;
    if constexpr (kDeform) p.F[q] = (Eigen::Matrix3d::Identity() + dt * gradv) * p.F[q];  // (3.17)
    p.x[q] += dt * v;                                                                     // (3.16)
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

void particleToGrid(const std::vector<const Particles*>& sets, SparseGrid& grid, int degree,
                    std::vector<SupportNodes>* supports) {
  checkDegree(degree);
  std::vector<SupportNodes> scratch;
  std::vector<SupportNodes>& s = supports ? *supports : scratch;
  if (degree == 2)
    particleToGridImpl<2>(sets, grid, s);
  else
    particleToGridImpl<3>(sets, grid, s);
}

void updateGridVelocity(SparseGrid& grid, const Eigen::Vector3d& gravity, double dt) {
  for (int i = 0; i < grid.size(); ++i) {
    if (grid.mass[i] <= 0.0) continue;
    grid.momentum[i] += dt * (grid.force[i] + grid.mass[i] * gravity);  // (5.40)
    grid.velocity[i] = grid.momentum[i] / grid.mass[i];                 // (3.10)
  }
}

void gridToParticle(const SparseGrid& grid, Particles& particles, int degree, double rpic_damping,
                    double dt, const SupportNodes* support, bool deformation_gradients) {
  checkDegree(degree);
  if (!(rpic_damping >= 0.0 && rpic_damping <= 1.0))
    throw InputError("RPIC damping must lie in [0, 1]");
  if (support) support->check(particles.size(), degree);
  if (degree == 2 && deformation_gradients)
    gridToParticleImpl<2, true>(grid, particles, rpic_damping, dt, support);
  else if (degree == 2)
    gridToParticleImpl<2, false>(grid, particles, rpic_damping, dt, support);
  else if (deformation_gradients)
    gridToParticleImpl<3, true>(grid, particles, rpic_damping, dt, support);
  else
    gridToParticleImpl<3, false>(grid, particles, rpic_damping, dt, support);
}

double cflTimeStep(const Particles& particles, double dx, double cfl, double dt_max) {
  double vmax = 0.0;
  for (const auto& v : particles.v) vmax = std::max(vmax, v.norm());
  return vmax > 0.0 ? std::min(dt_max, cfl * dx / vmax) : dt_max;
}

}  // namespace chs::mpm
