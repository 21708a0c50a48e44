// Backward Euler grid momentum update of the hybrid shell (Han (3.7)-(3.9) with x* = x^{n+1}):
// statics that agree with the explicit integrator, steps far beyond the explicit stability bound
// that never create energy, free fall, momentum, and bad settings.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_test_material.h"
#include "held_sheet.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

HybridShellSettings backwardEuler(double dt) {
  HybridShellSettings s;
  s.integration = TimeIntegration::kBackwardEuler;
  s.max_time_step = dt;
  return s;
}

using test::HeldSheet;
using test::totalEnergy;

// The hanging sheet's equilibrium does not depend on the integrator: backward Euler at a step
// 16 times the explicit bound settles where the damped explicit run settles, and its pins
// carry the weight.
TEST(HybridShellImplicit, HangingSheetSettlesWhereExplicitDoes) {
  const HeldSheet sheet(true);
  HybridShellSettings se;
  se.damping = 20.0;
  HybridShellDynamics explicit_run(sheet.problem, se);
  const double dt_explicit = explicit_run.stableTimeStep();
  while (explicit_run.time() < 0.6) explicit_run.step(explicit_run.stableTimeStep());

  const double dt = 1.0 / 240.0;
  HybridShellDynamics d(sheet.problem, backwardEuler(dt));
  Vec3 held = Vec3::Zero();
  int samples = 0, unconverged = 0;
  while (d.time() < 0.6 - 1e-9) {
    d.step(d.stableTimeStep());
    if (!d.lastImplicitSolve().converged()) ++unconverged;
    if (d.time() > 0.4) {
      for (const Vec3& f : d.holdingForces(sheet.top)) held += f;
      ++samples;
    }
  }
  double gap = 0.0;
  for (int p = 0; p < d.numVertices(); ++p)
    gap = std::max(gap, (d.positions()[p] - explicit_run.positions()[p]).norm());
  const double weight = d.totalMass() * 9.81, lift = held.z() / samples;
  std::printf(
      "[figure] hanging sheet, backward Euler at dt %.2e s (%.0f x the explicit bound %.2e s): "
      "largest distance to the damped explicit state %.2e m (%.2e dx); pins hold %.3f %% of the "
      "weight; %d unconverged solves (redone explicitly)\n",
      dt, dt / dt_explicit, dt_explicit, gap, gap / d.gridSpacing(), 100 * lift / weight,
      unconverged);
  EXPECT_GT(dt / dt_explicit, 10.0);
  EXPECT_LT(gap, 0.01 * d.gridSpacing());
  EXPECT_NEAR(lift, weight, 1e-3 * weight);
  EXPECT_EQ(unconverged, 0);
}

