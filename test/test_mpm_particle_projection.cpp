// The projection of a node field through the mass-carrying particles (mpm/particle_projection.h):
// S u = P(u) / m reproduces affine fields, P is symmetric (so forces entered as P(f / m) are the
// transpose of the velocities S v), P(f / m) keeps the total force on the nodes with mass, and a
// node of almost no mass gets the velocity of the particle that gives it that mass.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/particle_projection.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {
namespace {

struct Scene {
  Particles carriers, massless;
  SparseGrid grid{0.1};
  std::vector<SupportNodes> supports;
  std::vector<MassCarriers> sets() const {
    return {{&carriers.x, &carriers.mass, &supports[0]},
            {&massless.x, &massless.mass, &supports[1]}};
  }
};

// Random particles in a 0.4 m box with random masses, and massless ones around them whose
// supports reach nodes the carriers do not (as the shell's contact particles do).
Scene makeScene(int degree, unsigned seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 0.4), m(0.5, 2.0), far(-0.1, 0.5);
  for (int p = 0; p < 300; ++p)
    s.carriers.add(Eigen::Vector3d(u(rng), u(rng), u(rng)), Eigen::Vector3d::Zero(), m(rng), 1.0);
  for (int p = 0; p < 100; ++p)
    s.massless.add(Eigen::Vector3d(far(rng), far(rng), far(rng)), Eigen::Vector3d::Zero(), 0.0,
                   1.0);
  particleToGrid({&s.carriers, &s.massless}, s.grid, degree, &s.supports);
  return s;
}

std::vector<Eigen::Vector3d> randomField(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> f(n);
  for (auto& v : f) v = Eigen::Vector3d(g(rng), g(rng), g(rng));
  return f;
}

class ParticleProjection : public ::testing::TestWithParam<int> {};

TEST_P(ParticleProjection, ReproducesAffineFieldsAtNodesWithMass) {
  const int degree = GetParam();
  Scene s = makeScene(degree, 1);
  Eigen::Matrix3d A;
  A << 0.3, -1.2, 0.5, 2.0, 0.1, -0.7, 0.4, 0.9, -0.2;
  const Eigen::Vector3d b(0.5, -0.25, 1.0);
  std::vector<Eigen::Vector3d> u(s.grid.size());
  for (int i = 0; i < s.grid.size(); ++i) u[i] = A * s.grid.position(i) + b;
  std::vector<Eigen::Vector3d> p;
  projectThroughParticles(s.grid, s.sets(), degree, u, p);
  double worst = 0.0;
  int with_mass = 0, without = 0;
  for (int i = 0; i < s.grid.size(); ++i) {
    if (s.grid.mass[i] > 0.0) {
      worst = std::max(worst, (p[i] / s.grid.mass[i] - u[i]).norm() / u[i].norm());
      ++with_mass;
    } else {
      EXPECT_EQ(p[i].norm(), 0.0);
      ++without;
    }
  }
  std::printf(
      "[figure] degree %d: affine field through %d carriers, %d nodes with mass (%d without): "
      "largest relative error %.2e (tolerance 1e-12)\n",
      degree, s.carriers.size(), with_mass, without, worst);
  EXPECT_GT(without, 0);  // the massless particles reach nodes no carrier does
  EXPECT_LT(worst, 1e-12);
}

