// The hybrid Lagrangian/MPM thin shell (Han chapter 5) against conservation laws and its
// contracts: momentum, free fall, a hanging cloth's support force, bad settings. The physical
// cases against the FEM shell and closed forms are in test_hybrid_shell_validation.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// Runs until time t with steps of at most the stable one.
void runFor(HybridShellDynamics& d, double t) {
  while (d.time() < t - 1e-12) d.step(std::min(d.stableTimeStep(), t - d.time()));
}

// A gently curved 6 x 6 patch spinning and flying without gravity: the transfers and the grid
// forces (5.46)-(5.49) exchange momentum only between particles. With massless contact
// particles the step is APIC's exactly; with massive ones (5.54) re-places them on the surface
// without moving their momentum, which shifts angular momentum by O(dt) per step.
TEST(HybridShell, MomentumConservedInFreeFlight) {
  for (double fraction : {0.0, 0.5}) {
    DrapeProblem p;
    p.mesh = makeRectangleMesh(0.1, 0.1, 6, 6);
    for (auto& x : p.mesh.vertices) x.z() = 2.0 * x.x() * x.x();
    p.material = testCloth();
    p.gravity.setZero();
    HybridShellSettings s;
    s.contact_mass_fraction = fraction;
    HybridShellDynamics d(p, s);
    const Vec3 w(0.5, -1.0, 2.0), v0(0.3, 0.1, -0.2);
    std::vector<Vec3> v;
    for (const Vec3& x : d.positions()) v.push_back(v0 + w.cross(x));
    d.setVelocities(v);
    const Vec3 P0 = d.linearMomentum(), L0 = d.angularMomentum();
    for (int i = 0; i < 200; ++i) d.step(2e-5);
    const double dP = (d.linearMomentum() - P0).norm() / P0.norm();
    const double dL = (d.angularMomentum() - L0).norm() / L0.norm();
    std::printf(
        "[figure] free flight, contact mass fraction %.1f, 200 steps: relative change of "
        "linear momentum %.2e, angular momentum %.2e\n",
        fraction, dP, dL);
    EXPECT_LT(dP, 1e-10);
    if (fraction == 0.0) {
      EXPECT_LT(dL, 1e-10);
    }
  }
}

// A flat sheet tilted against the grid and translating: its contact particles' supports reach
// nodes that no control point's does. Fibres that read those nodes' zero velocity saw a rigid
// motion as strain, and their forces there were dropped (9.4e-8 / 7.9e-7 of the momentum lost
// at 0.3 / 0.6 rad in 0.04 s); with the weight gradients restricted to the nodes with mass
// (mpm/mass_supported_gradient.h) the momentum stays.
TEST(HybridShell, TiltedSheetKeepsItsMomentum) {
  for (double angle : {0.3, 0.6}) {
    DrapeProblem p;
    p.mesh = makeRectangleMesh(0.1, 0.1, 10, 10);
    const Eigen::AngleAxisd tilt(angle, Vec3::UnitX());
    for (auto& x : p.mesh.vertices) x = tilt * x + Vec3(0.003, 0.002, 0.001);
    p.material = testCloth();
    p.gravity.setZero();
    HybridShellSettings s;
    s.grid_spacing = 0.01;
    HybridShellDynamics d(p, s);
    d.setVelocities(std::vector<Vec3>(d.numVertices(), Vec3(0.3, -0.2, 0.1)));
    const Vec3 P0 = d.linearMomentum();
    runFor(d, 0.04);
    const double dP = (d.linearMomentum() - P0).norm() / P0.norm();
    std::printf(
        "[figure] sheet tilted %.1f rad translating 0.04 s (%d steps): relative change of linear "
        "momentum %.2e (tolerance 1e-10)\n",
        angle, d.stageTimes().steps, dP);
    EXPECT_LT(dP, 1e-10);
  }
}

// Without obstacles the centre of mass falls at g whatever the internal forces do.
TEST(HybridShell, FreeFallAcceleratesAtG) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 5, 5);
  p.material = testCloth();
  HybridShellDynamics d(p);
  runFor(d, 0.05);
  const Vec3 v = d.linearMomentum() / d.totalMass();
  std::printf("[figure] free fall: centre-of-mass velocity %.12f m/s after %.3f s (g t = %.12f)\n",
              v.z(), d.time(), -9.81 * d.time());
  EXPECT_NEAR(v.z(), -9.81 * d.time(), 1e-10);
  std::printf("[figure] mass %.9f kg vs rho_A A = %.9f kg\n", d.totalMass(), 0.2 * 0.01);
  EXPECT_NEAR(d.totalMass(), 0.2 * 0.01, 1e-12);
}

// A sheet hung from its top row settles; the pins then carry its weight.
TEST(HybridShell, HangingSheetPinsCarryTheWeight) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 8, 8);
  for (auto& x : p.mesh.vertices) x = Vec3(x.x(), 0.0, x.y());  // vertical, in the x-z plane
  p.material = testCloth();
  std::vector<int> top;
  for (int i = 0; i <= 8; ++i) top.push_back(8 * 9 + i);
  p.bc.pinned = top;
  HybridShellSettings s;
  s.damping = 20.0;
  HybridShellDynamics d(p, s);
  Vec3 sum = Vec3::Zero();
  int samples = 0;
  while (d.time() < 1.0) {
    d.step(d.stableTimeStep());
    if (d.time() > 0.8) {
      for (const Vec3& f : d.holdingForces(top)) sum += f;
      ++samples;
    }
  }
  const double weight = d.totalMass() * 9.81;
  const double held = sum.z() / samples;
  std::printf(
      "[figure] hanging sheet: pins hold %.6f N upward on average over the last 0.2 s, "
      "weight %.6f N (error %.3f %%)\n",
      held, weight, 100 * (held - weight) / weight);
  EXPECT_NEAR(held, weight, 1e-3 * weight);
}

TEST(HybridShell, RejectsNonsense) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 2, 2);
  p.material = testCloth();
  HybridShellSettings s;
  s.kernel_degree = 4;
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  s = {};
  s.contact_mass_fraction = 1.0;
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  s = {};
  s.max_control_points = 8;  // the 3 x 3 grid has 9
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  p.material.areal_density = 0.0;
  EXPECT_THROW(HybridShellDynamics{p}, InputError);
  p.material = testCloth();
  HybridShellDynamics d(p);
  EXPECT_THROW(d.step(-1.0), InputError);
  EXPECT_THROW(d.pin(99), InputError);
  EXPECT_THROW(d.setPositions({}), InputError);
  // A clamp holds an edge: the centre vertex is not on one. Clamped points and their ghosts
  // (appended after the mesh's 9 vertices) cannot be pinned or released.
  p.bc.clamped = {4};
  EXPECT_THROW(HybridShellDynamics{p}, InputError);
  p.bc.clamped = {0, 3, 6};
  HybridShellDynamics clamped(p);
  EXPECT_EQ(clamped.numVertices(), 12);
  EXPECT_TRUE(clamped.isPinned(3) && clamped.isPinned(10));
  EXPECT_THROW(clamped.unpin(3), InputError);
  EXPECT_THROW(clamped.pin(10), InputError);
  EXPECT_NO_THROW(clamped.pin(1));  // the neighbour clamp 0's points follow
  p.bc.pinned = {3};                // clamped and pinned
  EXPECT_THROW(HybridShellDynamics{p}, InputError);
}

}  // namespace
}  // namespace chs
