// Validation of the hybrid Lagrangian/MPM thin shell (Han chapter 5) against the static FEM
// shell, closed forms and its own contracts: cantilever bending for three thicknesses (and Han's
// +-tau/4 thickness rule), Coulomb friction on an incline, denting with a von Mises lamina,
// penetration of a cloth dropped on a sphere, self-intersections of a twisted tube.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/collision/triangle_intersections.h"
#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/gnuplot.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

// The integration the cases run with: the explicit step unless CHS_INTEGRATION names another
// (ctest runs this file twice: test_hybrid_shell_validation and, with lagrangian_implicit,
// test_hybrid_shell_validation_lagrangian).
HybridShellSettings settingsUnderTest() {
  HybridShellSettings s;
  if (const char* name = std::getenv("CHS_INTEGRATION"))
    s.integration = timeIntegrationFromName(name);
  return s;
}

using Vec3 = Eigen::Vector3d;
constexpr double kG = 9.81;

// Wall time of a test case, printed as a figure at the end of its scope.
class WallClock {
 public:
  explicit WallClock(const char* name) : name_(name), start_(std::chrono::steady_clock::now()) {}
  ~WallClock() {
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::printf("[figure] %s: wall time %.2f s\n", name_, s);
  }

 private:
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

// Steps of at most the stable one up to time t; after each step calls `each` (if given).
void runUntil(HybridShellDynamics& d, double t, const std::function<void()>& each = {}) {
  while (d.time() < t - 1e-12) {
    d.step(std::min(d.stableTimeStep(), t - d.time()));
    if (each) each();
  }
}

// Indices of the limit-surface samples (displaySurface / surfacePoints) whose reference
// position satisfies `where`: a read-out of the shell itself, not of its control net.
std::vector<int> samplesWhere(const HybridShellDynamics& d,
                              const std::function<bool(const Vec3&)>& where) {
  std::vector<int> ids;
  const std::vector<Vec3> x = d.surfacePoints();
  for (int i = 0; i < static_cast<int>(x.size()); ++i)
    if (where(x[i])) ids.push_back(i);
  return ids;
}

double meanZ(const std::vector<Vec3>& x, const std::vector<int>& ids) {
  double z = 0.0;
  for (int i : ids) z += x[i].z();
  return z / ids.size();
}

// ---------------------------------------------------------------------------------------------
// 1. Cantilever strip under gravity against the static FEM shell.

// 8 x 2 quads and thick strips keep the explicit settle inside the test budget: the steps to
// settle scale as L^2 / (h tau) (membrane time step h / c over bending period L^2 / (c tau)).
constexpr double kBeamL = 0.1, kBeamW = 0.02, kBeamE = 1.375e5, kBeamRho = 0.2;
constexpr int kBeamNx = 8, kBeamNy = 2;

// The strip along +x from the wall at x = 0, flat in z = 0, clamped along x = 0.
DrapeProblem cantilever(double thickness, double poisson, double length, int nx, int ny) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(length, kBeamW, nx, ny, Vec3(0.5 * length, 0.0, 0.0));
  p.material = testCloth(kBeamE, thickness, kBeamRho);
  p.material.poisson = poisson;
  p.gravity = Vec3(0.0, 0.0, -kG);
  for (int j = 0; j <= ny; ++j) p.bc.clamped.push_back(j * (nx + 1));
  return p;
}

// Fundamental bending frequency of a uniformly loaded cantilever strip, omega_1 = 1.875^2
// sqrt(D / (rho_A L^4)): sets the damping (critical for mode 1, c = 2 omega_1, every higher mode
// then decays at the same rate omega_1) and the settling time.
double cantileverOmega(double thickness, double poisson, double length) {
  const double D = kBeamE * std::pow(thickness, 3) / (12.0 * (1.0 - poisson * poisson));
  return 3.516 * std::sqrt(D / (kBeamRho * std::pow(length, 4)));
}

