// The Lagrangian implicit step of the hybrid shell (Han's split, sections 4.2 and 6.1.1, applied
// to the shell of chapter 5): backward Euler of the Kirchhoff-Love elasticity in the control
// points with an assembled projected Hessian (shell/implicit_elasticity.h), then the grid for
// contact only. Its Hessian against differences of the energy, statics that agree with the
// explicit integrator, steps far beyond the explicit bound that never create energy, the
// swinging sheet's numerical damping against the explicit step, free fall, momenta.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/bdf2.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/shell/implicit_elasticity.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"
#include "cloth_test_material.h"
#include "held_sheet.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

HybridShellSettings lagrangian(double dt) {
  HybridShellSettings s;
  s.integration = TimeIntegration::kLagrangianImplicit;
  s.max_time_step = dt;
  return s;
}

using test::HeldSheet;
using test::totalEnergy;

// Each fibre's Hessian in its stencil sums is the energy's second derivative (on a stretched, bent
// patch): central differences of the energy along random directions agree to 1e-5.
TEST(HybridShellLagrangian, FibreHessianIsTheEnergysSecondDerivative) {
  QuadMesh mesh = makeRectangleMesh(0.1, 0.1, 4, 4);
  const LimitSurface surface(mesh);
  const auto points = buildKirchhoffLovePoints(
      static_cast<int>(mesh.quads.size()),
      [&](int f, double u, double v) { return surface.stencil(f, u, v); }, mesh.vertices, 1e-3);
  std::vector<Vec3> x = mesh.vertices;
  for (auto& p : x) p = Vec3(1.03 * p.x(), 1.02 * p.y(), 3.0 * p.x() * p.x());
  const HenckyLamina material(1e6, 0.3);
  const std::vector<FibreRange> fibres = fibreRanges(points);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  double worst = 0.0;
  int checked = 0;
  for (std::size_t f = 0; f < fibres.size(); f += 7) {
    const StencilSums s = MidSurfaceFrame::sums(points[fibres[f].first].stencil(), x);
    const FibreHessian H = fibreHessian(points, fibres[f], material, s);
    Eigen::Matrix<double, 15, 1> d;
    for (int i = 0; i < 15; ++i) d(i) = normal(rng);
    double scale = 0.0;
    for (const auto& v : s) scale = std::max(scale, v.norm());
    const double h = 1e-4 * scale;
    auto energy = [&](double t) {
      StencilSums st = s;
      for (int a = 0; a < 5; ++a) st[a] += t * d.segment<3>(3 * a);
      return fibreEnergy(points, fibres[f], material, st);
    };
    const double second = (energy(h) - 2.0 * energy(0.0) + energy(-h)) / (h * h);
    const double quadratic = d.dot(H * d);
    worst = std::max(worst, std::abs(second - quadratic) / std::abs(quadratic));
    ++checked;
  }
  std::printf(
      "[figure] fibre Hessian against central differences of the energy: %d fibres, worst "
      "relative error %.2e\n",
      checked, worst);
  EXPECT_GT(checked, 3);
  EXPECT_LT(worst, 1e-5);
}

