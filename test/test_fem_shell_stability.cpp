// Stability of FEM shell equilibria: the lowest eigenvalue of the symmetrised, constrained
// tangent (core/solver/stability.h) on an Euler strut, against Euler's load and the elastica.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/solver/stability.h"

namespace chs {
namespace {

constexpr double kL = 1.0, kB = 0.05, kH = 0.01, kE = 1e6;
constexpr int kCells = 32;
const double kEI = kE * kB * kH * kH * kH / 12.0;
const double kEuler = M_PI * M_PI * kEI / (kL * kL);  // pinned-pinned strut

// A flat strip along x, pinned at x = -L/2, the other end held in y and z and pushed along -x by
// P: the straight strut is an equilibrium for every P, stable below Euler's load only.
DrapeProblem strut(double P) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(kL, kB, kCells, 1);
  p.material.young = kE;
  p.material.poisson = 0.0;
  p.material.thickness = kH;
  p.material.areal_density = 0.0;
  p.gravity.setZero();
  for (int v = 0; v < p.mesh.numVertices(); ++v) {
    const double x = p.mesh.vertices[v].x();
    if (x < -0.5 * kL + 1e-9) p.bc.pinned.push_back(v);
    if (x > 0.5 * kL - 1e-9) {
      p.bc.fixed_components.push_back({v, 1});
      p.bc.fixed_components.push_back({v, 2});
      p.bc.loads.push_back({v, Eigen::Vector3d(-0.5 * P, 0, 0), Eigen::Vector3d::Zero()});
    }
  }
  return p;
}

DrapeResult solveStrut(double P, FemShellMethod method) {
  FemShellSettings s;
  s.solver = method;
  return solveFemShell(strut(P), s);
}

TEST(FemShellStability, LowestEigenvalueMatchesADenseSolver) {
  const DrapeProblem p = strut(1.2 * kEuler);
  ShellModel model(p, 0.0);
  Eigen::VectorXd R, F0;
  Eigen::SparseMatrix<double> K;
  // Newton onto the compressed straight strut (dense: a few hundred unknowns).
  for (int it = 0; it < 8; ++it) {
    model.linearize(1.0, R, F0, &K);
    model.increment(Eigen::MatrixXd(K).partialPivLu().solve(R));
  }
  model.linearize(1.0, R, F0, &K);
  ASSERT_LT(R.norm(), 1e-10 * model.loadNorm());
  const StabilityCheck c = checkStability(K);
  ASSERT_TRUE(c.computed);
  Eigen::MatrixXd S = 0.5 * (Eigen::MatrixXd(K) + Eigen::MatrixXd(K).transpose());
  const Eigen::VectorXd d = S.diagonal().cwiseAbs().cwiseSqrt().cwiseInverse();
  S = d.asDiagonal() * S * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(S);
  const double ref = dense.eigenvalues()[0];
  const int negative = static_cast<int>((dense.eigenvalues().array() < 0.0).count());
  std::printf("strut at 1.2 P_E: lowest eigenvalue %.6e (dense %.6e), negative %d (dense %d)\n",
              c.lowest_eigenvalue, ref, c.negative_eigenvalues, negative);
  EXPECT_NEAR(c.lowest_eigenvalue, ref, 1e-8 * dense.eigenvalues().cwiseAbs().maxCoeff());
  EXPECT_EQ(c.negative_eigenvalues, negative);
  EXPECT_LT(ref, 0.0);
}

// A negative eigenvalue behind a cluster of tiny positive ones (as a folding sheet's tangent
// has): the eigenvalues nearest zero are all positive, the inertia counts one below. The lowest
// must still be found, with its mode (the saddle escape moves along it). Built as Q diag(l) Q^T
// with unit diagonal, so the check's scaling leaves the spectrum as built.
TEST(FemShellStability, NegativeEigenvalueBehindTinyPositiveOnesIsFound) {
  const int n = 40;
  Eigen::VectorXd l = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  l[0] = -1e-3;
  for (int i = 1; i < 12; ++i) l[i] = 1e-7 * i;  // 11 eigenvalues nearer zero than the negative
  Eigen::MatrixXd Q = Eigen::MatrixXd::Random(n, n).householderQr().householderQ();
  Eigen::MatrixXd A = Q * l.asDiagonal() * Q.transpose();
  // Rescale to unit diagonal: a congruence (same inertia); the reference is A's own spectrum.
  const Eigen::VectorXd d = A.diagonal().cwiseAbs().cwiseSqrt().cwiseInverse();
  A = d.asDiagonal() * A * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(A);
  const StabilityCheck c = checkStability(A.sparseView());
  ASSERT_TRUE(c.computed);
  const double residual =
      (A * (c.mode / c.mode.norm()) - c.lowest_eigenvalue * c.mode / c.mode.norm()).norm();
  std::printf("lowest eigenvalue %.6e (dense %.6e), negative %d, mode residual %.2e\n",
              c.lowest_eigenvalue, dense.eigenvalues()[0], c.negative_eigenvalues, residual);
  EXPECT_EQ(c.negative_eigenvalues, 1);
  EXPECT_FALSE(c.stable);
  EXPECT_NEAR(c.lowest_eigenvalue, dense.eigenvalues()[0], 1e-8);
  EXPECT_LT(residual, 1e-8);
}

TEST(FemShellStability, StraightStrutIsStableBelowEulersLoadAndASaddleAbove) {
  // Path following keeps the strut straight; the stability check decides.
  const DrapeResult below = solveStrut(0.9 * kEuler, FemShellMethod::kArcLength);
  const DrapeResult above = solveStrut(1.1 * kEuler, FemShellMethod::kArcLength);
  std::printf("0.9 P_E: %s, lowest eigenvalue %.4e; 1.1 P_E: %s, lowest eigenvalue %.4e\n",
              below.stability.verdict.c_str(), below.stability.lowest_eigenvalue,
              above.stability.verdict.c_str(), above.stability.lowest_eigenvalue);
  std::printf("1.1 P_E status: %s\n", above.status.c_str());
  EXPECT_TRUE(below.converged) << below.status;
  EXPECT_TRUE(below.stability.stable);
  EXPECT_GT(below.stability.lowest_eigenvalue, 0.0);
  EXPECT_FALSE(above.converged) << "a saddle reported as a converged drape";
  EXPECT_TRUE(above.stability.assessed);
  EXPECT_FALSE(above.stability.stable);
  EXPECT_EQ(above.stability.negative_eigenvalues, 1);
  EXPECT_NE(above.status.find("unstable"), std::string::npos) << above.status;
  // The straight strut stays straight: the saddle is the symmetric state itself.
  double lift = 0.0;
  for (const auto& x : above.positions) lift = std::max(lift, std::abs(x.z()));
  EXPECT_LT(lift, 1e-9);

  // Where the lowest eigenvalue crosses zero: Euler's load pi^2 EI / L^2.
  double lo = 0.9, hi = 1.1;
  for (int k = 0; k < 14; ++k) {
    const double mid = 0.5 * (lo + hi);
    (solveStrut(mid * kEuler, FemShellMethod::kArcLength).stability.stable ? lo : hi) = mid;
  }
  const double critical = 0.5 * (lo + hi);
  std::printf("critical load from the eigenvalue: %.5f P_E (%d elements; error %.3f %%)\n",
              critical, kCells, 100 * std::abs(critical - 1.0));
  EXPECT_NEAR(critical, 1.0, 0.01);
}

// The elastica of a pinned strut: P / P_E = (2 K(k) / pi)^2 and midspan deflection
// delta / L = k / K(k) (Timoshenko and Gere, Theory of Elastic Stability, section 2.7), K the
// complete elliptic integral of the first kind (by the arithmetic-geometric mean).
double elasticaDeflection(double load_ratio) {
  auto K = [](double k) {
    double a = 1.0, b = std::sqrt(1.0 - k * k);
    for (int i = 0; i < 30; ++i) {
      const double an = 0.5 * (a + b);
      b = std::sqrt(a * b);
      a = an;
    }
    return M_PI / (2.0 * a);
  };
  double lo = 0.0, hi = 0.99;
  for (int i = 0; i < 60; ++i) {
    const double k = 0.5 * (lo + hi);
    (std::pow(2.0 * K(k) / M_PI, 2) < load_ratio ? lo : hi) = k;
  }
  const double k = 0.5 * (lo + hi);
  return k / K(k);
}

TEST(FemShellStability, EnergyMinimisationLeavesTheSaddleForTheBuckledStrut) {
  const double ratio = 1.1;
  const DrapeResult r = solveStrut(ratio * kEuler, FemShellMethod::kEnergyNewton);
  ASSERT_TRUE(r.converged) << r.status;
  EXPECT_TRUE(r.stability.stable);
  double delta = 0.0;
  for (const auto& x : r.positions) delta = std::max(delta, std::abs(x.z()));
  const double exact = elasticaDeflection(ratio) * kL;
  std::printf(
      "buckled strut at %.2f P_E: %s; midspan deflection %.5f m, elastica %.5f m "
      "(%.2f %%), lowest eigenvalue %.4e, %d iterations\n",
      ratio, r.status.c_str(), delta, exact, 100 * std::abs(delta - exact) / exact,
      r.stability.lowest_eigenvalue, r.iterations);
  EXPECT_NEAR(delta, exact, 0.02 * exact);
}

}  // namespace
}  // namespace chs