// Settles the clamped strip and returns the tip deflection of the limit surface, averaged over
// the tip edge, the largest control speed at the end, the clamp's vertical force over the
// strip's weight W, and its moment about the clamp line over W x_c, the weight's lever arm
// (x_c the centre of mass's distance from the wall, the same for every sample point).
// Also the deformed centre line y = 0 of the limit surface, in the order of its reference x.
struct SettledTip {
  double deflection, speed, clamp_load, clamp_moment;
  std::vector<Vec3> centreline;
};
SettledTip settledHybridTip(const DrapeProblem& p, double omega, ThicknessRule rule) {
  HybridShellSettings s = settingsUnderTest();
  s.damping = 2.0 * omega;
  s.kirchhoff_love.thickness_rule = rule;
  HybridShellDynamics d(p, s);
  const std::vector<int> tip = samplesWhere(d, [](const Vec3& x) { return x.x() > kBeamL - 1e-9; });
  std::vector<int> centre_ids =
      samplesWhere(d, [](const Vec3& x) { return std::abs(x.y()) < 1e-9; });
  const std::vector<Vec3> x0 = d.surfacePoints();
  std::sort(centre_ids.begin(), centre_ids.end(),
            [&](int a, int b) { return x0[a].x() < x0[b].x(); });
  // e^{-omega t} (1 + omega t) < 5e-4 at omega t = 10.
  runUntil(d, 10.0 / omega);
  double speed = 0.0;
  for (const Vec3& v : d.velocities()) speed = std::max(speed, v.norm());
  double clamp = 0.0;
  for (const Vec3& f : d.holdingForces(p.bc.clamped)) clamp += f.z();
  std::vector<Vec3> centreline;
  const std::vector<Vec3> x1 = d.surfacePoints();
  for (int i : centre_ids) centreline.push_back(x1[i]);
  double centre = 0.0;  // x of the centre of mass
  for (int i = 0; i < d.numVertices(); ++i) centre += d.masses()[i] * d.positions()[i].x();
  centre /= d.totalMass();
  // The cloth's weight turns it about +y at the wall (x right, z up); the clamp holds it back.
  const double weight = kBeamRho * kBeamL * kBeamW * kG;
  const double moment = -d.clampWrench(Vec3::Zero()).torque.y();
  return {-meanZ(d.surfacePoints(), tip), speed, clamp / weight, moment / (weight * centre),
          centreline};
}
SettledTip settledHybridTip(double thickness, double poisson, ThicknessRule rule, int nx = kBeamNx,
                            int ny = kBeamNy) {
  return settledHybridTip(cantilever(thickness, poisson, kBeamL, nx, ny),
                          cantileverOmega(thickness, poisson, kBeamL), rule);
}

// The FEM's tip deflection (mean over the tip edge) and its middle row of nodes (y = 0).
struct FemTip {
  double deflection;
  std::vector<Vec3> centreline;
};
FemTip femTip(double thickness, double poisson, int nx = kBeamNx, int ny = kBeamNy) {
  const DrapeProblem p = cantilever(thickness, poisson, kBeamL, nx, ny);
  const DrapeResult r = solveFemShell(p, FemShellSettings{});
  EXPECT_TRUE(r.converged) << r.status;
  double z = 0.0;
  for (int j = 0; j <= ny; ++j) z += r.positions[j * (nx + 1) + nx].z();
  FemTip t{-z / (ny + 1), {}};
  for (int i = 0; i <= nx; ++i) t.centreline.push_back(r.positions[(ny / 2) * (nx + 1) + i]);
  return t;
}