// The closed-form fibre Hessian (before the projection) against central differences of the exact
// gradient in the sums, fibre by fibre, in states that reach every term: at rest (C = I exactly,
// the Hencky tangent's isotropic limit), stretched, compressed into ripples (indefinite),
// sheared, bent up, bent down and twisted, wrapped on a tight cylinder, rough; each also under a
// plastic map F^P != I. Errors are measured on the Hessian in sums scaled to their size (the
// difference steps), overall and on the curvature block (a_{alpha,beta}), which is smaller by
// (thickness / cell)^2.
TEST(HybridShellLagrangian, FibreHessianIsExactInEveryState) {
  const QuadMesh mesh = makeRectangleMesh(0.1, 0.1, 4, 4);
  const LimitSurface surface(mesh);
  const std::vector<KirchhoffLovePoint> elastic = buildKirchhoffLovePoints(
      static_cast<int>(mesh.quads.size()),
      [&](int f, double u, double v) { return surface.stencil(f, u, v); }, mesh.vertices, 2e-3);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<KirchhoffLovePoint> plastic = elastic;
  for (KirchhoffLovePoint& p : plastic) {
    Eigen::Matrix3d F_p = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F_p(i, j) += 0.15 * uniform(rng);
    p.setPlasticDeformation(F_p);
  }
  std::vector<std::vector<Vec3>> states(8, mesh.vertices);
  for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
    const Vec3& X = mesh.vertices[k];
    states[1][k] = Vec3(1.1 * X.x(), 1.04 * X.y(), 0.0);
    states[2][k] = Vec3(0.9 * X.x(), 0.97 * X.y(), 2e-3 * std::sin(60.0 * X.x() + 20.0 * X.y()));
    states[3][k] = Vec3(X.x() + 0.3 * X.y(), X.y(), 0.0);
    states[4][k] = Vec3(X.x(), X.y(), 4.0 * X.x() * X.x());
    states[5][k] = Vec3(X.x(), X.y(), -6.0 * X.y() * X.y() + 5.0 * X.x() * X.y());
    const double R = 0.05;
    states[6][k] = Vec3(R * std::sin(X.x() / R), 1.02 * X.y(), R * std::cos(X.x() / R));
    states[7][k] = X + 2e-3 * Vec3(uniform(rng), uniform(rng), uniform(rng));
  }
  const HenckyLamina material(1e6, 0.3);
  const std::vector<FibreRange> fibres = fibreRanges(elastic);
  double worst = 0.0, worst_curvature = 0.0, worst_projected = 0.0;
  int checked = 0, indefinite = 0, semidefinite = 0, changed_semidefinite = 0, projected = 0;
  for (const std::vector<KirchhoffLovePoint>* points : {&elastic, &std::as_const(plastic)}) {
    for (const std::vector<Vec3>& x : states) {
      for (const FibreRange& fibre : fibres) {
        const StencilSums s = MidSurfaceFrame::sums((*points)[fibre.first].stencil(), x);
        const FibreHessian H = fibreHessian(*points, fibre, material, s);
        FibreHessian reference;
        Eigen::Matrix<double, 15, 1> scale;
        for (int a = 0; a < 5; ++a) {
          scale.segment<3>(3 * a).setConstant(std::max({s[a].norm(), s[0].norm(), s[1].norm()}));
          const double h = 1e-6 * scale(3 * a);
          for (int i = 0; i < 3; ++i) {
            StencilSums plus = s, minus = s, g_plus, g_minus;
            plus[a][i] += h;
            minus[a][i] -= h;
            fibreEnergy(*points, fibre, material, plus, &g_plus);
            fibreEnergy(*points, fibre, material, minus, &g_minus);
            for (int b = 0; b < 5; ++b)
              reference.block<3, 1>(3 * b, 3 * a + i) = (g_plus[b] - g_minus[b]) / (2.0 * h);
          }
        }
        const FibreHessian error = scale.asDiagonal() * (H - reference) * scale.asDiagonal();
        const FibreHessian scaled = scale.asDiagonal() * reference * scale.asDiagonal();
        worst = std::max(worst, error.norm() / scaled.norm());
        worst_curvature = std::max(worst_curvature, error.bottomRightCorner<9, 9>().norm() /
                                                        scaled.bottomRightCorner<9, 9>().norm());
        const double lowest =
            Eigen::SelfAdjointEigenSolver<FibreHessian>(scaled, Eigen::EigenvaluesOnly)
                .eigenvalues()(0);
        if (lowest < -1e-6 * scaled.norm()) ++indefinite;
        ++checked;
        // The implicit step's matrix: the exact Hessian where that is positive semidefinite,
        // elsewhere its Gauss-Newton form, positive semidefinite by construction.
        const FibreHessian P = projectedFibreHessian(*points, fibre, material, s);
        if (lowest >= -1e-12 * scaled.norm()) {
          ++semidefinite;
          if (P != H) ++changed_semidefinite;
        } else if (P != H) {
          ++projected;
          const double lowest_P =
              Eigen::SelfAdjointEigenSolver<FibreHessian>(P, Eigen::EigenvaluesOnly)
                  .eigenvalues()(0);
          worst_projected = std::min(worst_projected, lowest_P / P.norm());
        }
      }
    }
  }
  std::printf(
      "[figure] closed-form fibre Hessian against central differences of the gradient: %d fibres "
      "(%d indefinite), worst relative error %.2e (curvature block %.2e)\n",
      checked, indefinite, worst, worst_curvature);
  std::printf(
      "[figure] projected fibre Hessian: %d positive semidefinite fibres kept exact (%d "
      "changed); %d indefinite ones in Gauss-Newton form, lowest eigenvalue over the norm %.2e "
      "at worst\n",
      semidefinite, changed_semidefinite, projected, worst_projected);
  EXPECT_GT(indefinite, 10);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_curvature, 1e-6);
  EXPECT_GT(semidefinite, 10);
  // The pivoted LDL^T that picks them also sends a few semidefinite fibres whose zero modes
  // round to a negative pivot to the Gauss-Newton form.
  EXPECT_LE(4 * changed_semidefinite, semidefinite);
  EXPECT_GT(projected, 10);
  EXPECT_GT(worst_projected, -1e-12);
}

// The hanging sheet's equilibrium does not depend on the integrator: the Lagrangian implicit step
// at 1/60 s (far beyond the explicit bound) settles where the damped explicit run settles, and
// its pins carry the weight.
TEST(HybridShellLagrangian, HangingSheetSettlesWhereExplicitDoes) {
  const HeldSheet sheet(true);
  HybridShellSettings se;
  se.damping = 20.0;
  HybridShellDynamics explicit_run(sheet.problem, se);
  const double dt_explicit = explicit_run.stableTimeStep();
  while (explicit_run.time() < 0.6) explicit_run.step(explicit_run.stableTimeStep());

  const double dt = 1.0 / 60.0;
  HybridShellSettings s = lagrangian(dt);
  s.damping = 20.0;
  HybridShellDynamics d(sheet.problem, s);
  Vec3 held = Vec3::Zero();
  int samples = 0, unconverged = 0, factorizations = 0, iterations = 0, steps = 0;
  while (d.time() < 1.2 - 1e-9) {
    d.step(d.stableTimeStep());
    ++steps;
    if (!d.lastElasticSolve().converged) ++unconverged;
    factorizations += d.lastElasticSolve().factorizations;
    iterations += d.lastElasticSolve().iterations;
    if (d.time() > 1.0) {
      for (const Vec3& f : d.holdingForces(sheet.top)) held += f;
      ++samples;
    }
  }
  double gap = 0.0;
  for (int p = 0; p < d.numVertices(); ++p)
    gap = std::max(gap, (d.positions()[p] - explicit_run.positions()[p]).norm());
  const double weight = d.totalMass() * 9.81, lift = held.z() / samples;
  std::printf(
      "[figure] hanging sheet, Lagrangian implicit at dt %.2e s (%.0f x the explicit bound %.2e "
      "s): largest distance to the damped explicit state %.2e m (%.2e dx); pins hold %.3f %% of "
      "the weight; %d steps, %.2f Newton iterations and %.2f factorisations per step, %d "
      "unconverged\n",
      dt, dt / dt_explicit, dt_explicit, gap, gap / d.gridSpacing(), 100 * lift / weight, steps,
      double(iterations) / steps, double(factorizations) / steps, unconverged);
  EXPECT_GT(dt / dt_explicit, 40.0);
  EXPECT_LT(gap, 0.01 * d.gridSpacing());
  EXPECT_NEAR(lift, weight, 1e-3 * weight);
  EXPECT_EQ(unconverged, 0);
}

