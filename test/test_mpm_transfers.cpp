// MPM core (Han chapter 3): B-spline kernel identities, APIC transfers that conserve mass, linear
// and angular momentum and reproduce affine velocity fields, RPIC damping, and free flight.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/mpm/bspline_kernel.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {
namespace {

Eigen::Matrix3d cross(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return S;
}

// Partition of unity, zero first moment, second moment D = dx^2 (d + 1)/12 I and
// sum grad w (x_i - x_p)^T = I, at random positions.
template <int D>
void checkKernel() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  const double dx = 0.37;
  double worst = 0.0;
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    const ParticleStencil<D> s(x, dx);
    double sum = 0.0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero(), grad = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero(), gx = Eigen::Matrix3d::Zero();
    const int n = ParticleStencil<D>::kSupport;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const Eigen::Vector3d d =
              (s.base + Eigen::Vector3i(i, j, k)).template cast<double>() * dx - x;
          const double w = s.weight(i, j, k);
          sum += w;
          first += w * d;
          second += w * d * d.transpose();
          grad += s.gradient(i, j, k);
          gx += s.gradient(i, j, k) * d.transpose();
        }
    const Eigen::Matrix3d D_exact = dx * dx * (D + 1) / 12.0 * Eigen::Matrix3d::Identity();
    worst = std::max({worst, std::abs(sum - 1.0), first.norm() / dx, grad.norm() * dx,
                      (second - D_exact).norm() / (dx * dx),
                      (gx - Eigen::Matrix3d::Identity()).norm()});
  }
  std::printf("degree %d kernel: worst deviation from the identities %.2e\n", D, worst);
  EXPECT_LT(worst, 1e-13);
}

TEST(MpmKernel, QuadraticIdentities) {
  checkKernel<2>();
}
TEST(MpmKernel, CubicIdentities) {
  checkKernel<3>();
}

Particles randomCloud(int n, bool random_motion) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), m(0.5, 1.5);
  Particles p;
  for (int i = 0; i < n; ++i) {
    p.add(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.2,
          random_motion ? Eigen::Vector3d(u(rng), u(rng), u(rng)) : Eigen::Vector3d::Zero(),
          m(rng) * 1e-3, 1e-6);
    if (random_motion) p.C.back() = Eigen::Matrix3d::Random() * 3.0;
  }
  return p;
}

struct Momenta {
  double mass;
  Eigen::Vector3d linear, angular;
};

Momenta ofGrid(const SparseGrid& g) {
  Momenta s{0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int i = 0; i < g.size(); ++i) {
    s.mass += g.mass[i];
    s.linear += g.mass[i] * g.velocity[i];
    s.angular += g.position(i).cross(g.mass[i] * g.velocity[i]);
  }
  return s;
}

// Particle angular momentum including the affine part: sum_i w_ip (x_i - x_p) x m_p C_p (x_i -
// x_p) for each particle (Jiang et al.'s APIC angular momentum), evaluated over the stencil.
template <int D>
Momenta ofParticles(const Particles& p, double dx) {
  Momenta s{0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int q = 0; q < p.size(); ++q) {
    s.mass += p.mass[q];
    s.linear += p.mass[q] * p.v[q];
    s.angular += p.x[q].cross(p.mass[q] * p.v[q]);
    const ParticleStencil<D> st(p.x[q], dx);
    const int n = ParticleStencil<D>::kSupport;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const Eigen::Vector3d d =
              (st.base + Eigen::Vector3i(i, j, k)).template cast<double>() * dx - p.x[q];
          s.angular += st.weight(i, j, k) * d.cross(p.mass[q] * p.C[q] * d);
        }
  }
  return s;
}

template <int D>
void checkConservation(double nu) {
  const double dx = 0.05;
  Particles p = randomCloud(2000, true);
  SparseGrid grid(dx);
  const Momenta before = ofParticles<D>(p, dx);
  particleToGrid(p, grid, D);
  const Momenta on_grid = ofGrid(grid);
  gridToParticle(grid, p, D, nu, 0.0);  // dt = 0: transfers only
  const Momenta after = ofParticles<D>(p, dx);
  const double em = std::abs(on_grid.mass - before.mass) / before.mass;
  const double el = (on_grid.linear - before.linear).norm() / before.linear.norm();
  const double ea = (on_grid.angular - before.angular).norm() / before.angular.norm();
  const double el2 = (after.linear - on_grid.linear).norm() / on_grid.linear.norm();
  const double ea2 = (after.angular - on_grid.angular).norm() / on_grid.angular.norm();
  std::printf(
      "degree %d, RPIC nu %.1f: P2G mass %.1e, linear %.1e, angular %.1e; G2P linear "
      "%.1e, angular %.1e (relative)\n",
      D, nu, em, el, ea, el2, ea2);
  for (double e : {em, el, ea, el2, ea2}) EXPECT_LT(e, 1e-10);
}