// With CHS_VALIDATION_PLOTS=<dir>: the centre lines at nu = 0.3 as <dir>/hybrid_cantilever.png,
// the hybrid's (lines) against the FEM's nodes (points), and the old clamp of two pinned control
// columns at tau = 6.3 mm (dashed) for comparison.
void plotCantilevers(const std::vector<std::pair<double, SettledTip>>& hybrid,
                     const std::vector<FemTip>& fem, const SettledTip& pinned_columns) {
  const char* dir = std::getenv("CHS_VALIDATION_PLOTS");
  if (!dir) return;
  std::ostringstream s;
  const auto block = [&s](const std::string& name, const std::vector<Vec3>& line) {
    s << "$" << name << " << EOD\n";
    for (const Vec3& x : line) s << 1e3 * x.x() << " " << 1e3 * x.z() << "\n";
    s << "EOD\n";
  };
  for (std::size_t k = 0; k < hybrid.size(); ++k) {
    block("h" + std::to_string(k), hybrid[k].second.centreline);
    block("f" + std::to_string(k), fem[k].centreline);
  }
  block("old", pinned_columns.centreline);
  s << "set terminal pngcairo size 1000,520 font 'sans,11'\n"
    << "set output " << gnuplotQuote(std::string(dir) + "/hybrid_cantilever.png") << "\n"
    << "set title 'Strip 10 x 2 cm clamped at x = 0, under gravity, nu = 0.3, 8 x 2 quads: "
       "centre lines'\n"
    << "set xlabel 'x [mm]'\nset ylabel 'z [mm]'\nset key below maxcols 2\nset grid\n"
    << "set size ratio -1\nplot ";
  const char* colours[] = {"#1f77b4", "#2ca02c", "#d62728"};
  for (std::size_t k = 0; k < hybrid.size(); ++k)
    s << "$h" << k << " with lines lw 2 lc rgb '" << colours[k % 3]
      << "' title 'hybrid, tau = " << 1e3 * hybrid[k].first << " mm', $f" << k
      << " with points pt 7 ps 1.2 lc rgb '" << colours[k % 3] << "' title 'FEM shell', ";
  s << "$old with lines dt 2 lw 2 lc rgb '#d62728' title 'two pinned control columns (before "
       "clamped edges), tau = 6.3 mm'\n";
  runGnuplot(s.str());
  std::printf("[figure] cantilever centre lines plotted to %s/hybrid_cantilever.png\n", dir);
}