// A 10 x 2 cm strip clamped at x = 0 (ghost faces, the clamped points slaved to their interior
// neighbours) settles under gravity where the explicit run does, and the clamp carries the
// weight: the slaving enters the Hessian as J^T H J.
TEST(HybridShellLagrangian, ClampedCantileverSettlesWhereExplicitDoes) {
  constexpr int nx = 8, ny = 2;
  constexpr double L = 0.1, tau = 6.3e-3;
  DrapeProblem p;
  p.mesh = makeRectangleMesh(L, 0.02, nx, ny, Vec3(0.5 * L, 0.0, 0.0));
  p.material = testCloth(1.375e5, tau, 0.2);
  for (int j = 0; j <= ny; ++j) p.bc.clamped.push_back(j * (nx + 1));
  const double D = 1.375e5 * std::pow(tau, 3) / (12.0 * (1.0 - 0.09));
  const double omega = 3.516 * std::sqrt(D / (0.2 * std::pow(L, 4)));
  const auto settledTip = [&](HybridShellSettings s, double& clamp_load) {
    s.damping = 2.0 * omega;
    HybridShellDynamics d(p, s);
    while (d.time() < 10.0 / omega) d.step(std::min(d.stableTimeStep(), 10.0 / omega - d.time()));
    clamp_load = 0.0;
    for (const Vec3& f : d.holdingForces(p.bc.clamped)) clamp_load += f.z();
    clamp_load /= d.totalMass() * 9.81;
    double z = 0.0;
    for (int j = 0; j <= ny; ++j) z += d.positions()[j * (nx + 1) + nx].z();
    return -z / (ny + 1);
  };
  double load_explicit = 0.0, load_implicit = 0.0;
  const double tip_explicit = settledTip(HybridShellSettings{}, load_explicit);
  const double tip_implicit = settledTip(lagrangian(1.0 / 240.0), load_implicit);
  std::printf(
      "[figure] clamped cantilever settled: tip control row %.4f mm Lagrangian implicit (1/240 "
      "s) vs %.4f mm explicit (ratio %.4f); the clamp carries %.4f / %.4f of the weight\n",
      1e3 * tip_implicit, 1e3 * tip_explicit, tip_implicit / tip_explicit, load_implicit,
      load_explicit);
  EXPECT_NEAR(tip_implicit / tip_explicit, 1.0, 5e-3);
  EXPECT_NEAR(load_implicit, 1.0, 3e-3);
}

// Swing angle of the free edge about the held edge (x = 0 side held, the sheet swings in xz).
double swingAngle(const HybridShellDynamics& d, int n) {
  Vec3 free = Vec3::Zero();
  for (int i = 0; i <= n; ++i) free += d.positions()[i];
  free /= n + 1;
  return std::atan2(free.y() - 0.05, -free.z());
}

struct Swing {
  std::vector<double> peaks;  // |angle| at successive turning points
  double worst_rise = 0.0, energy_lost = 0.0;
  double scale = 0.0;  // weight times the sheet's length [J]
};

Swing swing(const HeldSheet& sheet, const HybridShellSettings& s, double duration, double dt) {
  HybridShellDynamics d(sheet.problem, s);
  const Vec3 g = sheet.problem.gravity;
  const double e0 = totalEnergy(d, g);
  double e_prev = e0;
  Swing out;
  out.scale = d.totalMass() * 9.81 * 0.1;
  double a_prev = swingAngle(d, 8), da_prev = 0.0;
  while (d.time() < duration - 1e-9) {
    d.step(dt > 0.0 ? dt : d.stableTimeStep());
    const double e = totalEnergy(d, g);
    out.worst_rise = std::max(out.worst_rise, e - e_prev);
    e_prev = e;
    const double a = swingAngle(d, 8), da = a - a_prev;
    if (da_prev != 0.0 && (da > 0.0) != (da_prev > 0.0)) out.peaks.push_back(std::abs(a_prev));
    a_prev = a;
    da_prev = da;
  }
  out.energy_lost = e0 - e_prev;
  return out;
}

