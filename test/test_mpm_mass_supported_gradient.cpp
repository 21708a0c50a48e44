// Weight gradients of a massless particle's support restricted to the nodes with mass
// (mpm/mass_supported_gradient.h): they sum to zero, reproduce the plain gradients where every
// node carries mass, read no strain in a uniform velocity, and an affine field over the nodes
// with mass comes out closer than with the massless nodes at rest.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/bspline_kernel.h"
#include "cloth_hair_sim/core/mpm/mass_supported_gradient.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {
namespace {

class MassSupportedGradient : public ::testing::TestWithParam<int> {};

// One massive particle at `carrier` and a massless one at `probe`, 0.1 m cells.
struct Pair {
  Particles carrier, probe;
  SparseGrid grid{0.1};
  std::vector<SupportNodes> supports;
  Pair(int degree, const Eigen::Vector3d& at_carrier, const Eigen::Vector3d& at_probe) {
    carrier.add(at_carrier, Eigen::Vector3d::Zero(), 1.0, 1.0);
    probe.add(at_probe, Eigen::Vector3d::Zero(), 0.0, 1.0);
    particleToGrid({&carrier, &probe}, grid, degree, &supports);
  }
};

TEST_P(MassSupportedGradient, SumsToZeroAndIgnoresUniformMotion) {
  const int degree = GetParam();
  Pair s(degree, Eigen::Vector3d(0.21, 0.33, 0.27), Eigen::Vector3d(0.29, 0.36, 0.34));
  std::vector<Eigen::Vector3d> g;
  massSupportedGradients(s.grid, s.probe.x[0], degree, s.supports[1].of(0), g);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int massless = 0;
  for (int n = 0; n < s.supports[1].per_particle; ++n) {
    sum += g[n];
    if (s.grid.mass[s.supports[1].of(0)[n]] == 0.0) {
      ++massless;
      EXPECT_EQ(g[n].norm(), 0.0);
    }
  }
  // A uniform velocity on the nodes with mass (the massless ones at rest) is no strain.
  std::vector<Eigen::Vector3d> u(s.grid.size(), Eigen::Vector3d::Zero());
  for (int i = 0; i < s.grid.size(); ++i)
    if (s.grid.mass[i] > 0.0) u[i] = Eigen::Vector3d(0.4, -1.0, 2.0);
  std::vector<Eigen::Matrix3d> grad;
  interpolateMassSupportedGradient(s.grid, u, s.probe.x, degree, s.supports[1], grad);
  std::printf(
      "[figure] degree %d: %d of %d support nodes massless; |sum g| %.1e 1/m, uniform motion "
      "reads |grad u| %.1e 1/s (tolerance 1e-12)\n",
      degree, massless, s.supports[1].per_particle, sum.norm(), grad[0].norm());
  EXPECT_GT(massless, 0);
  EXPECT_LT(sum.norm(), 1e-12);
  EXPECT_LT(grad[0].norm(), 1e-12);
}

TEST_P(MassSupportedGradient, EqualsTheWeightGradientWhereAllNodesCarryMass) {
  const int degree = GetParam();
  const Eigen::Vector3d x(0.23, 0.31, 0.28);
  Pair s(degree, x, x);  // the carrier's support is the probe's
  std::vector<Eigen::Vector3d> g;
  massSupportedGradients(s.grid, x, degree, s.supports[1].of(0), g);
  double worst = 0.0;
  const int n = degree + 1;
  const auto check = [&](const auto& stencil) {
    for (int i = 0, m = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k, ++m)
          worst = std::max(worst, (g[m] - stencil.gradient(i, j, k)).norm());
  };
  if (degree == 2)
    check(ParticleStencil<2>(x, 0.1));
  else
    check(ParticleStencil<3>(x, 0.1));
  std::printf("[figure] degree %d, every node with mass: largest |g - grad w| %.1e 1/m\n", degree,
              worst);
  EXPECT_LT(worst, 1e-12);
}

// Rotation about the carrier: the massless nodes at rest read a spurious gradient; given the
// particle's mean velocity they read less of one.
TEST_P(MassSupportedGradient, ReadsRigidRotationBetterThanNodesAtRest) {
  const int degree = GetParam();
  Pair s(degree, Eigen::Vector3d(0.21, 0.33, 0.27), Eigen::Vector3d(0.29, 0.36, 0.34));
  Eigen::Matrix3d W;
  W << 0, -1, 0.5, 1, 0, -2, -0.5, 2, 0;
  std::vector<Eigen::Vector3d> u(s.grid.size(), Eigen::Vector3d::Zero());
  for (int i = 0; i < s.grid.size(); ++i)
    if (s.grid.mass[i] > 0.0) u[i] = W * s.grid.position(i);
  std::vector<Eigen::Matrix3d> restricted;
  interpolateMassSupportedGradient(s.grid, u, s.probe.x, degree, s.supports[1], restricted);
  Eigen::Matrix3d at_rest = Eigen::Matrix3d::Zero();
  const int* nodes = s.supports[1].of(0);
  const int n = degree + 1;
  const auto plain = [&](const auto& stencil) {
    for (int i = 0, m = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k, ++m)
          at_rest += u[nodes[m]] * stencil.gradient(i, j, k).transpose();
  };
  if (degree == 2)
    plain(ParticleStencil<2>(s.probe.x[0], 0.1));
  else
    plain(ParticleStencil<3>(s.probe.x[0], 0.1));
  const double e_restricted = (restricted[0] - W).norm() / W.norm();
  const double e_rest = (at_rest - W).norm() / W.norm();
  std::printf(
      "[figure] degree %d, rigid rotation: relative gradient error %.3f restricted to the nodes "
      "with mass, %.3f with the massless nodes at rest\n",
      degree, e_restricted, e_rest);
  EXPECT_LT(e_restricted, e_rest);
}

TEST(MassSupportedGradientInput, RejectsBadDegreeAndSizes) {
  Pair s(2, Eigen::Vector3d(0.2, 0.3, 0.2), Eigen::Vector3d(0.25, 0.3, 0.2));
  std::vector<Eigen::Vector3d> g;
  EXPECT_THROW(massSupportedGradients(s.grid, s.probe.x[0], 4, s.supports[1].of(0), g), InputError);
  std::vector<Eigen::Matrix3d> grad;
  EXPECT_THROW(interpolateMassSupportedGradient(s.grid, std::vector<Eigen::Vector3d>(1), s.probe.x,
                                                2, s.supports[1], grad),
               InputError);
}

INSTANTIATE_TEST_SUITE_P(Degrees, MassSupportedGradient, ::testing::Values(2, 3));

}  // namespace
}  // namespace chs::mpm