// The clamp (ghost faces across the clamped edge, subdiv/clamped_edges.h) holds the root's
// position and tangent plane and leaves its curvature free. With nu = 0 the strip bends as a
// beam and the hybrid meets the FEM to within what separates the two shells (the FEM's
// transverse shear, ~0.4 % here). With nu = 0.3 the strip also curls across its width
// (anticlastic curvature); Catmull-Clark's free hems hold zero curvature across the edge, where
// a free edge's moment vanishes at kappa_nn = -nu kappa_tt instead, so the strip is a few per
// cent stiffer, less on a finer mesh.
TEST(HybridShellValidation, CantileverMatchesFemShell) {
  WallClock clock("cantilever");
  double gauss = 0.0;  // tip of the last (stiffest) strip, for the thickness-rule comparison
  double coarse_error = 0.0;
  std::vector<std::pair<double, SettledTip>> plotted;  // nu = 0.3, by thickness
  std::vector<FemTip> plotted_fem;
  for (double poisson : {0.0, 0.3})
    for (double thickness : {4.0e-3, 5.0e-3, 6.3e-3}) {
      const FemTip fem_tip = femTip(thickness, poisson);
      const double fem = fem_tip.deflection;
      const SettledTip mpm = settledHybridTip(thickness, poisson, ThicknessRule::kGauss);
      if (poisson > 0.0) {
        plotted.push_back({thickness, mpm});
        plotted_fem.push_back(fem_tip);
      }
      gauss = mpm.deflection;
      const double ratio = mpm.deflection / fem;
      coarse_error = 1.0 - ratio;
      std::printf(
          "[figure] cantilever nu = %.1f, tau = %.1f mm, %d x %d quads: tip deflection hybrid "
          "%.4f mm (%.1f %% of L), FEM %.4f mm, ratio %.4f; clamp carries %.4f of the weight and "
          "%.4f of its moment; largest control speed at the end %.1e m/s\n",
          poisson, 1e3 * thickness, kBeamNx, kBeamNy, 1e3 * mpm.deflection,
          100 * mpm.deflection / kBeamL, 1e3 * fem, ratio, mpm.clamp_load, mpm.clamp_moment,
          mpm.speed);
      EXPECT_NEAR(ratio, 1.0, poisson == 0.0 ? 0.01 : 0.05);
      EXPECT_NEAR(mpm.clamp_load, 1.0, 3e-3);
      EXPECT_NEAR(mpm.clamp_moment, 1.0, 5e-3);
    }
  // The free hems' error shrinks with the spacing.
  const double fine =
      settledHybridTip(6.3e-3, 0.3, ThicknessRule::kGauss, 2 * kBeamNx, 2 * kBeamNy).deflection /
      femTip(6.3e-3, 0.3, 2 * kBeamNx, 2 * kBeamNy).deflection;
  std::printf(
      "[figure] cantilever nu = 0.3, tau = 6.3 mm, %d x %d quads: ratio %.4f; error %.1f %% -> "
      "%.1f %%\n",
      2 * kBeamNx, 2 * kBeamNy, fine, 100 * coarse_error, 100 * (1 - fine));
  EXPECT_LT(std::abs(1.0 - fine), coarse_error);
  // Han's +-tau/4 points integrate xi3^2 as tau^3 / 16: 3/4 of the bending stiffness.
  const double thickness = 6.3e-3;
  const double han = settledHybridTip(thickness, 0.3, ThicknessRule::kHanQuarter).deflection;
  std::printf(
      "[figure] cantilever tau = %.1f mm, Han +-tau/4 rule: tip %.4f mm vs Gauss %.4f mm, ratio "
      "%.4f (small-deflection theory 4/3)\n",
      1e3 * thickness, 1e3 * han, 1e3 * gauss, han / gauss);
  EXPECT_NEAR(han / gauss, 4.0 / 3.0, 0.04);
  if (std::getenv("CHS_VALIDATION_PLOTS")) {
    DrapeProblem pinned = cantilever(6.3e-3, 0.3, kBeamL, kBeamNx, kBeamNy);
    pinned.bc.clamped.clear();
    for (int j = 0; j <= kBeamNy; ++j)
      for (int i = 0; i < 2; ++i) pinned.bc.pinned.push_back(j * (kBeamNx + 1) + i);
    plotCantilevers(
        plotted, plotted_fem,
        settledHybridTip(pinned, cantileverOmega(6.3e-3, 0.3, kBeamL), ThicknessRule::kGauss));
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Coulomb friction on an incline: a 4 x 4 cm patch on a plane tilted by theta, mu = 0.4.

struct InclineRun {
  double travel;        // centre-of-mass displacement along the slope after the run [m]
  double acceleration;  // (v(t_end) - v(t_end / 3)) / (2 t_end / 3) along the slope [m/s^2]
};
InclineRun slideOnIncline(double theta, double mu, double t_end) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Vec3::UnitY()).toRotationMatrix();
  const Vec3 normal = R * Vec3::UnitZ(), downhill = R * Vec3::UnitX();
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.04, 0.04, 4, 4);
  for (Vec3& x : p.mesh.vertices) x = R * x;  // lying on the plane through the origin
  p.material = testCloth(2e5, 5e-4, 0.2);
  p.gravity = Vec3(0.0, 0.0, -kG);
  HybridShellDynamics d(p, settingsUnderTest());
  d.setColliders({std::make_shared<PlaneSurface>(Vec3::Zero(), normal)}, {}, {mu});
  auto centre = [&] {
    Vec3 c = Vec3::Zero();
    for (int i = 0; i < d.numVertices(); ++i) c += d.masses()[i] * d.positions()[i];
    return Vec3(c / d.totalMass());
  };
  auto speed = [&] { return d.linearMomentum().dot(downhill) / d.totalMass(); };
  const Vec3 c0 = centre();
  runUntil(d, t_end / 3.0);
  const double v1 = speed(), t1 = d.time();
  runUntil(d, t_end);
  return {(centre() - c0).dot(downhill), (speed() - v1) / (d.time() - t1)};
}