// A sheet held along one edge swings down from horizontal as a pendulum. The Lagrangian implicit
// step at 1/240 s never gains energy. Its numerical damping, the loss of swing amplitude from one
// turning point to the next, is printed beside the explicit step's (whose APIC transfers lose
// some too): backward Euler's own share is about 1 - (1 + (omega dt)^2)^(-N/2) per swing of N
// steps. With the transfer back keeping the elastic velocity where the grid stage changed
// nothing (flip_blend 1, the lone sheet's fibres out of contact: the defaults since 2026-12-07)
// backward Euler stays within the 10 % per swing of the explicit step, and BDF2 below
// it; the grid's velocity alone (flip_blend 0) averaged a third more away.
TEST(HybridShellLagrangian, SwingingSheetDampsLittleAndNeverGainsEnergy) {
  const HeldSheet sheet(false);
  const double dt = 1.0 / 240.0;
  const Swing implicit_swing = swing(sheet, lagrangian(dt), 1.5, dt);
  HybridShellSettings bdf2 = lagrangian(dt);
  bdf2.integration = TimeIntegration::kLagrangianBdf2;
  const Swing bdf2_swing = swing(sheet, bdf2, 1.5, dt);
  const Swing explicit_swing = swing(sheet, HybridShellSettings{}, 1.5, 0.0);
  HybridShellSettings pic = lagrangian(dt);
  pic.flip_blend = 0.0;
  pic.contact_between_layers_only = false;
  const Swing pic_swing = swing(sheet, pic, 1.5, dt);
  pic.integration = TimeIntegration::kLagrangianBdf2;
  const Swing pic_bdf2_swing = swing(sheet, pic, 1.5, dt);
  auto decay = [](const Swing& s) {
    // Mean loss per half swing over the recorded turning points, per full swing.
    if (s.peaks.size() < 2) return 1.0;
    const double r = std::pow(s.peaks.back() / s.peaks.front(), 1.0 / (s.peaks.size() - 1));
    return 1.0 - r * r;
  };
  std::printf(
      "[figure] swinging sheet, 1.5 s: Lagrangian implicit dt %.2e s: %zu turning points, "
      "amplitude loss %.2f %% per swing, largest energy rise in a step %.2e J; explicit: %zu "
      "turning points, %.2f %% per swing\n",
      dt, implicit_swing.peaks.size(), 100.0 * decay(implicit_swing), implicit_swing.worst_rise,
      explicit_swing.peaks.size(), 100.0 * decay(explicit_swing));
  std::printf(
      "[figure] swinging sheet, 1.5 s: Lagrangian BDF2 dt %.2e s: %zu turning points, amplitude "
      "loss %.2f %% per swing, largest energy rise in a step %.2e J (%.1e of m g L)\n",
      dt, bdf2_swing.peaks.size(), 100.0 * decay(bdf2_swing), bdf2_swing.worst_rise,
      bdf2_swing.worst_rise / bdf2_swing.scale);
  std::printf(
      "[figure] swinging sheet, the grid's velocity alone (flip_blend 0, fibres on every layer): "
      "amplitude loss %.2f %% per swing (backward Euler), %.2f %% (BDF2); largest energy rise in "
      "a step %.2e J\n",
      100.0 * decay(pic_swing), 100.0 * decay(pic_bdf2_swing), pic_swing.worst_rise);
  ASSERT_GE(implicit_swing.peaks.size(), 2u);
  EXPECT_LT(implicit_swing.worst_rise, 1e-4 * implicit_swing.scale);
  EXPECT_GT(decay(implicit_swing), decay(explicit_swing));  // backward Euler does damp
  EXPECT_LT(decay(implicit_swing), decay(explicit_swing) + 0.10);
  EXPECT_LT(decay(implicit_swing), decay(pic_swing) - 0.01);
  // BDF2: not monotone in energy, but never by much.
  ASSERT_GE(bdf2_swing.peaks.size(), 2u);
  EXPECT_LT(decay(bdf2_swing), decay(explicit_swing));
  EXPECT_LT(decay(bdf2_swing), decay(implicit_swing) - 0.05);
  EXPECT_LT(bdf2_swing.worst_rise, 1e-2 * bdf2_swing.scale);
  ASSERT_GE(pic_swing.peaks.size(), 2u);
  EXPECT_LT(pic_swing.worst_rise, 1e-4 * pic_swing.scale);
}

// The solves' stop at a share of gravity's velocity in the step (lagrangian_gravity_fraction):
// the sheet swinging down at 1/60 s stops each elastic solve below 0.004 |g| dt = 6.5e-4 m/s
// instead of 1e-4 m/s, on fewer factorisations, and swings as the tighter solves do: the
// residual is a force, 0.4 % of the weight, against the motion's own.
TEST(HybridShellLagrangian, SolvesStopAtAShareOfGravitysVelocity) {
  const HeldSheet sheet(false);
  const double dt = 1.0 / 60.0, g = 9.81;
  struct Run {
    std::vector<Vec3> x;
    double largest_residual = 0.0;
    int factorizations = 0;
    bool converged = true;
  };
  auto run = [&](double fraction) {
    HybridShellSettings s = lagrangian(dt);
    s.lagrangian_gravity_fraction = fraction;
    s.elastic_max_iterations = 16;
    HybridShellDynamics d(sheet.problem, s);
    Run r;
    while (d.time() < 1.0 - 1e-9) {
      d.step(d.stableTimeStep());
      const ImplicitElasticityResult& e = d.lastElasticSolve();
      r.largest_residual = std::max(r.largest_residual, e.residual);
      r.factorizations += e.factorizations;
      r.converged = r.converged && e.converged;
    }
    r.x = d.positions();
    return r;
  };
  const Run tight = run(0.0), weighted = run(0.004);
  double gap = 0.0;
  for (std::size_t p = 0; p < tight.x.size(); ++p)
    gap = std::max(gap, (tight.x[p] - weighted.x[p]).norm());
  std::printf(
      "[figure] sheet swinging down 1 s at 1/60 s: elastic solves stopped at 1e-4 m/s: largest "
      "residual %.2e m/s, %d factorisations; at 0.004 |g| dt = %.2e m/s: %.2e m/s, %d; largest "
      "distance between the two end states %.2e m (sheet 0.1 m)\n",
      tight.largest_residual, tight.factorizations, 0.004 * g * dt, weighted.largest_residual,
      weighted.factorizations, gap);
  EXPECT_TRUE(tight.converged);
  EXPECT_TRUE(weighted.converged);
  EXPECT_LT(tight.largest_residual, 1e-4);
  EXPECT_LT(weighted.largest_residual, 0.004 * g * dt);
  EXPECT_LT(weighted.factorizations, tight.factorizations);
  EXPECT_LT(gap, 1e-3);
}