TEST_P(ParticleProjection, IsSymmetricAndKeepsTheTotalForce) {
  const int degree = GetParam();
  Scene s = makeScene(degree, 2);
  const int n = s.grid.size();
  const auto a = randomField(n, 3), b = randomField(n, 4);
  std::vector<Eigen::Vector3d> pa, pb;
  projectThroughParticles(s.grid, s.sets(), degree, a, pa);
  projectThroughParticles(s.grid, s.sets(), degree, b, pb);
  double ab = 0.0, ba = 0.0, scale = 0.0;
  for (int i = 0; i < n; ++i) {
    ab += a[i].dot(pb[i]);
    ba += b[i].dot(pa[i]);
    scale += std::abs(a[i].dot(pb[i]));
  }
  // A force field on the nodes with mass enters as P(f / m) with the same total.
  std::vector<Eigen::Vector3d> f(n, Eigen::Vector3d::Zero()), u(n, Eigen::Vector3d::Zero()), pf;
  Eigen::Vector3d total = Eigen::Vector3d::Zero(), entered = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    if (s.grid.mass[i] <= 0.0) continue;
    f[i] = a[i];
    u[i] = f[i] / s.grid.mass[i];
    total += f[i];
  }
  projectThroughParticles(s.grid, s.sets(), degree, u, pf);
  for (const auto& v : pf) entered += v;
  const double asym = std::abs(ab - ba) / scale, force = (entered - total).norm() / total.norm();
  std::printf(
      "[figure] degree %d: |<a, P b> - <b, P a>| / scale %.2e; total force through P(f/m) "
      "relative error %.2e (tolerance 1e-12 each)\n",
      degree, asym, force);
  EXPECT_LT(asym, 1e-12);
  EXPECT_LT(force, 1e-12);
}

// One particle: a node at the edge of its support has mass ~ w m with w tiny. Whatever value u
// has there, S u at that node is the particle's APIC field, bounded by the field at the nodes
// that carry the particle's mass.
TEST_P(ParticleProjection, NodeOfTinyMassTakesTheParticleField) {
  const int degree = GetParam();
  Particles one;
  const double dx = 0.1;
  const double edge = degree == 2 ? 1.5 : 2.0;  // support half-width in cells
  one.add(Eigen::Vector3d(0.5 * dx, 0.5 * dx, (edge - 1e-6) * dx), Eigen::Vector3d::Zero(), 1.0,
          1.0);
  SparseGrid grid(dx);
  std::vector<SupportNodes> supports;
  particleToGrid({&one}, grid, degree, &supports);
  int tiny = -1;
  double largest = 0.0;
  for (int i = 0; i < grid.size(); ++i) {
    largest = std::max(largest, grid.mass[i]);
    if (grid.mass[i] > 0.0 && (tiny < 0 || grid.mass[i] < grid.mass[tiny])) tiny = i;
  }
  ASSERT_GE(tiny, 0);
  std::vector<Eigen::Vector3d> u(grid.size(), Eigen::Vector3d(1.0, 0.0, 0.0));
  u[tiny] = Eigen::Vector3d(0.0, 0.0, 1e10);  // what dt f / m gives such a node
  std::vector<Eigen::Vector3d> p;
  projectThroughParticles(grid, {{&one.x, &one.mass, &supports[0]}}, degree, u, p);
  const Eigen::Vector3d s = p[tiny] / grid.mass[tiny];
  std::printf(
      "[figure] degree %d: node of mass %.1e of the largest, given 1e10 m/s: S u = (%.3f, %.3f, "
      "%.3e)\n",
      degree, grid.mass[tiny] / largest, s.x(), s.y(), s.z());
  EXPECT_LT(grid.mass[tiny] / largest, 1e-9);
  EXPECT_NEAR(s.x(), 1.0, 1e-6);
  // The 1e10 enters with its weight (~1e-13) times O(1) from the affine part.
  EXPECT_LT(std::abs(s.z()), 0.1);
}

TEST(ParticleProjectionInput, RejectsMismatchedSizes) {
  Scene s = makeScene(2, 5);
  std::vector<Eigen::Vector3d> p;
  EXPECT_THROW(projectThroughParticles(s.grid, s.sets(), 2,
                                       std::vector<Eigen::Vector3d>(s.grid.size() + 1), p),
               InputError);
  EXPECT_THROW(
      projectThroughParticles(s.grid, s.sets(), 3, std::vector<Eigen::Vector3d>(s.grid.size()), p),
      InputError);  // supports recorded for degree 2
  std::vector<double> short_masses(3, 1.0);
  EXPECT_THROW(projectThroughParticles(s.grid, {{&s.carriers.x, &short_masses, &s.supports[0]}}, 2,
                                       std::vector<Eigen::Vector3d>(s.grid.size()), p),
               InputError);
}

INSTANTIATE_TEST_SUITE_P(Degrees, ParticleProjection, ::testing::Values(2, 3));

}  // namespace
}  // namespace chs::mpm
