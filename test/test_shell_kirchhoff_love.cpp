// Kirchhoff-Love quadrature points with the Hencky lamina model and von Mises denting (Han ch. 5):
// exact forces, rigid-motion invariance, finite stretch and bending against closed forms, and
// the denting return mapping. Stencils are uniform bicubic B-spline patches, which is what
// Catmull-Clark gives on regular faces.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"

namespace chs {
namespace {

using Points = std::vector<Eigen::Vector3d>;

// Uniform cubic B-spline basis on [0,1] and its first and second derivatives.
void cubicBSpline(double t, double b[4], double db[4], double ddb[4]) {
  const double s = 1.0 - t;
  b[0] = s * s * s / 6.0;
  b[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
  b[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
  b[3] = t * t * t / 6.0;
  db[0] = -0.5 * s * s;
  db[1] = 0.5 * (3.0 * t * t - 4.0 * t);
  db[2] = 0.5 * (-3.0 * t * t + 2.0 * t + 1.0);
  db[3] = 0.5 * t * t;
  ddb[0] = s;
  ddb[1] = 3.0 * t - 2.0;
  ddb[2] = 1.0 - 3.0 * t;
  ddb[3] = t;
}

// A regular control grid of (nu + 3) x (nv + 3) points carrying nu x nv bicubic faces; face
// (fi, fj) uses the 4 x 4 control points from (fi, fj).
struct BSplineGrid {
  int nu, nv;
  int columns() const { return nu + 3; }
  int rows() const { return nv + 3; }
  int index(int i, int j) const { return j * columns() + i; }
  int faces() const { return nu * nv; }

  SurfaceStencil stencil(int face, double u, double v) const {
    const int fi = face % nu, fj = face / nu;
    double bu[4], dbu[4], ddbu[4], bv[4], dbv[4], ddbv[4];
    cubicBSpline(u, bu, dbu, ddbu);
    cubicBSpline(v, bv, dbv, ddbv);
    SurfaceStencil s;
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        s.points.push_back(index(fi + a, fj + b));
        s.w.push_back(bu[a] * bv[b]);
        s.du.push_back(dbu[a] * bv[b]);
        s.dv.push_back(bu[a] * dbv[b]);
        s.duu.push_back(ddbu[a] * bv[b]);
        s.duv.push_back(dbu[a] * dbv[b]);
        s.dvv.push_back(bu[a] * ddbv[b]);
      }
    return s;
  }
  FaceStencilFunction source() const {
    return [this](int f, double u, double v) { return stencil(f, u, v); };
  }
  // Flat grid of spacing h in the z = 0 plane.
  Points flat(double h) const {
    Points x(columns() * rows());
    for (int j = 0; j < rows(); ++j)
      for (int i = 0; i < columns(); ++i) x[index(i, j)] = Eigen::Vector3d(h * i, h * j, 0.0);
    return x;
  }
};

Points transformed(const Points& X, const Eigen::Matrix3d& M, const Eigen::Vector3d& t) {
  Points x;
  for (const auto& p : X) x.push_back(M * p + t);
  return x;
}

double totalVolume(const std::vector<KirchhoffLovePoint>& points) {
  double v = 0.0;
  for (const auto& q : points) v += q.referenceVolume();
  return v;
}

// A doubly curved reference with jitter, and a stretched, bent, randomly perturbed current state.
struct CurvedCase {
  BSplineGrid grid{2, 2};
  double h = 0.25, thickness = 0.02;
  Points X, x;
  CurvedCase() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    X = grid.flat(h);
    for (auto& p : X) {
      p.z() = 0.3 * std::sin(2.0 * p.x()) * std::cos(1.5 * p.y());
      p += 0.05 * h * Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    for (const auto& p : X) {
      const double bend = 0.4 * p.x() * p.x() - 0.2 * p.x() * p.y();
      x.push_back(Eigen::Vector3d(1.15 * p.x() + 0.1 * p.y(), 0.95 * p.y(), p.z() + bend) +
                  0.08 * h * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
  }
};

// Largest |analytic - central difference| over the largest |analytic| gradient component.
double gradientError(const std::vector<KirchhoffLovePoint>& points, const HenckyLamina& m,
                     const Points& x, double step) {
  Points g;
  kirchhoffLoveEnergy(points, m, x, &g);
  double err = 0.0, scale = 0.0;
  for (std::size_t p = 0; p < x.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      Points xp = x, xm = x;
      xp[p](c) += step;
      xm[p](c) -= step;
      const double fd =
          (kirchhoffLoveEnergy(points, m, xp) - kirchhoffLoveEnergy(points, m, xm)) / (2 * step);
      err = std::max(err, std::abs(fd - g[p](c)));
      scale = std::max(scale, std::abs(g[p](c)));
    }
  return err / scale;
}

TEST(ShellKirchhoffLove, GradientMatchesFiniteDifferences) {
  CurvedCase c;
  const HenckyLamina elastic(1.0e4, 0.3);
  auto points = buildKirchhoffLovePoints(c.grid.faces(), c.grid.source(), c.X, c.thickness);
  const double tol = 1e-6;
  const double err_elastic = gradientError(points, elastic, c.x, 1e-6 * c.h);
  std::printf("[figure] dPsi/dx vs central differences, elastic: relative error %.3e (tol %.0e)\n",
              err_elastic, tol);
  EXPECT_LT(err_elastic, tol);

  // Plastic strain: yield at the current state, then take the gradient at another state.
  const HenckyLamina plastic(1.0e4, 0.3, 50.0);
  const int yielded = updateKirchhoffLovePlasticity(points, plastic, c.x);
  double max_plastic = 0.0;
  for (const auto& q : points)
    max_plastic =
        std::max(max_plastic, (q.plasticDeformation() - Eigen::Matrix3d::Identity()).norm());
  Points x2 = c.x;
  for (auto& p : x2)
    p += Eigen::Vector3d(0.02 * p.y() * p.y(), -0.03 * p.x(), 0.05 * p.x() * p.y());
  const double err_plastic = gradientError(points, plastic, x2, 1e-6 * c.h);
  std::printf(
      "[figure] with plastic strain (%d of %zu points yielded, max |F^P - I| %.3f): "
      "relative error %.3e (tol %.0e)\n",
      yielded, points.size(), max_plastic, err_plastic, tol);
  EXPECT_GT(yielded, 0);
  EXPECT_GT(max_plastic, 1e-2);
  EXPECT_LT(err_plastic, tol);
}

TEST(ShellKirchhoffLove, RigidMotionHasNoEnergyNorForce) {
  CurvedCase c;
  const HenckyLamina m(1.0e4, 0.3);
  const auto points = buildKirchhoffLovePoints(c.grid.faces(), c.grid.source(), c.X, c.thickness);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Points x = transformed(c.X, R, Eigen::Vector3d(0.4, -2.0, 1.3));
  Points g;
  const double energy = kirchhoffLoveEnergy(points, m, x, &g);
  double g_max = 0.0;
  for (const auto& v : g) g_max = std::max(g_max, v.cwiseAbs().maxCoeff());
  // Scales: E V for the energy, E tau h for a control-point force.
  const double e_rel = energy / (m.youngsModulus() * totalVolume(points));
  const double f_rel = g_max / (m.youngsModulus() * c.thickness * c.h);
  const double tol_e = 1e-24, tol_f = 1e-11;
  std::printf(
      "[figure] rigid motion: energy/(E V) %.2e (tol %.0e), max force/(E tau h) %.2e "
      "(tol %.0e)\n",
      e_rel, tol_e, f_rel, tol_f);
  EXPECT_LT(e_rel, tol_e);
  EXPECT_LT(f_rel, tol_f);
}

// Uniform stretch of a flat patch: F^KL is the stretch itself at every point, and Hencky strain
// makes (5.11)/(5.12) exact at finite strain.
void checkUniformStretch(const char* name, double s1, double s2) {
  const BSplineGrid grid{3, 3};
  const double h = 0.1, thickness = 0.01;
  const HenckyLamina m(2.0e3, 0.35);
  const Points X = grid.flat(h);
  const auto points = buildKirchhoffLovePoints(grid.faces(), grid.source(), X, thickness);
  // Stretch along axes rotated by 30 degrees in the plane, then tilt the patch rigidly.
  const Eigen::Matrix3d V =
      Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3d stretch = V * Eigen::Vector3d(s1, s2, 1.0).asDiagonal() * V.transpose();
  const Points x = transformed(X, Q * stretch, Eigen::Vector3d(0.3, 0.1, -0.2));

  const double l1 = std::log(s1), l2 = std::log(s2);
  const double psi = m.mu() * (l1 * l1 + l2 * l2) + 0.5 * m.lambda() * (l1 + l2) * (l1 + l2);
  const Eigen::Vector3d tau_principal(2 * m.mu() * l1 + m.lambda() * (l1 + l2),
                                      2 * m.mu() * l2 + m.lambda() * (l1 + l2), 0.0);
  const Eigen::Matrix3d tau_exact =
      Q * V * tau_principal.asDiagonal() * V.transpose() * Q.transpose();

  double tau_err = 0.0, piola_err = 0.0;
  for (const auto& q : points) {
    const Eigen::Matrix3d F = q.trialElasticDeformation(x);
    const Eigen::Matrix3d tau = m.kirchhoffStress(F, q.laminaFrame());
    const Eigen::Matrix3d P = m.firstPiolaStress(F, q.laminaFrame());
    tau_err = std::max(tau_err, (tau - tau_exact).norm() / tau_exact.norm());
    piola_err = std::max(piola_err, (P - tau * F.inverse().transpose()).norm() / P.norm());
  }
  const double energy = kirchhoffLoveEnergy(points, m, x);
  const double energy_exact = psi * grid.faces() * h * h * thickness;
  const double e_err = std::abs(energy - energy_exact) / energy_exact;
  const double tol = 1e-12;
  std::printf(
      "[figure] %s stretch (%.2f, %.2f): energy %.10e vs closed form %.10e (rel %.1e), "
      "max |tau - tau_exact|/|tau| %.1e, |P - tau F^-T|/|P| %.1e (tol %.0e)\n",
      name, s1, s2, energy, energy_exact, e_err, tau_err, piola_err, tol);
  EXPECT_LT(e_err, tol);
  EXPECT_LT(tau_err, tol);
  EXPECT_LT(piola_err, tol);
}

TEST(ShellKirchhoffLove, UniformStretchMatchesClosedForm) {
  checkUniformStretch("equibiaxial", 1.3, 1.3);
  checkUniformStretch("uniaxial", 1.5, 1.0);
  checkUniformStretch("biaxial tension-compression", 1.4, 0.8);
}

// Bend a flat strip onto a cylinder of radius R: control points on a circle of radius
// rho = 3R / (2 + cos theta), so the limit points of the nodes, (P_{i-1} + 4 P_i + P_{i+1}) / 6,
// lie on radius R at arc spacing R theta = h (no mid-surface stretch, up to O(theta^4)).
double bendingRatio(ThicknessRule rule, double* measured_energy_density) {
  const BSplineGrid grid{8, 2};
  const double h = 0.05, R = 1.0, thickness = 0.01;
  const HenckyLamina m(1.0e5, 0.3);
  const Points X = grid.flat(h);
  KirchhoffLoveQuadrature quadrature;
  quadrature.thickness_rule = rule;
  const auto points =
      buildKirchhoffLovePoints(grid.faces(), grid.source(), X, thickness, quadrature);
  const double theta = h / R, rho = 3.0 * R / (2.0 + std::cos(theta));
  const double centre = 0.5 * (grid.columns() - 1);
  Points x(X.size());
  for (int j = 0; j < grid.rows(); ++j)
    for (int i = 0; i < grid.columns(); ++i) {
      const double phi = (i - centre) * theta;
      x[grid.index(i, j)] = Eigen::Vector3d(rho * std::sin(phi), h * j, rho * std::cos(phi));
    }
  const double area = grid.faces() * h * h;
  *measured_energy_density = kirchhoffLoveEnergy(points, m, x) / area;
  const double kappa = 1.0 / R;
  return *measured_energy_density / (0.5 * m.bendingStiffness(thickness) * kappa * kappa);
}

TEST(ShellKirchhoffLove, PureBendingEnergyAgainstPlateStiffness) {
  double gauss_density, han_density;
  const double gauss = bendingRatio(ThicknessRule::kGauss, &gauss_density);
  const double han = bendingRatio(ThicknessRule::kHanQuarter, &han_density);
  const double tol = 0.01, tol_ratio = 1e-3;
  std::printf(
      "[figure] cylinder R = 1, tau = 0.01: energy/area over D kappa^2/2: Gauss +-tau/(2 "
      "sqrt3) %.5f (tol +-%.2f of 1), Han +-tau/4 %.5f (tol +-%.2f of 0.75), Han/Gauss "
      "%.5f (tol +-%.0e of 0.75)\n",
      gauss, tol, han, tol, han / gauss, tol_ratio);
  EXPECT_NEAR(gauss, 1.0, tol);
  EXPECT_NEAR(han, 0.75, tol);
  EXPECT_NEAR(han / gauss, 0.75, tol_ratio);
}

TEST(ShellKirchhoffLove, ReturnMappingProjectsAssociatively) {
  const HenckyLamina m(1.0e3, 0.3, 10.0);
  const double c = m.yieldStress();
  auto flow_residual = [&](const Eigen::Vector2d& trial, const Eigen::Vector2d& tau) {
    // Plastic log strain increment A^{-1} (tau_tr - tau) must be parallel to grad f(tau).
    const Eigen::Vector2d dep = m.principalLogStretch(trial - tau);
    const Eigen::Vector2d n(2 * tau(0) - tau(1), 2 * tau(1) - tau(0));
    const double cross = dep(0) * n(1) - dep(1) * n(0);
    EXPECT_GT(dep.dot(n), 0.0);
    return std::abs(cross) / (dep.norm() * n.norm());
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-4.0 * c, 4.0 * c);
  double yield_err = 0.0, flow_err = 0.0;
  int outside = 0, inside = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector2d trial(u(rng), u(rng));
    const Eigen::Vector2d tau = m.projectPrincipalStress(trial);
    if (HenckyLamina::vonMises(trial) <= c) {
      ++inside;
      EXPECT_EQ(tau, trial);
      continue;
    }
    ++outside;
    yield_err = std::max(yield_err, std::abs(HenckyLamina::vonMises(tau) - c) / c);
    flow_err = std::max(flow_err, flow_residual(trial, tau));
  }
  // Uniaxial closed form: at tau* = (sqrt(3/2) c, 0) the normal is (2, -1); a trial state
  // tau* + k A (2, -1) must return exactly to tau*, with plastic strain ratio -1/2.
  const Eigen::Vector2d tau_star(std::sqrt(1.5) * c, 0.0);
  const Eigen::Vector2d trial = tau_star + m.principalStress(Eigen::Vector2d(2.0, -1.0) * 0.01);
  const Eigen::Vector2d tau = m.projectPrincipalStress(trial);
  const Eigen::Vector2d dep = m.principalLogStretch(trial - tau);
  const double uniaxial_err = (tau - tau_star).norm() / c;
  const double ratio = dep(1) / dep(0);
  const double tol = 1e-10;
  std::printf(
      "[figure] von Mises return (%d outside, %d inside): max |f_vM - c|/c %.1e, max "
      "flow misalignment %.1e; uniaxial return error %.1e, plastic strain ratio %.12f "
      "(closed form -0.5) (tol %.0e)\n",
      outside, inside, yield_err, flow_err, uniaxial_err, ratio, tol);
  EXPECT_GT(outside, 100);
  EXPECT_GT(inside, 100);
  EXPECT_LT(yield_err, tol);
  EXPECT_LT(flow_err, tol);
  EXPECT_LT(uniaxial_err, tol);
  EXPECT_NEAR(ratio, -0.5, tol);
}

TEST(ShellKirchhoffLove, DentingKeepsDecompositionOnCurvedShell) {
  CurvedCase c;
  const HenckyLamina m(1.0e4, 0.3, 50.0);
  auto points = buildKirchhoffLovePoints(c.grid.faces(), c.grid.source(), c.X, c.thickness);
  const int yielded = updateKirchhoffLovePlasticity(points, m, c.x);
  double product_err = 0.0, yield_err = 0.0, normal_err = 0.0;
  for (const auto& q : points) {
    const Eigen::Matrix3d F = q.deformationGradient(c.x);
    const Eigen::Matrix3d Fe = q.trialElasticDeformation(c.x);
    product_err = std::max(product_err, (Fe * q.plasticDeformation() - F).norm() / F.norm());
    // F^{KL,P} leaves the reference normal alone (5.8).
    const Eigen::Vector3d e3 = q.laminaFrame().col(2);
    normal_err = std::max(normal_err, (q.plasticDeformation() * e3 - e3).norm());
    const Eigen::Matrix3d tau = m.kirchhoffStress(Fe, q.laminaFrame());
    const Eigen::Matrix3d dev = tau - tau.trace() / 3.0 * Eigen::Matrix3d::Identity();
    yield_err = std::max(yield_err, std::abs(dev.norm() / m.yieldStress() - 1.0));
  }
  const double tol = 1e-10;
  std::printf(
      "[figure] curved denting (%d of %zu yielded): max |F^E F^P - F|/|F| %.1e, max "
      "|F^P e3 - e3| %.1e, max |f_vM/c - 1| %.1e (tol %.0e)\n",
      yielded, points.size(), product_err, normal_err, yield_err, tol);
  EXPECT_GT(yielded, 0);
  EXPECT_LT(product_err, tol);
  EXPECT_LT(normal_err, tol);
  EXPECT_LT(yield_err, tol);
}

// Stretch a flat patch (uniaxial strain), update plasticity, release. A low yield stress leaves a
// permanent stretch F^P: the patch is stress free at x = F^P X, not at X. A high one springs back.
TEST(ShellKirchhoffLove, LoadUnloadPermanentStrain) {
  const BSplineGrid grid{3, 3};
  const double h = 0.1, thickness = 0.01, stretch = 1.2;
  const Points X = grid.flat(h);
  const Eigen::Matrix3d load = Eigen::Vector3d(stretch, 1.0, 1.0).asDiagonal();
  const Points x_loaded = transformed(X, load, Eigen::Vector3d::Zero());
  const double tol = 1e-10;
  for (double yield : {20.0, 1.0e4}) {
    const HenckyLamina m(2.0e3, 0.3, yield);
    auto points = buildKirchhoffLovePoints(grid.faces(), grid.source(), X, thickness);
    const double loaded_energy = kirchhoffLoveEnergy(points, m, x_loaded);
    const int yielded = updateKirchhoffLovePlasticity(points, m, x_loaded);
    const Eigen::Matrix3d Fp = points.front().plasticDeformation();
    // Closed form: project tau_tr = A (log 1.2, 0); plastic log strain = trial - elastic.
    const Eigen::Vector2d trial_strain(std::log(stretch), 0.0);
    const Eigen::Vector2d elastic_strain =
        m.principalLogStretch(m.projectPrincipalStress(m.principalStress(trial_strain)));
    const Eigen::Vector2d plastic_exact = trial_strain - elastic_strain;
    const Eigen::Vector2d plastic(std::log(Fp(0, 0)), std::log(Fp(1, 1)));
    const double unloaded_energy = kirchhoffLoveEnergy(points, m, X);
    Points g;
    const Points x_rest = transformed(X, Fp, Eigen::Vector3d::Zero());
    const double rest_energy = kirchhoffLoveEnergy(points, m, x_rest, &g);
    double g_max = 0.0;
    for (const auto& v : g) g_max = std::max(g_max, v.cwiseAbs().maxCoeff());
    std::printf(
        "[figure] c_vM = %g: %d of %zu yielded; permanent log strain (%.6f, %.6f) vs "
        "closed form (%.6f, %.6f); energy loaded %.4e, at X %.4e, at F^P X %.1e, max "
        "force there %.1e\n",
        yield, yielded, points.size(), plastic(0), plastic(1), plastic_exact(0), plastic_exact(1),
        loaded_energy, unloaded_energy, rest_energy, g_max);
    EXPECT_LT((plastic - plastic_exact).norm(), tol);
    EXPECT_LT(rest_energy, tol * loaded_energy);
    EXPECT_LT(g_max, tol * m.youngsModulus() * thickness * h);
    if (yield < 100.0) {
      EXPECT_EQ(yielded, static_cast<int>(points.size()));
      EXPECT_GT(plastic(0), 0.05);
      EXPECT_GT(unloaded_energy, 0.01 * loaded_energy);
    } else {
      EXPECT_EQ(yielded, 0);
      EXPECT_EQ(Fp, Eigen::Matrix3d::Identity());
      EXPECT_LT(unloaded_energy, tol * loaded_energy);
    }
  }
}

TEST(ShellKirchhoffLove, GaussLegendreRule) {
  double worst = 0.0;
  for (int n = 1; n <= 5; ++n) {
    std::vector<double> t, w;
    gaussLegendreUnit(n, t, w);
    for (int p = 0; p <= 2 * n - 1; ++p) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += w[i] * std::pow(t[i], p);
      worst = std::max(worst, std::abs(sum - 1.0 / (p + 1)));
    }
  }
  std::printf(
      "[figure] Gauss-Legendre n = 1..5 on [0,1], max error on t^p, p <= 2n-1: %.1e "
      "(tol 1e-14)\n",
      worst);
  EXPECT_LT(worst, 1e-14);
}

TEST(ShellKirchhoffLove, BadInputThrows) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(HenckyLamina(0.0, 0.3), InputError);
  EXPECT_THROW(HenckyLamina(-1.0, 0.3), InputError);
  EXPECT_THROW(HenckyLamina(nan, 0.3), InputError);
  EXPECT_THROW(HenckyLamina(inf, 0.3), InputError);
  EXPECT_THROW(HenckyLamina(1.0, -1.0), InputError);
  EXPECT_THROW(HenckyLamina(1.0, 0.6), InputError);
  EXPECT_THROW(HenckyLamina(1.0, nan), InputError);
  EXPECT_THROW(HenckyLamina(1.0, 0.3, 0.0), InputError);
  EXPECT_THROW(HenckyLamina(1.0, 0.3, -5.0), InputError);
  EXPECT_THROW(HenckyLamina(1.0, 0.3, nan), InputError);
  EXPECT_NO_THROW(HenckyLamina(1.0, 0.5, inf));

  const BSplineGrid grid{1, 1};
  const Points X = grid.flat(0.1);
  EXPECT_THROW(buildKirchhoffLovePoints(1, grid.source(), X, 0.0), InputError);
  KirchhoffLoveQuadrature zero_order;
  zero_order.in_plane_order = 0;
  EXPECT_THROW(buildKirchhoffLovePoints(1, grid.source(), X, 0.01, zero_order), InputError);
  // Stencil naming a control point that does not exist.
  const FaceStencilFunction out_of_range = [&](int f, double u, double v) {
    SurfaceStencil s = grid.stencil(f, u, v);
    s.points[5] = static_cast<int>(X.size());
    return s;
  };
  EXPECT_THROW(buildKirchhoffLovePoints(1, out_of_range, X, 0.01), InputError);
  // All control points on a line: no tangent plane.
  Points line = X;
  for (auto& p : line) p.y() = 0.0;
  EXPECT_THROW(buildKirchhoffLovePoints(1, grid.source(), line, 0.01), InputError);
  // Thickness beyond the radius of curvature (R ~ 0.1): the inner lamina folds over.
  Points tube(X.size());
  for (int j = 0; j < grid.rows(); ++j)
    for (int i = 0; i < grid.columns(); ++i) {
      const double phi = 0.6 * (i - 1.5);
      tube[grid.index(i, j)] = Eigen::Vector3d(0.1 * std::sin(phi), 0.1 * j, 0.1 * std::cos(phi));
    }
  EXPECT_NO_THROW(buildKirchhoffLovePoints(1, grid.source(), tube, 0.01));
  EXPECT_THROW(buildKirchhoffLovePoints(1, grid.source(), tube, 0.5), InputError);
  std::printf("[figure] bad input: 10 material, 5 quadrature cases rejected with InputError\n");
}

}  // namespace
}  // namespace chs