// The variable-step BDF2 formula (bdf2.h) differentiates a quadratic exactly, whatever the ratio
// of its two steps; without a previous step it is backward Euler.
TEST(HybridShellLagrangian, Bdf2CoefficientsDifferentiateQuadraticsExactly) {
  auto y = [](double t) { return 3.0 + 2.0 * t - 5.0 * t * t; };
  double worst = 0.0;
  for (double ratio : {0.5, 1.0, 1.7, 3.0}) {
    const double h0 = 0.01, h1 = ratio * h0, t1 = 0.2, t2 = t1 + h1;
    const Bdf2Coefficients c = bdf2Coefficients(h1, h0);
    const double derivative = (c.a0 * y(t2) + c.a1 * y(t1) + c.a2 * y(t1 - h0)) / h1;
    worst = std::max(worst, std::abs(derivative - (2.0 - 10.0 * t2)));
  }
  std::printf("[figure] BDF2 on y = 3 + 2t - 5t^2, step ratios 0.5-3: largest error of y' %.1e\n",
              worst);
  EXPECT_LT(worst, 1e-10);
  const Bdf2Coefficients first = bdf2Coefficients(0.01, 0.0);
  EXPECT_EQ(first.a0, 1.0);
  EXPECT_EQ(first.a1, -1.0);
  EXPECT_EQ(first.a2, 0.0);
}

// BDF2 changes the dynamics, not the statics or the conservation laws: the damped hanging sheet
// at 1/60 s settles where backward Euler's does, and a free, spinning, curved sheet keeps its
// linear momentum to the solves' tolerance.
TEST(HybridShellLagrangian, Bdf2SettlesWhereBackwardEulerDoesAndKeepsMomentum) {
  const HeldSheet sheet(true);
  auto settle = [&](TimeIntegration integration) {
    HybridShellSettings s = lagrangian(1.0 / 60.0);
    s.integration = integration;
    s.damping = 20.0;
    HybridShellDynamics d(sheet.problem, s);
    while (d.time() < 1.2 - 1e-9) d.step(d.stableTimeStep());
    return d.positions();
  };
  const std::vector<Vec3> be = settle(TimeIntegration::kLagrangianImplicit);
  const std::vector<Vec3> bdf2 = settle(TimeIntegration::kLagrangianBdf2);
  double gap = 0.0;
  for (std::size_t p = 0; p < be.size(); ++p) gap = std::max(gap, (be[p] - bdf2[p]).norm());

  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 6, 6);
  for (auto& x : p.mesh.vertices) x.z() = 2.0 * x.x() * x.x();
  p.material = testCloth();
  p.gravity.setZero();
  HybridShellSettings s = lagrangian(1.0 / 240.0);
  s.integration = TimeIntegration::kLagrangianBdf2;
  HybridShellDynamics d(p, s);
  const Vec3 w(0.5, -1.0, 2.0), v0(0.3, 0.1, -0.2);
  std::vector<Vec3> v;
  for (const Vec3& x : d.positions()) v.push_back(v0 + w.cross(x));
  d.setVelocities(v);
  const Vec3 P0 = d.linearMomentum();
  while (d.time() < 0.25 - 1e-9) d.step(std::min(d.stableTimeStep(), 0.25 - d.time()));
  const double dP = (d.linearMomentum() - P0).norm() / P0.norm();
  const double bound = 60.0 * s.lagrangian_tolerance / v0.norm();
  std::printf(
      "[figure] BDF2: hanging sheet settled 1.2 s at 1/60 s, largest distance to backward "
      "Euler's state %.2e m; free flight 0.25 s, linear momentum change %.2e (bound %.1e)\n",
      gap, dP, bound);
  EXPECT_LT(gap, 1e-5);
  EXPECT_LT(dP, bound);
}

