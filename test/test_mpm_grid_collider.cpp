// MPM grid boundary conditions from colliders (Han section 3.4): the Coulomb projection in
// closed form, and a block on an incline that slides iff tan(theta) > mu, with acceleration
// g (sin theta - mu cos theta).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/mpm/transfers.h"

namespace chs::mpm {
namespace {

TEST(MpmGridCollider, CoulombProjection) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const double mu = 0.5;
  // Approaching with enough slip: |v_t| loses mu |v_n|.
  Eigen::Vector3d v = collideRelativeVelocity({2.0, 0.0, -1.0}, n, ColliderBoundary::kSlip, mu);
  EXPECT_NEAR((v - Eigen::Vector3d(1.5, 0.0, 0.0)).norm(), 0.0, 1e-15);
  // Too little slip to overcome friction: stops.
  v = collideRelativeVelocity({0.3, 0.1, -1.0}, n, ColliderBoundary::kSeparating, mu);
  EXPECT_EQ(v, Eigen::Vector3d::Zero());
  // Separating nodes that leave are untouched; slip nodes lose the normal part, no friction.
  v = collideRelativeVelocity({0.3, 0.0, 0.7}, n, ColliderBoundary::kSeparating, mu);
  EXPECT_EQ(v, Eigen::Vector3d(0.3, 0.0, 0.7));
  v = collideRelativeVelocity({0.3, 0.0, 0.7}, n, ColliderBoundary::kSlip, mu);
  EXPECT_NEAR((v - Eigen::Vector3d(0.3, 0.0, 0.0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(collideRelativeVelocity({1, 2, 3}, n, ColliderBoundary::kSticky, mu),
            Eigen::Vector3d::Zero());
}

// Down-slope speed of a particle cloud held in an incline of angle theta after `steps` steps.
double slideSpeed(double theta, double mu, int steps, double dt) {
  const double g = 9.81;
  const Eigen::Vector3d n(-std::sin(theta), 0.0, std::cos(theta)),
      down(-std::cos(theta), 0.0, -std::sin(theta));
  GridCollider incline;
  incline.surface = std::make_shared<PlaneSurface>(Eigen::Vector3d::Zero(), n);
  incline.friction = mu;
  // The cloud sits 0.2 m inside the solid, so every node it touches is a boundary node and the
  // friction law alone decides its motion.
  Particles p;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      for (int k = -2; k <= 2; ++k)
        p.add(-0.2 * n + 0.004 * Eigen::Vector3d(i, j, k), Eigen::Vector3d::Zero(), 1e-3, 1e-6);
  SparseGrid grid(0.01);
  for (int s = 0; s < steps; ++s) {
    particleToGrid(p, grid, 2);
    updateGridVelocity(grid, Eigen::Vector3d(0, 0, -g), dt);
    applyGridColliders(grid, {incline});
    gridToParticle(grid, p, 2, 0.0, dt);
  }
  double speed = 0.0;
  for (const auto& v : p.v) speed += v.dot(down);
  return speed / p.size();
}

TEST(MpmGridCollider, InclineSlidesIffTanThetaExceedsMu) {
  const double mu = 0.4, theta_c = std::atan(mu), g = 9.81, dt = 1e-3;
  const int steps = 100;
  const double one_degree = M_PI / 180.0;
  const double below = slideSpeed(theta_c - one_degree, mu, steps, dt);
  const double above = slideSpeed(theta_c + one_degree, mu, steps, dt);
  const double th = theta_c + one_degree;
  const double expected = g * (std::sin(th) - mu * std::cos(th)) * steps * dt;
  std::printf(
      "mu %.2f (onset %.2f deg): at onset - 1 deg speed %.2e m/s; at onset + 1 deg "
      "%.5f m/s vs g (sin - mu cos) t = %.5f m/s\n",
      mu, theta_c / one_degree, below, above, expected);
  EXPECT_LT(std::abs(below), 1e-12);
  EXPECT_NEAR(above, expected, 1e-9);
}

// A moving collider carries sticky nodes with it.
TEST(MpmGridCollider, StickyNodesFollowAMovingCollider) {
  GridCollider floor;
  floor.surface = std::make_shared<PlaneSurface>(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  floor.velocity.linear = Eigen::Vector3d(0.5, -0.25, 0.0);
  floor.boundary = ColliderBoundary::kSticky;
  Particles p;
  p.add(Eigen::Vector3d(0.0, 0.0, -0.1), Eigen::Vector3d(3, 2, 1), 1e-3, 1e-6);
  SparseGrid grid(0.01);
  particleToGrid(p, grid, 2);
  updateGridVelocity(grid, Eigen::Vector3d(0, 0, -9.81), 1e-3);
  applyGridColliders(grid, {floor});
  gridToParticle(grid, p, 2, 0.0, 1e-3);
  EXPECT_NEAR((p.v[0] - floor.velocity.linear).norm(), 0.0, 1e-14);
}

}  // namespace
}  // namespace chs::mpm