TEST(HybridShellValidation, SlidesOnAnInclineIffTanThetaExceedsMu) {
  WallClock clock("incline");
  const double mu = 0.4, t = 0.3, onset = std::atan(mu), degree = M_PI / 180.0;
  const double below = onset - degree, above = onset + degree;
  const double a_above = kG * (std::sin(above) - mu * std::cos(above));
  const double free_travel = 0.5 * a_above * t * t;  // what sliding at onset + 1 deg gives
  const InclineRun stick = slideOnIncline(below, mu, t);
  const InclineRun slide = slideOnIncline(above, mu, t);
  std::printf(
      "[figure] incline mu = %.1f (onset %.2f deg), %.1f s: at onset - 1 deg travel %.3e m "
      "(%.2f %% of the %.3e m slid at onset + 1 deg in theory), acceleration %.3e m/s^2\n",
      mu, onset / degree, t, stick.travel, 100 * stick.travel / free_travel, free_travel,
      stick.acceleration);
  std::printf(
      "[figure] incline at onset + 1 deg: acceleration %.4f m/s^2 vs g (sin - mu cos) = %.4f "
      "(ratio %.3f), travel %.3e m\n",
      slide.acceleration, a_above, slide.acceleration / a_above, slide.travel);
  EXPECT_LT(std::abs(stick.travel), 0.05 * free_travel);
  EXPECT_NEAR(slide.acceleration / a_above, 1.0, 0.1);
}

// ---------------------------------------------------------------------------------------------
// 3. Denting: a 5 cm strip bent by its tip and released keeps a permanent set only if it yields.

double dentResidual(double yield_stress, double depth) {
  constexpr double L = 0.05, T = 0.05, tau = 5e-3;  // strip length, press duration, thickness
  constexpr int nx = 8, ny = 2;
  DrapeProblem p = cantilever(tau, 0.3, L, nx, ny);
  p.gravity.setZero();
  HybridShellSettings s = settingsUnderTest();
  s.yield_stress = yield_stress;
  const double omega = cantileverOmega(tau, 0.3, L);
  s.damping = 2.0 * omega;
  HybridShellDynamics d(p, s);
  const std::vector<int> tip_samples =
      samplesWhere(d, [&](const Vec3& x) { return x.x() > L - 1e-9; });
  std::vector<int> tip;
  for (int j = 0; j <= ny; ++j) tip.push_back(j * (nx + 1) + nx);
  const std::vector<Vec3> x0 = d.positions();
  // Down and back up along w = depth sin^2(pi t / T); the tip also moves in by the shortening of
  // an inextensible tip-loaded cantilever, 0.6 w^2 / L, so the press bends rather than stretches.
  while (d.time() < T - 1e-12) {
    const double dt = std::min(d.stableTimeStep(), T - d.time());
    const double w = depth * std::pow(std::sin(M_PI * (d.time() + dt) / T), 2);
    for (int v : tip) d.pin(v, x0[v] - Vec3(0.6 * w * w / L, 0.0, w));  // where it is at t + dt
    d.step(dt);
  }
  // Released, the strip rings out under the same damping (critical for its first mode).
  for (int v : tip) d.unpin(v);
  const double t_release = d.time();
  for (double wait : {10.0, 20.0, 30.0}) {
    runUntil(d, t_release + wait / omega);
    std::printf(
        "[figure]   c_vM %.0f Pa: tip deflection %.4f mm at omega_1 t = %.0f after release\n",
        yield_stress, -1e3 * meanZ(d.surfacePoints(), tip_samples), wait);
  }
  return -meanZ(d.surfacePoints(), tip_samples);
}