// The elastic solve's path must not change its answer: the sheet swinging down from horizontal
// (large rotations, a factor that goes stale every few steps) with L-BFGS pairs on the kept
// factor, with plain chord iterations on it, and with a fresh factorisation every iteration
// reaches the same states to within the tolerance's reach, on no more factorisations. (At this
// tolerance the kept factor's iterations stall, which turns the solves to Newton: the pairs'
// saving, 74 -> 60 of fresh Newton's 306 on the projected matrix, is now within a few.)
TEST(HybridShellLagrangian, LbfgsOnTheKeptFactorReachesTheSameStates) {
  const HeldSheet sheet(false);
  const double dt = 1.0 / 240.0;
  struct Run {
    std::vector<Vec3> x;
    int factorizations = 0, iterations = 0;
  };
  auto run = [&](bool reuse, int history) {
    HybridShellSettings s = lagrangian(dt);
    s.lagrangian_tolerance = 1e-9;
    s.lagrangian_gravity_fraction = 0.0;
    s.elastic_max_iterations = 40;
    s.reuse_factorization = reuse;
    s.elastic_history = history;
    HybridShellDynamics d(sheet.problem, s);
    Run r;
    for (int i = 0; i < 60; ++i) {
      d.step(dt);
      EXPECT_TRUE(d.lastElasticSolve().converged) << "step " << i;
      r.factorizations += d.lastElasticSolve().factorizations;
      r.iterations += d.lastElasticSolve().iterations;
    }
    r.x = d.positions();
    return r;
  };
  const Run fresh = run(false, 0), chord = run(true, 0), lbfgs = run(true, 8);
  auto distance = [&](const Run& r) {
    double worst = 0.0;
    for (std::size_t p = 0; p < r.x.size(); ++p)
      worst = std::max(worst, (r.x[p] - fresh.x[p]).norm());
    return worst;
  };
  std::printf(
      "[figure] swinging sheet, 60 steps of 1/240 s, tolerance 1e-9 m/s: factorisations / Newton "
      "iterations: fresh Newton %d / %d, chord %d / %d, L-BFGS (8 pairs) %d / %d; largest "
      "distance to fresh Newton's state: chord %.2e m, L-BFGS %.2e m\n",
      fresh.factorizations, fresh.iterations, chord.factorizations, chord.iterations,
      lbfgs.factorizations, lbfgs.iterations, distance(chord), distance(lbfgs));
  EXPECT_LT(distance(chord), 1e-7);
  EXPECT_LT(distance(lbfgs), 1e-7);
  EXPECT_LE(lbfgs.factorizations, fresh.factorizations);
  EXPECT_LE(chord.factorizations, fresh.factorizations);
}

// Without internal forces the elastic stage is exact at once: the discrete free fall of
// symplectic Euler, z_n = -g dt^2 n (n + 1) / 2.
TEST(HybridShellLagrangian, FreeFallIsExact) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 4, 4);
  p.material = testCloth();
  const double dt = 1.0 / 240.0;
  HybridShellDynamics d(p, lagrangian(dt));
  const int n = 48;
  for (int i = 0; i < n; ++i) d.step(dt);
  const double expected = -9.81 * dt * dt * n * (n + 1) / 2.0;
  double worst = 0.0;
  for (const Vec3& x : d.positions()) worst = std::max(worst, std::abs(x.z() - expected));
  std::printf("[figure] Lagrangian implicit free fall, %d steps: largest error %.2e m of %.4f m\n",
              n, worst, -expected);
  EXPECT_LT(worst, 1e-12);
}

// A curved patch spinning in free flight: the elastic forces sum to zero and the grid, with
// nothing to touch, hands back no change, so linear momentum changes only by the solve's
// residual. Backward Euler is not a symplectic map: the spin's angular momentum drifts, and
// the figure is printed against the explicit step's. Where the grid changes nothing, the
// Lagrangian step's transfer back keeps the control points' own velocities (flip_blend 1), so
// theirs, sum x m v, is the angular momentum it carries; APIC's (with the affine velocities'
// spin, which the explicit step conserves) is printed beside it.
TEST(HybridShellLagrangian, MomentaInFreeFlight) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 6, 6);
  for (auto& x : p.mesh.vertices) x.z() = 2.0 * x.x() * x.x();
  p.material = testCloth();
  p.gravity.setZero();
  const Vec3 w(0.5, -1.0, 2.0), v0(0.3, 0.1, -0.2);
  int most_evaluations = 0;  // of a contact solve
  auto controlPointSpin = [](const HybridShellDynamics& d) {
    Vec3 L = Vec3::Zero();
    for (std::size_t i = 0; i < d.positions().size(); ++i)
      L += d.masses()[i] * d.positions()[i].cross(d.velocities()[i]);
    return L;
  };
  // Relative changes of linear momentum, of the control points' and of APIC's angular momentum.
  struct Change {
    double P = 0.0, L_points = 0.0, L_apic = 0.0;
  };
  auto run = [&](const HybridShellSettings& s) {
    HybridShellDynamics d(p, s);
    std::vector<Vec3> v;
    for (const Vec3& x : d.positions()) v.push_back(v0 + w.cross(x));
    d.setVelocities(v);
    const Vec3 P0 = d.linearMomentum(), L0 = d.angularMomentum(), S0 = controlPointSpin(d);
    most_evaluations = 0;
    while (d.time() < 0.25 - 1e-9) {
      d.step(std::min(d.stableTimeStep(), 0.25 - d.time()));
      most_evaluations = std::max(most_evaluations, d.lastImplicitSolve().residual_evaluations);
    }
    return Change{(d.linearMomentum() - P0).norm() / P0.norm(),
                  (controlPointSpin(d) - S0).norm() / S0.norm(),
                  (d.angularMomentum() - L0).norm() / L0.norm()};
  };
  HybridShellSettings s = lagrangian(1.0 / 240.0);
  const Change lagrangian_change = run(s);
  const int lagrangian_evaluations = most_evaluations;
  const Change explicit_change = run(HybridShellSettings{});
  const double bound = 60.0 * s.lagrangian_tolerance / v0.norm();
  std::printf(
      "[figure] free flight 0.25 s: Lagrangian implicit (1/240 s) linear momentum change %.2e "
      "(bound %.1e), angular momentum change of the control points %.2e (APIC's %.2e); at most "
      "%d force evaluation(s) per contact solve; explicit %.2e, %.2e (APIC's %.2e)\n",
      lagrangian_change.P, bound, lagrangian_change.L_points, lagrangian_change.L_apic,
      lagrangian_evaluations, explicit_change.P, explicit_change.L_points, explicit_change.L_apic);
  EXPECT_LT(lagrangian_change.P, bound);
  EXPECT_LT(lagrangian_change.L_points, 0.01);
  EXPECT_LT(explicit_change.L_apic, 1e-6);
  // With the contact broad phase (the default) a lone layer has no fibre in contact: the contact
  // solve has no force to balance and evaluates none.
  EXPECT_EQ(lagrangian_evaluations, 0);
  // The grid's velocity alone at every point (flip_blend 0) and every fibre in contact: APIC's
  // angular momentum is what that transfer keeps.
  s.flip_blend = 0.0;
  s.contact_between_layers_only = false;
  const Change pic_change = run(s);
  std::printf(
      "[figure] free flight, the grid's velocity alone (flip_blend 0, fibres on every layer): "
      "linear momentum change %.2e, angular: APIC's %.2e (the control points' %.2e)\n",
      pic_change.P, pic_change.L_apic, pic_change.L_points);
  EXPECT_LT(pic_change.P, bound);
  EXPECT_LT(pic_change.L_apic, 0.05);
}