TEST(MpmTransfers, ConserveMomentaQuadratic) {
  checkConservation<2>(0.0);
}
TEST(MpmTransfers, ConserveMomentaCubic) {
  checkConservation<3>(0.0);
}
// RPIC removes the symmetric part of C, which carries no angular momentum (D_p is isotropic).
TEST(MpmTransfers, RpicDampingConservesMomenta) {
  checkConservation<2>(1.0);
}

// A rigid motion v = v0 + w x (x - c), C = [w]x is an affine field: APIC transfers it to the grid
// and back unchanged.
TEST(MpmTransfers, ReproduceRigidMotion) {
  for (int degree : {2, 3}) {
    Particles p = randomCloud(1000, false);
    const Eigen::Vector3d v0(0.3, -0.2, 0.5), w(1.0, -2.0, 0.7), c(0.01, 0.02, -0.03);
    for (int q = 0; q < p.size(); ++q) {
      p.v[q] = v0 + w.cross(p.x[q] - c);
      p.C[q] = cross(w);
    }
    const Particles start = p;
    SparseGrid grid(0.04);
    particleToGrid(p, grid, degree);
    gridToParticle(grid, p, degree, 1.0, 0.0);
    double ev = 0.0, ec = 0.0;
    for (int q = 0; q < p.size(); ++q) {
      ev = std::max(ev, (p.v[q] - start.v[q]).norm());
      ec = std::max(ec, (p.C[q] - start.C[q]).norm());
    }
    std::printf("degree %d rigid motion through P2G/G2P: velocity error %.1e, C error %.1e\n",
                degree, ev, ec);
    EXPECT_LT(ev, 1e-12);
    EXPECT_LT(ec, 1e-11);
  }
}

// Free flight under gravity with symplectic Euler: v_n = v0 + n dt g and
// x_n = x0 + n dt v0 + dt^2 g n (n + 1) / 2, for every particle.
TEST(MpmStep, FreeFlightUnderGravity) {
  Particles p = randomCloud(500, false);
  const Eigen::Vector3d v0(0.1, 0.0, 0.4), g(0.0, 0.0, -9.81);
  for (auto& v : p.v) v = v0;
  const Particles start = p;
  SparseGrid grid(0.03);
  const double dt = 1e-3;
  const int steps = 200;
  for (int n = 0; n < steps; ++n) {
    particleToGrid(p, grid, 2);
    updateGridVelocity(grid, g, dt);
    gridToParticle(grid, p, 2, 0.0, dt);
  }
  double ex = 0.0, ev = 0.0;
  for (int q = 0; q < p.size(); ++q) {
    const Eigen::Vector3d v = v0 + steps * dt * g;
    const Eigen::Vector3d x =
        start.x[q] + steps * dt * v0 + dt * dt * g * steps * (steps + 1) / 2.0;
    ev = std::max(ev, (p.v[q] - v).norm());
    ex = std::max(ex, (p.x[q] - x).norm());
  }
  std::printf("free flight, %d steps: velocity error %.1e m/s, position error %.1e m\n", steps, ev,
              ex);
  EXPECT_LT(ev, 1e-12);
  EXPECT_LT(ex, 1e-12);
}

TEST(MpmStep, CflLimitsTheStep) {
  Particles p = randomCloud(10, false);
  p.v[3] = Eigen::Vector3d(0, 0, 20.0);
  EXPECT_DOUBLE_EQ(cflTimeStep(p, 0.01, 0.5, 1.0), 0.5 * 0.01 / 20.0);
  EXPECT_DOUBLE_EQ(cflTimeStep(Particles(), 0.01, 0.5, 1e-3), 1e-3);
}

}  // namespace
}  // namespace chs::mpm