TEST(HybridShellValidation, DentingKeepsAPermanentSetOnlyBeyondYield) {
  WallClock clock("denting");
  const double depth = 5e-3;  // 10 % of the strip's length
  // Peak bending stress of the press: E kappa tau / 2 with kappa = 3 w / L^2 at the root,
  // 1.375e5 Pa * 6 / m * 2.5 mm = 2.1 kPa. c_vM = 0.5 kPa yields well inside it, 10 kPa never.
  const double low = dentResidual(500.0, depth), high = dentResidual(1e4, depth);
  std::printf(
      "[figure] denting, tip pressed %.1f mm and released: residual tip deflection %.4f mm "
      "(%.1f %%) with c_vM = 0.5 kPa, %.2e mm (%.3f %%) with c_vM = 10 kPa\n",
      1e3 * depth, 1e3 * low, 100 * low / depth, 1e3 * high, 100 * std::abs(high) / depth);
  EXPECT_GT(low, 0.2 * depth);
  // Released from the elastic press the strip creeps back slowly (the residual halves every
  // ~10 / omega_1); 30 / omega_1 leaves ~3 %, against ~30 % kept after yielding.
  EXPECT_LT(std::abs(high), 0.05 * depth);
}

// ---------------------------------------------------------------------------------------------
// 4. A cloth dropped on a sphere: the limit surface stays outside to a quarter cell.

// The test cloth `mesh` under gravity on one collider with Coulomb mu, damped at 10/s, with the
// integrator under test.
struct ClothOnCollider {
  DrapeProblem problem;
  HybridShellSettings settings;
};

ClothOnCollider clothOn(QuadMesh mesh, std::shared_ptr<const RigidSurface> collider, double mu) {
  ClothOnCollider c;
  c.problem.mesh = std::move(mesh);
  c.problem.material = testCloth(2e5, 5e-4, 0.2);
  c.problem.gravity = Vec3(0.0, 0.0, -kG);
  c.problem.colliders = {std::move(collider)};
  c.settings = settingsUnderTest();
  c.settings.friction = mu;
  c.settings.damping = 10.0;
  return c;
}

TEST(HybridShellValidation, ClothOnSphereDoesNotPenetrate) {
  WallClock clock("sphere");
  constexpr double R = 0.03;
  const ClothOnCollider c = clothOn(makeRectangleMesh(0.08, 0.08, 8, 8, Vec3(0.0, 0.0, R + 0.005)),
                                    std::make_shared<SphereSurface>(Vec3::Zero(), R), 0.3);
  HybridShellDynamics d(c.problem, c.settings);
  double deepest = 0.0;
  runUntil(d, 0.3, [&] { deepest = std::max(deepest, d.deepestPenetration()); });
  const double final_depth = d.deepestPenetration(), dx = d.gridSpacing();
  std::printf(
      "[figure] cloth on sphere, %.2f s: deepest penetration of the limit surface %.3e m during "
      "(%.3f dx), %.3e m at the end (%.3f dx); dx = %.3e m; lowest point z = %.4f m\n",
      d.time(), deepest, deepest / dx, final_depth, final_depth / dx, dx, [&] {
        double z = 1.0;
        for (const Vec3& x : d.surfacePoints()) z = std::min(z, x.z());
        return z;
      }());
  EXPECT_LE(deepest, 0.25 * dx);
  EXPECT_LE(final_depth, 0.25 * dx);
}

// A sheet of 4 cm cells laid over a forearm-thin bar (a capsule of radius 3.8 cm, as the
// mannequin's forearm) and left to hang over it. The control points stay out of the bar, but the
// limit surface of a net of spacing h wrapped on radius R lies R (1 - cos(h / R)) / 3 inside it
// (mpm/surface_collisions.h): 6.3 mm here, and a cell of the grid is wider than the bar. With
// surface_collisions the displayed surface stays out at every step; the bar carries the sheet's
// weight either way. Without, the grid holds the net alone: the Lagrangian steps' obstacles in the
// elastic solve (which hold the fibres' mid-surface points out) are off too.
struct BarDrape {
  double deepest = 0.0;        // over the run, of the displayed limit surface [m]
  double load_fraction = 0.0;  // the bar's vertical load over the last 0.3 s / the weight
  double end_speed = 0.0;      // largest control-point speed at the end [m/s]
};

