// Type (i) elastic-solid particles on the hybrid shell's grid (Han chapter 3 with chapter 5): a
// block and a garment that meet on shared grid nodes. Momentum through a collision in free
// flight, a block resting on a trampoline (the pins carry block and sheet, the block stays above
// the sheet) with symplectic and backward Euler, rollback, and bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// Particles filling the box [lo, hi], `per_cell` per grid cell and axis, at density rho and
// velocity v.
mpm::Particles fillBox(const Vec3& lo, const Vec3& hi, double dx, int per_cell, double rho,
                       const Vec3& v = Vec3::Zero()) {
  const double h = dx / per_cell;
  const Eigen::Vector3i n = ((hi - lo) / h).array().round().cast<int>();
  mpm::Particles p;
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k)
        p.add(lo + h * Vec3(i + 0.5, j + 0.5, k + 0.5), v, rho * h * h * h, h * h * h);
  return p;
}

double lowestZ(const mpm::Particles& p) {
  double z = std::numeric_limits<double>::infinity();
  for (const Vec3& x : p.x) z = std::min(z, x.z());
  return z;
}

// A 10 x 10 x 2 cm foam block (E = 50 kPa, 100 kg/m^3) falls onto an 8 x 8 cm sheet rising
// toward it, off-centre and with a sideways drift, no gravity, no pins, no obstacles. Every
// force in the step is internal (shell, fibre contact and solid stress forces each sum to zero
// over the grid) and APIC's transfers conserve momentum, so the collision may only exchange it.
// The solid's Kirchhoff stress is symmetric and the shell's forces come from a rotation-
// invariant energy, so angular momentum (with APIC's affine part) is conserved as well. The
// block covers the sheet, which stays flat: a sloped sheet leaks momentum by itself (see
// docs/VALIDATION.md, hybrid shell with an elastic solid).
TEST(HybridShellSolid, CollisionConservesMomentum) {
  const double dx = 0.01;
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.08, 0.08, 8, 8, Vec3(0.003, -0.002, 0.0013));
  p.material = testCloth();
  p.gravity.setZero();
  HybridShellSettings s;
  s.grid_spacing = dx;
  HybridShellDynamics d(p, s);
  const Vec3 v_sheet(0.0, 0.1, 0.5), v_block(0.2, 0.0, -0.5);
  d.setVelocities(std::vector<Vec3>(d.numVertices(), v_sheet));
  d.addSolid(fillBox(Vec3(-0.045, -0.052, 0.015), Vec3(0.055, 0.048, 0.035), dx, 2, 100.0, v_block),
             mpm::HenckySolid(5e4, 0.3));
  const Vec3 P0 = d.linearMomentum(), L0 = d.angularMomentum();
  double sheet_mass = 0.0;
  for (double m : d.masses()) sheet_mass += m;
  while (d.time() < 0.04) d.step(d.stableTimeStep());
  Vec3 P_sheet = Vec3::Zero();
  for (int q = 0; q < d.numVertices(); ++q) P_sheet += d.masses()[q] * d.velocities()[q];
  const double dP = (d.linearMomentum() - P0).norm() / P0.norm();
  const double dL = (d.angularMomentum() - L0).norm() / L0.norm();
  std::printf(
      "[figure] block onto sheet, no gravity, %d steps to t = %.3f s: sheet vertical velocity "
      "%+.4f -> %+.4f m/s (the collision reversed it); relative change of linear momentum "
      "%.2e, angular momentum %.2e (tolerance 1e-10 each)\n",
      d.stageTimes().steps, d.time(), v_sheet.z(), P_sheet.z() / sheet_mass, dP, dL);
  EXPECT_LT(P_sheet.z() / sheet_mass, 0.0);
  EXPECT_LT(dP, 1e-10);
  EXPECT_LT(dL, 1e-10);
}

// A 10 x 10 cm sheet of 10 x 10 quads pinned along its edges x = -5 and +5 cm (a trampoline),
// and a 4 x 4 x 2 cm foam block (E = 50 kPa, nu = 0.3, 200 kg/m^3, 256 particles) held 2 cm
// above its middle; dx = 1 cm.
struct Trampoline {
  static constexpr double dx = 0.01, drop = 0.02;
  DrapeProblem problem;
  std::vector<int> pins;
  mpm::Particles block;
  mpm::HenckySolid foam{5e4, 0.3};

