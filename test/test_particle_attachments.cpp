// Holding forces of pinned vertices (what a gripper feels) and obstacles that move with a
// velocity (a collider carried by tf) in the dynamic particle model.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/dynamics/holding_wrench.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// 10 x 10 cm of the seed's cotton as n x n quads.
DrapeProblem cottonSquare(int n) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, n, n);
  p.material = *materialPreset("cotton_eischen");  // seed 000 section 4.4
  p.gravity = Vec3(0, 0, -9.81);
  return p;
}

TEST(HoldingForces, HangingClothWeighsOnItsTopEdge) {
  const int n = 4;
  DrapeProblem p = cottonSquare(n);
  for (auto& x : p.mesh.vertices) x = Vec3(x.x(), 0.0, x.y());  // hung in the xz plane
  std::vector<int> top;
  for (int i = 0; i <= n; ++i) top.push_back(n * (n + 1) + i);  // z = +0.05
  p.bc.pinned = top;
  ParticleDynamicsSettings s;
  s.damping = 20.0;
  ParticleDynamics dyn(p, s);
  // Start swinging: the cloth is pushed sideways, then settles.
  std::vector<Vec3> v(dyn.numVertices(), Vec3(0.0, 0.3, 0.0));
  dyn.setVelocities(v);
  const double dt = dyn.stableTimeStep();
  while (dyn.time() < 1.5) dyn.step(dt);

  const double weight = 0.2384 * 0.01 * 9.81;
  const Vec3 centre(0.0, 0.0, 0.05);
  const HoldingWrench w = holdingWrench(dyn, top, centre);
  std::printf(
      "hanging 10 x 10 cm cotton (%d x %d quads) after %.2f s: holding force (%.3e, %.3e, "
      "%.6e) N, weight %.6e N (error %.2e), torque about the edge centre %.2e N m\n",
      n, n, dyn.time(), w.force.x(), w.force.y(), w.force.z(), weight, w.force.z() / weight - 1.0,
      w.torque.norm());
  EXPECT_NEAR(w.force.z(), weight, 1e-4 * weight);
  EXPECT_NEAR(w.force.head<2>().norm(), 0.0, 1e-4 * weight);
  EXPECT_NEAR(w.torque.norm(), 0.0, 1e-4 * weight * 0.05);
  // About another point the moment is that of the weight's line of action through the centre.
  const Vec3 o(0.1, 0.0, 0.0);
  const HoldingWrench wo = holdingWrench(dyn, top, o);
  const Vec3 expected = (centre - o).cross(Vec3(0, 0, weight));
  EXPECT_LT((wo.torque - expected).norm(), 1e-4 * weight * 0.1);
  // The per-vertex reactions add up to the wrench.
  Vec3 sum = Vec3::Zero();
  for (const auto& r : dyn.holdingForces(top)) sum += r;
  EXPECT_LT((sum - w.force).norm(), 1e-15);
}

TEST(HoldingForces, AcceleratedSupportAddsInertia) {
  DrapeProblem p = cottonSquare(2);
  ParticleDynamics dyn(p);
  std::vector<int> all;
  for (int i = 0; i < dyn.numVertices(); ++i) all.push_back(i);
  const Vec3 a(0.0, 0.0, 2.0);  // lifted with 2 m/s^2: holding takes m (a - g)
  const HoldingWrench w = holdingWrench(dyn, all, Vec3::Zero(), std::vector<Vec3>(all.size(), a));
  const double mass = 0.2384 * 0.01;
  EXPECT_NEAR(w.force.z(), mass * (2.0 + 9.81), 1e-12);
  EXPECT_THROW(dyn.holdingForces({dyn.numVertices()}), InputError);
  EXPECT_THROW(dyn.holdingForces({0, 1}, {a}), InputError);
}

// A floor rising at u lifts the cloth lying on it; with its velocity given, the cloth moves at u
// (not only projected out at each step with no velocity of its own).
TEST(MovingObstacle, RisingFloorCarriesTheCloth) {
  const double u = 0.2;
  double vz[2] = {0.0, 0.0}, z[2] = {0.0, 0.0};
  for (int with_velocity = 0; with_velocity < 2; ++with_velocity) {
    ParticleDynamicsSettings s;
    s.damping = 1.0;
    ParticleDynamics dyn(cottonSquare(4), s);
    const double dt = dyn.stableTimeStep();
    while (dyn.time() < 0.2) {
      const double t = dyn.time() + dt;  // the floor's height at the end of the step
      RigidSurfaces floor{std::make_shared<PlaneSurface>(Vec3(0, 0, u * t), Vec3::UnitZ())};
      SurfaceVelocity vel;
      vel.linear = Vec3(0, 0, u);
      dyn.setColliders(floor, with_velocity ? std::vector<SurfaceVelocity>{vel}
                                            : std::vector<SurfaceVelocity>{});
      dyn.step(dt);
    }
    double lo = 1e9, mean_v = 0.0;
    for (int i = 0; i < dyn.numVertices(); ++i) {
      lo = std::min(lo, dyn.positions()[i].z());
      mean_v += dyn.velocities()[i].z() / dyn.numVertices();
    }
    z[with_velocity] = lo;
    vz[with_velocity] = mean_v;
  }
  std::printf(
      "floor rising at %.2f m/s for 0.2 s: cloth lowest z %.5f / %.5f m, mean vertical "
      "velocity %.4f (floor at rest in the model) / %.4f m/s (floor velocity given)\n",
      u, z[0], z[1], vz[0], vz[1]);
  EXPECT_NEAR(z[0], u * 0.2, 1e-3);  // pushed along either way
  EXPECT_NEAR(z[1], u * 0.2, 1e-3);
  EXPECT_NEAR(vz[1], u, 0.01 * u);
  EXPECT_THROW(ParticleDynamics(cottonSquare(1))
                   .setColliders({std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ())},
                                 std::vector<SurfaceVelocity>(2)),
               InputError);
}

}  // namespace
}  // namespace chs
