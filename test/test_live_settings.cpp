// Live gravity and damping of both dynamics backends (ClothDynamics::setGravity, setDamping), as
// the ROS node's dynamic_reconfigure changes them between steps: a free patch follows the new
// gravity at once, damping decays its velocity at the new rate, bad values are refused.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

std::unique_ptr<ClothDynamics> makeBackend(bool hybrid) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 4, 4);
  p.material = testCloth();
  p.gravity = Vec3(0.0, 0.0, -9.81);
  if (hybrid) return std::make_unique<HybridShellDynamics>(p);
  return std::make_unique<ParticleDynamics>(p);
}

Vec3 meanVelocity(const ClothDynamics& d) {
  Vec3 sum = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < d.numVertices(); ++i) {
    sum += d.masses()[i] * d.velocities()[i];
    m += d.masses()[i];
  }
  return sum / m;
}

void runFor(ClothDynamics& d, double t) {
  const double end = d.time() + t;
  while (d.time() < end - 1e-12) d.step(std::min(d.stableTimeStep(), end - d.time()));
}

TEST(LiveSettings, GravityTurnsSidewaysBetweenSteps) {
  for (bool hybrid : {false, true}) {
    auto d = makeBackend(hybrid);
    runFor(*d, 0.01);
    const Vec3 before = meanVelocity(*d);
    d->setGravity(Vec3(3.0, 0.0, 0.0));
    runFor(*d, 0.02);
    const Vec3 gained = meanVelocity(*d) - before;
    std::printf("[figure] %s: 0.02 s under gravity (3, 0, 0) m/s^2 adds (%.5f, %.5f, %.5f) m/s\n",
                hybrid ? "hybrid shell" : "particle", gained.x(), gained.y(), gained.z());
    EXPECT_NEAR(gained.x(), 0.06, 1e-3);
    EXPECT_NEAR(gained.z(), 0.0, 1e-3);
    // Refused, and the previous gravity still acts.
    EXPECT_THROW(d->setGravity(Vec3(0.0, std::nan(""), 0.0)), InputError);
    const Vec3 v1 = meanVelocity(*d);
    runFor(*d, 0.01);
    EXPECT_NEAR((meanVelocity(*d) - v1).x(), 0.03, 1e-3);
  }
}

TEST(LiveSettings, DampingDecaysAtTheNewRate) {
  for (bool hybrid : {false, true}) {
    auto d = makeBackend(hybrid);
    d->setGravity(Vec3::Zero());
    d->setVelocities(std::vector<Vec3>(d->numVertices(), Vec3(0.0, 0.0, 0.1)));
    d->setDamping(20.0);
    runFor(*d, 0.05);
    const double ratio = meanVelocity(*d).z() / 0.1;
    std::printf("[figure] %s: damping 20 1/s for 0.05 s keeps %.4f of the velocity (exp: %.4f)\n",
                hybrid ? "hybrid shell" : "particle", ratio, std::exp(-1.0));
    EXPECT_NEAR(ratio, std::exp(-1.0), 0.01);
    EXPECT_THROW(d->setDamping(-1.0), InputError);
    EXPECT_THROW(d->setDamping(std::nan("")), InputError);
    d->setDamping(0.0);
    const double v = meanVelocity(*d).z();
    runFor(*d, 0.02);
    EXPECT_NEAR(meanVelocity(*d).z(), v, 1e-9);
  }
}

}  // namespace
}  // namespace chs