namespace chs {
namespace {

// The energy minimiser needs R = -grad E exactly, contacts included: central differences of the
// energy along random directions against -R . d, on a sheet bent down over a table's edges (node
// and edge contacts active, the edges falling between nodes).
TEST(FemShellEnergy, GradientOfTheEnergyIsTheResidual) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.2, 0.2, 10, 10);
  p.material.young = 2e5;
  p.material.poisson = 0.3;
  p.material.thickness = 8e-4;
  p.material.areal_density = 0.22;
  p.colliders.push_back(std::make_shared<BoxSurface>(Eigen::Vector3d(-0.047, -0.047, -0.1),
                                                     Eigen::Vector3d(0.047, 0.047, 0.0), 0.003));
  p.bc.fixed_components = {{60, 0}, {60, 1}, {65, 1}};
  ShellModel model(p, 0.0);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), R, F0;
  // Bend the overhang down: translations z = -0.4 (|x|_inf - 0.045)+ (5 unknowns per node, in
  // vertex order, as none of the z components is constrained).
  int k = 0;
  for (int v = 0; v < p.mesh.numVertices(); ++v) {
    const Eigen::Vector3d& x = p.mesh.vertices[v];
    const double over = std::max(0.0, x.head<2>().lpNorm<Eigen::Infinity>() - 0.045);
    const int free_here = (v == 60) ? 3 : (v == 65 ? 4 : 5);
    const int z = (v == 60) ? 0 : (v == 65 ? 1 : 2);
    q[k + z] = -0.4 * over - 2e-6;  // slightly into the top: node contacts active too
    k += free_here;
  }
  model.increment(q);
  model.linearize(1.0, R, F0, nullptr);
  ShellModel nodes_only(p, 0.0, false);
  nodes_only.increment(q);
  Eigen::VectorXd R0;
  nodes_only.linearize(1.0, R0, F0, nullptr);
  std::printf("active contacts: %d at nodes, %d at edges\n", nodes_only.activeContacts(),
              model.activeContacts() - nodes_only.activeContacts());
  EXPECT_GT(model.activeContacts() - nodes_only.activeContacts(), 10);
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd d(model.size());
    for (int i = 0; i < d.size(); ++i) d[i] = n01(rng);
    d *= 1e-3 / d.norm();
    const double h = std::getenv("CHS_FD_H") ? std::atof(std::getenv("CHS_FD_H")) : 1e-4;
    model.save();
    model.increment(h * d);
    const double ep = model.energy(1.0);
    model.restore();
    model.increment(-h * d);
    const double em = model.energy(1.0);
    model.restore();
    const double fd = (ep - em) / (2 * h), exact = -R.dot(d);
    const double err = std::abs(fd - exact) / std::abs(exact);
    std::printf("  direction %d: dE/dh %.9e, -R.d %.9e, rel. error %.2e\n", trial, fd, exact, err);
    worst = std::max(worst, err);
  }
  // The edges' penalty potential is integrated by Gauss quadrature on smooth pieces; what is
  // left is its error where a piece holds two changes of the gap's curvature.
  EXPECT_LT(worst, 1e-3);
  // The energy minimiser factorises the lower triangle of K: a problem with a potential must
  // have a symmetric tangent, contacts included.
  Eigen::SparseMatrix<double> K;
  model.linearize(1.0, R, F0, &K);
  const double asym = (K - Eigen::SparseMatrix<double>(K.transpose())).norm() / K.norm();
  std::printf("  tangent asymmetry |K - K^T| / |K| = %.2e\n", asym);
  EXPECT_LT(asym, 1e-12);
}

}  // namespace
}  // namespace chs

namespace chs {
namespace {

// Energy minimisation asked for a problem without a potential (Kawabata bending): InputError.
TEST(FemShellEnergy, EnergyMinimisationWithoutAPotentialIsBadInput) {
  DrapeProblem p = strut(0.5 * kEuler);
  KawabataBending k;
  k.a = {1e-3, 0, 0, 0, 0};
  p.material.kawabata = k;
  FemShellSettings s;
  s.solver = FemShellMethod::kEnergyNewton;
  try {
    solveFemShell(p, s);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    std::printf("InputError: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("potential"), std::string::npos);
  }
}

}  // namespace
}  // namespace chs