// cfl_between_layers_only: a lone sheet spinning at 10 rad/s keeps its distances, so its step is
// the longest; shrinking towards its centre at 20 /s it closes in on itself, and the step is
// cfl dx over that closing speed. Without the option every pair's whole relative speed counts.
TEST(HybridShellLagrangian, ALayersOwnApproachCountsOnlyWhereItClosesIn) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 6, 6);
  p.material = testCloth();
  p.gravity.setZero();
  HybridShellSettings s = lagrangian(1.0 / 60.0);
  auto bound = [&](bool between_layers_only, double spin, double shrink) {
    s.cfl_between_layers_only = between_layers_only;
    HybridShellDynamics d(p, s);
    std::vector<Vec3> v;
    for (const Vec3& x : d.positions())
      v.push_back(Vec3(0.0, 0.0, spin).cross(x - Vec3(0.05, 0.05, 0.0)) -
                  shrink * (x - Vec3(0.05, 0.05, 0.0)));
    d.setVelocities(v);
    return d.stableTimeStep();
  };
  const double spinning = bound(true, 10.0, 0.0), spinning_all = bound(false, 10.0, 0.0);
  const double shrinking = bound(true, 0.0, 20.0), shrinking_all = bound(false, 0.0, 20.0);
  std::printf(
      "[figure] lone sheet, step bound with / without cfl_between_layers_only: spinning at 10 "
      "rad/s %.3e / %.3e s, shrinking at 20 /s %.3e / %.3e s (longest %.3e s)\n",
      spinning, spinning_all, shrinking, shrinking_all, s.max_time_step);
  EXPECT_EQ(spinning, s.max_time_step);
  EXPECT_LT(spinning_all, 0.5 * s.max_time_step);
  // Shrinking: points d apart close at 20 d (about 1 m/s for those that come within the support
  // in a step): a step far below the longest, and not below the one of every pair's speed.
  EXPECT_LT(shrinking, 0.5 * s.max_time_step);
  EXPECT_LE(shrinking_all, shrinking);
}

// One elastic stage of a flat sheet on a plane (tilted by theta about y) with the obstacles in
// the solve (ObstaclePenalty), from rest at the given depth into the offset band.
struct PlaneStep {
  double sink;     // mean motion into the plane [m]
  double slide;    // mean motion down the slope [m]
  double balance;  // |M (mean motion - dt^2 g) / dt^2 - sum of the pushes| / M g
  bool converged;
};
PlaneStep stepOnPlane(double theta, double mu, double depth, const ObstaclePenalty& settings,
                      double dt) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Vec3::UnitY()).toRotationMatrix();
  const Vec3 normal = R * Vec3::UnitZ(), downhill = R * Vec3::UnitX(), g(0.0, 0.0, -9.81);
  QuadMesh mesh = makeRectangleMesh(0.1, 0.1, 5, 5);
  for (Vec3& x : mesh.vertices) x = R * x;
  const LimitSurface surface(mesh);
  const auto points = buildKirchhoffLovePoints(
      static_cast<int>(mesh.quads.size()),
      [&](int f, double u, double v) { return surface.stencil(f, u, v); }, mesh.vertices, 1e-3);
  const int n = mesh.numVertices();
  ControlPointLinks links;
  links.owner.resize(n);
  for (int p = 0; p < n; ++p) links.owner[p] = p;
  links.map.assign(n, Eigen::Matrix3d::Identity());
  ImplicitElasticity elasticity(points, n, links);
  std::vector<Vec3> x0 = mesh.vertices, x_hat(n), free(n, Vec3::Ones());
  for (Vec3& x : x0) x += (settings.offset - depth) * normal;
  for (int p = 0; p < n; ++p) x_hat[p] = x0[p] + dt * dt * g;
  // Each point's mass the fibres' stencils give it (0.2 kg/m^2): the mass the penalty on the
  // mid-surface spreads over the points, so that uniform motion solves the step exactly.
  std::vector<double> mass(n, 0.0);
  for (const KirchhoffLovePoint& q : points)
    for (int k = 0; k < q.stencil().size(); ++k)
      mass[q.stencil().points[k]] += 0.2 / 1e-3 * q.referenceVolume() * q.stencil().w[k];
  ImplicitElasticitySettings s;
  s.tolerance = 1e-10;
  s.max_iterations = 60;
  s.obstacles = settings;
  s.obstacles.start = &x0;
  s.obstacles.nearest = [&](const Vec3& x) {
    return ObstacleQuery{0, x.dot(normal), normal, Vec3::Zero(), mu};
  };
  // The friction's normal force is the last solve's: a first step without the slope's pull
  // leaves the sheet where it is (at its resting depth) and sets it.
  std::vector<Vec3> x = x0, x_level(n);
  for (int p = 0; p < n; ++p) x_level[p] = x0[p] + dt * dt * g.dot(normal) * normal;
  const HenckyLamina lamina(1e6, 0.3);
  elasticity.solve(
      x, x_level, mass, dt, free, lamina, [](std::vector<Vec3>&) {}, s);
  x = x0;
  const ImplicitElasticityResult r = elasticity.solve(
      x, x_hat, mass, dt, free, lamina, [](std::vector<Vec3>&) {}, s);
  Vec3 motion = Vec3::Zero(), pushes = Vec3::Zero();
  double M = 0.0;
  for (int p = 0; p < n; ++p) {
    motion += mass[p] * (x[p] - x0[p]);
    M += mass[p];
  }
  motion /= M;
  for (const ObstaclePush& push : elasticity.obstaclePushes()) pushes += push.force;
  return {-motion.dot(normal), motion.dot(downhill),
          (M * (motion - dt * dt * g) / (dt * dt) - pushes).norm() / (M * 9.81), r.converged};
}