// A 10 x 2 cm strip (8 x 2 quads, 6.3 mm thick) clamped at x = 0 (ghost faces, the clamped
// points slaved to their neighbours: subdiv/clamped_edges.h) settles under gravity with
// damping at twice its first bending frequency. Backward Euler at 1/240 s and the explicit run
// reach the same tip, and the clamp carries the weight.
TEST(HybridShellImplicit, ClampedCantileverSettlesWhereExplicitDoes) {
  constexpr int nx = 8, ny = 2;
  constexpr double L = 0.1, tau = 6.3e-3;
  DrapeProblem p;
  p.mesh = makeRectangleMesh(L, 0.02, nx, ny, Vec3(0.5 * L, 0.0, 0.0));
  p.material = testCloth(1.375e5, tau, 0.2);
  for (int j = 0; j <= ny; ++j) p.bc.clamped.push_back(j * (nx + 1));
  const double D = 1.375e5 * std::pow(tau, 3) / (12.0 * (1.0 - 0.09));
  const double omega = 3.516 * std::sqrt(D / (0.2 * std::pow(L, 4)));
  const auto settledTip = [&](HybridShellSettings s, double& clamp_load, int& unconverged) {
    s.damping = 2.0 * omega;
    HybridShellDynamics d(p, s);
    while (d.time() < 10.0 / omega) {
      d.step(std::min(d.stableTimeStep(), 10.0 / omega - d.time()));
      if (s.integration == TimeIntegration::kBackwardEuler && !d.lastImplicitSolve().converged())
        ++unconverged;
    }
    // The clamped points, and the pinned ones (the clamp's neighbours, below) share the load.
    std::vector<int> held = p.bc.clamped;
    held.insert(held.end(), p.bc.pinned.begin(), p.bc.pinned.end());
    clamp_load = 0.0;
    for (const Vec3& f : d.holdingForces(held)) clamp_load += f.z();
    clamp_load /= d.totalMass() * 9.81;
    double z = 0.0;
    for (int j = 0; j <= ny; ++j) z += d.positions()[j * (nx + 1) + nx].z();
    return -z / (ny + 1);
  };
  double load_explicit = 0.0, load_implicit = 0.0;
  int unconverged = 0;
  const double tip_explicit = settledTip(HybridShellSettings{}, load_explicit, unconverged);
  const double tip_implicit = settledTip(backwardEuler(1.0 / 240.0), load_implicit, unconverged);
  // The clamped points' neighbours pinned as well: clamp and pins together carry the weight.
  for (int j = 0; j <= ny; ++j) p.bc.pinned.push_back(j * (nx + 1) + 1);
  double load_pinned = 0.0;
  settledTip(backwardEuler(1.0 / 240.0), load_pinned, unconverged);
  std::printf(
      "[figure] clamped cantilever settled: tip control row %.4f mm backward Euler (1/240 s) vs "
      "%.4f mm explicit (ratio %.4f); the clamp carries %.4f / %.4f of the weight, clamp and "
      "pinned neighbours %.4f; %d unconverged solves\n",
      1e3 * tip_implicit, 1e3 * tip_explicit, tip_implicit / tip_explicit, load_implicit,
      load_explicit, load_pinned, unconverged);
  EXPECT_NEAR(tip_implicit / tip_explicit, 1.0, 5e-3);
  EXPECT_NEAR(load_implicit, 1.0, 1e-3);
  EXPECT_NEAR(load_explicit, 1.0, 3e-3);
  EXPECT_NEAR(load_pinned, 1.0, 1e-3);
  EXPECT_EQ(unconverged, 0);
}

// A sheet held along one edge swings down from horizontal. Backward Euler at 1/240 s never gains
// energy (it dissipates); symplectic Euler at the same step diverges.
TEST(HybridShellImplicit, LargeStepsNeverCreateEnergy) {
  const HeldSheet sheet(false);
  const Vec3 g = sheet.problem.gravity;
  const double dt = 1.0 / 240.0;
  HybridShellDynamics d(sheet.problem, backwardEuler(dt));
  const double e0 = totalEnergy(d, g);
  double e_prev = e0, worst_rise = 0.0, lowest = 0.0;
  int steps = 0;
  while (d.time() < 0.5 - 1e-9) {
    d.step(d.stableTimeStep());
    ++steps;
    const double e = totalEnergy(d, g);
    worst_rise = std::max(worst_rise, e - e_prev);
    e_prev = e;
    for (const Vec3& x : d.positions()) lowest = std::min(lowest, x.z());
  }
  // Energy scale: the sheet's weight times its length (the drop of its centre is half that).
  const double scale = d.totalMass() * 9.81 * 0.1;
  std::printf(
      "[figure] swinging sheet, backward Euler dt %.2e s: energy lost %.3e J of scale %.3e J, "
      "largest rise in one step %.2e of the scale, lowest point %.4f m; %d of %d steps redone "
      "explicitly\n",
      dt, e0 - e_prev, scale, worst_rise / scale, lowest, d.implicitFallbacks(), steps);
  EXPECT_LT(worst_rise, 1e-4 * scale);
  EXPECT_LT(lowest, -0.05);  // it did swing down

  HybridShellDynamics se(sheet.problem);
  std::printf("[figure] symplectic Euler bound here %.2e s\n", se.stableTimeStep());
  bool diverged = false;
  for (int i = 0; i < 120 && !diverged; ++i) {
    se.step(dt);
    const double e = totalEnergy(se, g);
    diverged = !std::isfinite(e) || e > e0 + 10.0 * scale;
  }
  EXPECT_TRUE(diverged);
}