BarDrape drapeOverBar(bool surface_collisions) {
  constexpr double R = 0.038, t_end = 1.5, window = 0.3;
  ClothOnCollider c =
      clothOn(makeRectangleMesh(0.4, 0.16, 10, 4, Vec3(0.0, 0.0, R + 0.004)),
              std::make_shared<CapsuleSurface>(Vec3(0.0, -0.2, 0.0), Vec3(0.0, 0.2, 0.0), R), 0.5);
  c.settings.surface_collisions = surface_collisions;
  if (!surface_collisions) c.settings.obstacle_stiffness = 0.0;
  HybridShellDynamics d(c.problem, c.settings);
  BarDrape r;
  double impulse = 0.0, span = 0.0;
  runUntil(d, t_end, [&] {
    r.deepest = std::max(r.deepest, d.deepestPenetration());
    if (d.time() > t_end - window - 1e-12) {
      impulse += d.colliderImpulses()[0].linear.z();
      span = d.time() - (t_end - window);
    }
  });
  r.load_fraction = impulse / span / (d.totalMass() * kG);
  for (const Vec3& v : d.velocities()) r.end_speed = std::max(r.end_speed, v.norm());
  return r;
}

TEST(HybridShellValidation, SheetOverThinBarKeepsItsLimitSurfaceOut) {
  WallClock clock("thin bar");
  const double R = 0.038, h = 0.04;
  const double predicted = R * (1.0 - std::cos(h / R)) / 3.0;
  const BarDrape off = drapeOverBar(false), on = drapeOverBar(true);
  std::printf(
      "[figure] sheet over a bar r = 38 mm, 4 cm cells: deepest penetration of the limit surface "
      "%.3f mm without surface collisions (net on the bar predicts %.2f mm), %.4f mm with; bar "
      "carries %.4f / %.4f of the weight (end speed %.1e / %.1e m/s)\n",
      1e3 * off.deepest, 1e3 * predicted, 1e3 * on.deepest, off.load_fraction, on.load_fraction,
      off.end_speed, on.end_speed);
  EXPECT_GT(off.deepest, 0.5 * predicted);  // the gap the surface collisions close is real
  EXPECT_LE(on.deepest, 1e-5);
  EXPECT_NEAR(on.load_fraction, 1.0, 0.02);
}

// ---------------------------------------------------------------------------------------------
// 5. Self-collision: a cloth tube twisted by turning one end ring (Han fig. 5.7 / 5.11).

// Open cylinder about the z axis, n around and m along; vertex (k, j) is j n + k. Quads are
// counter-clockwise seen from outside (theta x z points outward).
QuadMesh cylinderMesh(double radius, double length, int n, int m) {
  QuadMesh mesh;
  for (int j = 0; j <= m; ++j)
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * k / n;
      mesh.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), length * j / m);
    }
  for (int j = 0; j < m; ++j)
    for (int k = 0; k < n; ++k)
      mesh.quads.push_back(
          {j * n + k, j * n + (k + 1) % n, (j + 1) * n + (k + 1) % n, (j + 1) * n + k});
  return mesh;
}