// The obstacles inside the elastic stage against the closed forms of one backward Euler step
// (uniform motion: the penalty's stiffness sums to (beta + beta_c) M / dt^2 over the samples, and
// the lagged friction to mu M g cos theta once the sheet rests at its depth):
// - from rest at the band's edge a level sheet sinks s = g dt^2 / (1 + beta + beta_c);
// - resting at the depth g cos dt^2 / (beta + beta_c) on a slope with tan theta > mu it slides by
//   dt^2 g (sin - mu cos) and does not sink further;
// - with tan theta < mu it sticks: the smoothed Coulomb force mu N f1(u) of the slip u balances
//   M g sin - M u / dt^2, a slip below eps = friction_velocity dt.
// The pushes the obstacle reports balance the sheet's momentum change (the collider's wrench).
TEST(HybridShellLagrangian, ObstaclesInTheElasticSolveMatchOneStepsClosedForms) {
  ObstaclePenalty o;
  o.offset = 1e-3;
  o.stiffness = 10.0;
  o.point_stiffness = 1.0;
  o.rise = o.offset;
  const double dt = 1.0 / 60.0, g = 9.81, beta = o.stiffness + o.point_stiffness;
  const double eps = o.friction_velocity * dt, deg = M_PI / 180.0;

  const PlaneStep level = stepOnPlane(0.0, 0.5, 0.0, o, dt);
  const double sink = g * dt * dt / (1.0 + beta);
  std::printf(
      "[figure] obstacle penalty, level sheet from rest at the band's edge, 1/60 s: sinks %.4e m "
      "vs g dt^2 / (1 + beta + beta_c) = %.4e m (ratio %.4f); momentum balance %.1e of M g\n",
      level.sink, sink, level.sink / sink, level.balance);
  EXPECT_TRUE(level.converged);
  EXPECT_NEAR(level.sink / sink, 1.0, 1e-6);
  EXPECT_LT(level.balance, 1e-6);

  for (const double mu : {0.2, 0.5}) {
    const double theta = 20.0 * deg, A = g * std::sin(theta), B = mu * g * std::cos(theta);
    const double rest = g * std::cos(theta) * dt * dt / beta;
    const PlaneStep step = stepOnPlane(theta, mu, rest, o, dt);
    // Sliding: u = dt^2 (A - B); sticking: (B / eps^2) u^2 - (1 / dt^2 + 2 B / eps) u + A = 0.
    const double b = 1.0 / (dt * dt) + 2.0 * B / eps;
    const double slide =
        A > B ? dt * dt * (A - B)
              : (b - std::sqrt(b * b - 4.0 * A * B / (eps * eps))) / (2.0 * B / (eps * eps));
    std::printf(
        "[figure] obstacle friction, 20 deg slope, mu = %.1f (%s): slides %.4e m in the step vs "
        "%.4e m (ratio %.4f; eps = %.2e m), sinks %.1e m; momentum balance %.1e of M g\n",
        mu, A > B ? "slips" : "sticks", step.slide, slide, step.slide / slide, eps, step.sink,
        step.balance);
    EXPECT_TRUE(step.converged);
    EXPECT_NEAR(step.slide / slide, 1.0, 1e-6);
    EXPECT_LT(std::abs(step.sink), 1e-6 * rest);
    EXPECT_LT(step.balance, 1e-6);
    if (A < B) {
      EXPECT_LT(step.slide, eps);
    }
  }
}

TEST(HybridShellLagrangian, RejectsASolid) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, 2, 2);
  p.material = testCloth();
  HybridShellDynamics d(p, lagrangian(0.01));
  mpm::Particles solid;
  solid.add(Vec3::Zero(), Vec3::Zero(), 1e-3, 1e-6);
  EXPECT_THROW(d.addSolid(solid, mpm::HenckySolid(1e5, 0.3)), InputError);
}

}  // namespace
}  // namespace chs