// A solve that cannot reach its tolerance (here: one Newton iteration allowed, a tolerance no
// solve meets) is not kept: the step is redone with explicit substeps, so the run follows the
// explicit integrator.
TEST(HybridShellImplicit, UnconvergedStepsAreRedoneExplicitly) {
  const HeldSheet sheet(false);
  HybridShellSettings s = backwardEuler(1.0 / 240.0);
  s.max_newton_iterations = 1;
  s.implicit_tolerance = 1e-14;
  HybridShellDynamics d(sheet.problem, s);
  HybridShellDynamics reference(sheet.problem);
  int steps = 0;
  while (d.time() < 0.1 - 1e-9) {
    d.step(d.stableTimeStep());
    ++steps;
    while (reference.time() < d.time() - 1e-12)
      reference.step(std::min(reference.stableTimeStep(), d.time() - reference.time()));
  }
  double gap = 0.0;
  for (int p = 0; p < d.numVertices(); ++p)
    gap = std::max(gap, (d.positions()[p] - reference.positions()[p]).norm());
  std::printf(
      "[figure] unconverged backward Euler: %d of %d steps redone explicitly; largest distance "
      "to a plain explicit run after 0.1 s %.2e m (%.2e dx)\n",
      d.implicitFallbacks(), steps, gap, gap / d.gridSpacing());
  EXPECT_EQ(d.implicitFallbacks(), steps);
  EXPECT_LT(gap, 1e-3 * d.gridSpacing());
}

// Without internal forces the solve is exact at once: the discrete free fall of symplectic Euler,
// z_n = -g dt^2 n (n + 1) / 2.
TEST(HybridShellImplicit, FreeFallIsExact) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 4, 4);
  p.material = testCloth();
  const double dt = 1.0 / 240.0;
  HybridShellDynamics d(p, backwardEuler(dt));
  const int n = 48;
  for (int i = 0; i < n; ++i) d.step(dt);
  const double expected = -9.81 * dt * dt * n * (n + 1) / 2.0;
  double worst = 0.0;
  for (const Vec3& x : d.positions()) worst = std::max(worst, std::abs(x.z() - expected));
  std::printf("[figure] backward Euler free fall, %d steps: largest error %.2e m of %.4f m\n", n,
              worst, -expected);
  EXPECT_LT(worst, 1e-12);
}

// A curved patch spinning in free flight: internal forces sum to zero at every trial state, so
// linear momentum changes only by the solve's residual.
TEST(HybridShellImplicit, LinearMomentumConservedToTheSolveTolerance) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 6, 6);
  for (auto& x : p.mesh.vertices) x.z() = 2.0 * x.x() * x.x();
  p.material = testCloth();
  p.gravity.setZero();
  HybridShellSettings s = backwardEuler(1.0 / 240.0);
  HybridShellDynamics d(p, s);
  const Vec3 w(0.5, -1.0, 2.0), v0(0.3, 0.1, -0.2);
  std::vector<Vec3> v;
  for (const Vec3& x : d.positions()) v.push_back(v0 + w.cross(x));
  d.setVelocities(v);
  const Vec3 P0 = d.linearMomentum();
  for (int i = 0; i < 60; ++i) d.step(d.stableTimeStep());
  const double dP = (d.linearMomentum() - P0).norm() / P0.norm();
  // Each step's residual is below implicit_tolerance in mass-weighted RMS velocity; summed over
  // the nodes and 60 steps that bounds the drift by about 60 * tolerance / |v0|.
  const double bound = 60.0 * s.implicit_tolerance / v0.norm();
  std::printf(
      "[figure] backward Euler free flight, 60 steps: relative change of linear momentum %.2e "
      "(bound %.1e)\n",
      dP, bound);
  EXPECT_LT(dP, bound);
}

TEST(HybridShellImplicit, RejectsNonsense) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 2, 2);
  p.material = testCloth();
  HybridShellSettings s = backwardEuler(0.0);
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  s = backwardEuler(0.01);
  s.krylov_tolerance = 1.0;
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  s = backwardEuler(0.01);
  s.max_newton_iterations = 0;
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
  s = backwardEuler(0.01);
  s.elastic_max_iterations = 0;
  EXPECT_THROW((HybridShellDynamics{p, s}), InputError);
}

}  // namespace
}  // namespace chs