  Trampoline() {
    const int n = 10;
    problem.mesh = makeRectangleMesh(0.1, 0.1, n, n);
    problem.material = testCloth();
    for (int j = 0; j <= n; ++j)
      for (int i : {0, n}) pins.push_back(j * (n + 1) + i);
    problem.bc.pinned = pins;
    block = fillBox(Vec3(-0.02, -0.02, drop), Vec3(0.02, 0.02, drop + 0.02), dx, 2, 200.0);
  }
};

// Height of the block's lowest particle above the highest limit-surface sample under the block.
double clearance(const HybridShellDynamics& d) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : d.surfacePoints())
    if (std::abs(x.x()) <= 0.02 && std::abs(x.y()) <= 0.02) top = std::max(top, x.z());
  return lowestZ(d.solidParticles()) - top;
}

struct Settled {
  double held = 0.0, weight = 0.0, least_clearance = 0.0, end_clearance = 0.0, sag = 0.0,
         block_speed = 0.0, dt = 0.0;
  int steps = 0, unconverged = 0, residual_evaluations = 0;
};

// Drops the block, runs until `duration` (damping as set), and averages the pins' vertical force
// over the last 0.2 s; the clearance is sampled every 2 ms.
Settled settle(HybridShellDynamics& d, const Trampoline& t, double duration) {
  Settled r;
  double sum = 0.0;
  int samples = 0;
  r.least_clearance = std::numeric_limits<double>::infinity();
  double next_check = 0.0;
  while (d.time() < duration - 1e-9) {
    r.dt = std::max(r.dt, d.stableTimeStep());
    d.step(std::min(d.stableTimeStep(), duration - d.time()));
    ++r.steps;
    if (d.settings().integration == TimeIntegration::kBackwardEuler) {
      if (!d.lastImplicitSolve().converged()) {
        ++r.unconverged;
        std::printf("unconverged solve at t = %.4f s: %s\n", d.time(),
                    d.lastImplicitSolve().describe().c_str());
      }
      r.residual_evaluations += d.lastImplicitSolve().residual_evaluations;
    }
    if (d.time() >= next_check) {
      r.least_clearance = std::min(r.least_clearance, clearance(d));
      next_check += 0.002;
    }
    if (d.time() > duration - 0.2) {
      for (const Vec3& f : d.holdingForces(t.pins)) sum += f.z();
      ++samples;
    }
  }
  r.held = sum / samples;
  r.weight = d.totalMass() * 9.81;
  r.end_clearance = clearance(d);
  const int centre = 5 * 11 + 5;
  r.sag = -d.positions()[centre].z();
  for (const Vec3& v : d.solidParticles().v) r.block_speed = std::max(r.block_speed, v.norm());
  return r;
}

// Static balance of the whole: sum of pin forces = (sheet + block) g; the block rests on the
// sheet instead of sinking through it. The shared nodes keep the two a kernel reach apart, so
// the block rests about a cell above the sheet (Han's visible separation of grid contact).
void checkTrampoline(const char* name, const Settled& r) {
  std::printf(
      "[figure] trampoline, %s (%d steps, dt up to %.2e s): pins hold %.6f N, weight of sheet "
      "and block %.6f N (error %+.3f %%, tolerance 0.5 %%); sheet centre sag %.2f mm; block's "
      "lowest particle above the sheet by %.2f mm at least during the run (%.2f dx), %.2f mm "
      "at the end (tolerance > -0.25 dx); block speed at the end %.1e m/s\n",
      name, r.steps, r.dt, r.held, r.weight, 100.0 * (r.held - r.weight) / r.weight, 1e3 * r.sag,
      1e3 * r.least_clearance, r.least_clearance / Trampoline::dx, 1e3 * r.end_clearance,
      r.block_speed);
  EXPECT_NEAR(r.held, r.weight, 5e-3 * r.weight);
  EXPECT_GT(r.least_clearance, -0.25 * Trampoline::dx);
  EXPECT_GT(r.end_clearance, -0.25 * Trampoline::dx);
}