// Twists the tube (radius R = 2 cm, length H = 8 cm, n x m quads, no gravity): the bottom ring
// pinned, the top ring turned by `turns` about the axis over T = 0.2 s while it moves down by
// `shortening` H (a twisted tube shortens and winds into contact with itself), then held for
// 0.05 s. Audits the tessellated limit surface every 0.025 s; returns the worst count.
std::size_t twistTube(double turns, double shortening, int n, int m,
                      TimeIntegration integration = settingsUnderTest().integration) {
  constexpr double R = 0.02, H = 0.08, T = 0.2, t_end = T + 0.05;
  DrapeProblem p;
  p.mesh = cylinderMesh(R, H, n, m);
  p.material = testCloth(2e5, 5e-4, 0.2);
  p.gravity.setZero();
  std::vector<int> bottom, top;
  for (int k = 0; k < n; ++k) {
    bottom.push_back(k);
    top.push_back(m * n + k);
  }
  p.bc.pinned = bottom;
  HybridShellSettings s;
  s.damping = 5.0;
  s.integration = integration;
  HybridShellDynamics d(p, s);
  const std::vector<Vec3> x0 = d.positions();
  std::size_t worst = 0;
  int checkpoint = 0;
  while (d.time() < t_end - 1e-12) {
    const double dt = std::min(d.stableTimeStep(), t_end - d.time());
    const double f = std::min(1.0, (d.time() + dt) / T);
    const Eigen::AngleAxisd turn(2.0 * M_PI * turns * f, Vec3::UnitZ());
    for (int v : top) d.pin(v, turn * x0[v] - Vec3(0.0, 0.0, shortening * H * f));
    d.step(dt);
    if (d.time() < 0.025 * (checkpoint + 1) - 1e-12) continue;
    ++checkpoint;
    const DisplaySurface surf = d.displaySurface();
    const TriangleIntersections hits = countTriangleIntersections(surf.vertices, surf.triangles);
    std::printf(
        "[figure] twisted tube %d x %d, %.2f turns, shortening %.2f: t = %.3f s (%.2f turns, %d "
        "steps): %zu intersecting triangle pairs (%zu neighbours) of %zu triangles\n",
        n, m, turns, shortening, d.time(), turns * f, d.stageTimes().steps, hits.count,
        hits.neighbour_count, surf.triangles.size());
    worst = std::max(worst, hits.count);
    if (hits.count == 0) continue;
    // Where they are: heights of the intersecting triangles' centroids between the rings and
    // their distance from the axis.
    double z_lo = 1.0, z_hi = -1.0, r_lo = 1.0, r_hi = 0.0;
    for (const auto& pr : hits.pairs)
      for (int t : pr) {
        Vec3 c = Vec3::Zero();
        for (int k : surf.triangles[t]) c += surf.vertices[k] / 3.0;
        z_lo = std::min(z_lo, c.z());
        z_hi = std::max(z_hi, c.z());
        r_lo = std::min(r_lo, c.head<2>().norm());
        r_hi = std::max(r_hi, c.head<2>().norm());
      }
    std::printf(
        "[figure]   intersecting triangles at z = %.1f..%.1f mm (rings at 0 and %.1f mm), "
        "radius %.1f..%.1f mm (tube radius %.0f mm, dx %.1f mm)\n",
        1e3 * z_lo, 1e3 * z_hi, 1e3 * (1.0 - shortening * f) * H, 1e3 * r_lo, 1e3 * r_hi, 1e3 * R,
        1e3 * d.gridSpacing());
  }
  return worst;
}

// One turn of a 16 x 10 tube (dx ~ 8 mm; the neck pinches to ~2 mm, below a cell), and 1.5 turns
// with 25 % shortening of a 24 x 16 one (dx ~ 5 mm). A tube too coarse for its twist
// intersects where the neck pinches (12 x 8 from the end of one turn in 4 of 6 runs, 16 x 10
// at 1.5 turns: docs/VALIDATION.md); CHS_TUBE="n m turns shortening [backward]" runs any other,
// with backward Euler if asked.
TEST(HybridShellValidation, TwistedTubeStaysFreeOfSelfIntersections) {
  WallClock clock("twisted tube");
  if (const char* spec = std::getenv("CHS_TUBE")) {
    int n = 0, m = 0;
    double turns = 0.0, shortening = 0.0;
    char integration[16] = "";
    ASSERT_GE(std::sscanf(spec, "%d %d %lf %lf %15s", &n, &m, &turns, &shortening, integration), 4)
        << spec;
    EXPECT_EQ(twistTube(turns, shortening, n, m,
                        std::string(integration) == "backward" ? TimeIntegration::kBackwardEuler
                                                               : settingsUnderTest().integration),
              0u);
    return;
  }
  EXPECT_EQ(twistTube(1.0, 0.0, 16, 10), 0u);
  EXPECT_EQ(twistTube(1.5, 0.25, 24, 16), 0u);
}

}  // namespace
}  // namespace chs