TEST(HybridShellSolid, BlockRestsOnTrampoline) {
  Trampoline t;
  HybridShellSettings s;
  s.grid_spacing = Trampoline::dx;
  s.damping = 40.0;
  HybridShellDynamics d(t.problem, s);
  d.addSolid(t.block, t.foam);
  checkTrampoline("symplectic Euler", settle(d, t, 1.0));
}

TEST(HybridShellSolid, BlockRestsOnTrampolineBackwardEuler) {
  Trampoline t;
  HybridShellSettings se;
  se.grid_spacing = Trampoline::dx;
  HybridShellDynamics explicit_shell(t.problem, se);
  explicit_shell.addSolid(t.block, t.foam);
  const double dt_explicit = explicit_shell.stableTimeStep();

  HybridShellSettings s = se;
  s.damping = 40.0;
  s.integration = TimeIntegration::kBackwardEuler;
  s.max_time_step = 1.0 / 240.0;
  HybridShellDynamics d(t.problem, s);
  d.addSolid(t.block, t.foam);
  const Settled r = settle(d, t, 0.9);
  std::printf(
      "[figure] trampoline, backward Euler at dt %.2e s = %.1f x the explicit bound %.2e s; "
      "%d of %d solves unconverged, %.0f residual evaluations per step\n",
      r.dt, r.dt / dt_explicit, dt_explicit, r.unconverged, r.steps,
      double(r.residual_evaluations) / r.steps);
  EXPECT_GT(r.dt, 4.0 * dt_explicit);
  checkTrampoline("backward Euler", r);
}

// Rollback restores the solid's particles with the shell's state.
TEST(HybridShellSolid, RestoreRollsTheSolidBack) {
  Trampoline t;
  HybridShellSettings s;
  s.grid_spacing = Trampoline::dx;
  HybridShellDynamics d(t.problem, s);
  d.addSolid(t.block, t.foam);
  for (int i = 0; i < 5; ++i) d.step(d.stableTimeStep());
  const auto snap = d.snapshot();
  const mpm::Particles saved = d.solidParticles();
  const Vec3 P = d.linearMomentum();
  for (int i = 0; i < 20; ++i) d.step(d.stableTimeStep());
  d.restore(*snap);
  double worst = 0.0;
  for (int p = 0; p < saved.size(); ++p)
    worst = std::max({worst, (d.solidParticles().x[p] - saved.x[p]).norm(),
                      (d.solidParticles().v[p] - saved.v[p]).norm(),
                      (d.solidParticles().F[p] - saved.F[p]).norm()});
  std::printf("[figure] restore: largest difference of solid x, v, F from the snapshot %.1e\n",
              worst);
  EXPECT_EQ(worst, 0.0);
  EXPECT_EQ((d.linearMomentum() - P).norm(), 0.0);
}

TEST(HybridShellSolid, RejectsBadSolids) {
  Trampoline t;
  HybridShellDynamics d(t.problem);
  auto rejects = [&](mpm::Particles p, const char* what) {
    try {
      d.addSolid(std::move(p), t.foam);
      ADD_FAILURE() << what << " accepted";
    } catch (const InputError& e) {
      std::printf("%s: %s\n", what, e.what());
    }
  };
  mpm::Particles bad = t.block;
  bad.x[3].y() = std::numeric_limits<double>::quiet_NaN();
  rejects(bad, "NaN position");
  bad = t.block;
  bad.mass[7] = 0.0;
  rejects(bad, "zero mass");
  bad = t.block;
  bad.volume0[7] = -1e-9;
  rejects(bad, "negative volume");
  bad = t.block;
  bad.F.pop_back();
  rejects(bad, "mismatched sizes");
  bad = t.block;
  bad.F[0](2, 2) = -1.0;
  rejects(bad, "inverted F");
  rejects(mpm::Particles{}, "no particles");
  EXPECT_EQ(d.solidParticles().size(), 0);
  d.addSolid(t.block, t.foam);
  rejects(t.block, "second solid");
}

}  // namespace
}  // namespace chs
