// Discrete elastic rods (core/rod): the energy's derivatives against finite differences, and the
// static validation cases of the rod codes (anchors.md, "Hair and rods"): the heavy cantilever
// under gravity against a shooting solve of the gravity elastica over a range of the gravity
// number rho g A L^3 / EI, a rod closed into a circle by the end moment 2 pi EI / L, and a
// helical rest shape that stays exactly at rest. Bad input is refused with InputError.
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/discrete_elastic_rod.h"
#include "cloth_hair_sim/core/rod/strand_newton_solver.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"
#include "cloth_hair_sim/core/solver/banded_cholesky.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

// An elliptic section of order-one numbers, so that finite differences resolve every term.
RodMaterial unitMaterial() {
  RodMaterial m;
  m.youngs_modulus = 1.0;
  m.shear_modulus = 0.4;
  m.radius_1 = 0.1;
  m.radius_2 = 0.06;
  m.density = 1.0;
  return m;
}

// A helix with its vertices and angles moved off the rest shape, committed there.
DiscreteElasticRod perturbedHelix() {
  DiscreteElasticRod rod(helicalStrand(Vec3::Zero(), Vec3::UnitZ(), 0.3, 0.4, 1.5, 6),
                         unitMaterial(), Vec3(1, 0, 0));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd q = rod.configuration();
  for (int k = 0; k < q.size(); ++k) q[k] += (k % 4 == 3 ? 0.4 : 0.05) * u(rng);
  EXPECT_TRUE(rod.setConfiguration(q));
  rod.commit();
  return rod;
}

TEST(RodElasticity, GradientMatchesFiniteDifferences) {
  DiscreteElasticRod rod = perturbedHelix();
  const Eigen::VectorXd q = rod.configuration();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(rod.numDofs());
  rod.addElasticDerivatives(&g, nullptr, false);
  const double h = 1e-6;
  double worst = 0.0;
  for (int k = 0; k < q.size(); ++k) {
    Eigen::VectorXd a = q, b = q;
    a[k] += h;
    b[k] -= h;
    rod.setConfiguration(a);
    const double ea = rod.elasticEnergy();
    rod.setConfiguration(b);
    const double eb = rod.elasticEnergy();
    worst = std::max(worst, std::abs((ea - eb) / (2 * h) - g[k]));
  }
  std::printf("rod gradient vs central differences: max error %.3e (|g| max %.3e)\n", worst,
              g.cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-6 * g.cwiseAbs().maxCoeff());
}

TEST(RodElasticity, HessianMatchesFiniteDifferences) {
  DiscreteElasticRod rod = perturbedHelix();
  const Eigen::VectorXd q = rod.configuration();
  chs::SymmetricBandMatrix H(rod.numDofs(), rod.hessianBandwidth());
  rod.addElasticDerivatives(nullptr, &H, false);
  const Eigen::MatrixXd Hd = H.dense();
  // Second differences of the energy, every configuration transported from q.
  const double h = 1e-4;
  const auto energy = [&](int k, double sk, int l, double sl) {
    Eigen::VectorXd x = q;
    x[k] += sk;
    x[l] += sl;
    rod.setConfiguration(x);
    return rod.elasticEnergy();
  };
  double worst = 0.0;
  for (int k = 0; k < q.size(); ++k)
    for (int l = k; l < q.size(); ++l) {
      const double fd =
          (energy(k, h, l, h) - energy(k, h, l, -h) - energy(k, -h, l, h) + energy(k, -h, l, -h)) /
          (4 * h * h);
      worst = std::max(worst, std::abs(fd - Hd(k, l)));
    }
  const double scale = Hd.cwiseAbs().maxCoeff();
  std::printf("rod Hessian vs second differences: max error %.3e (|H| max %.3e)\n", worst, scale);
  EXPECT_LT(worst, 1e-5 * scale);
}

// The strand's banded Cholesky against Eigen's dense one: a random SPD band matrix (the open
// strand's half-bandwidth 10, and a full band as a ring's), a shifted singular one, and an
// indefinite one it must refuse.
TEST(RodElasticity, BandedCholeskyAgreesWithDenseCholesky) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& [n, kd] : {std::pair{99, 10}, std::pair{40, 39}, std::pair{7, 6}}) {
    chs::SymmetricBandMatrix a(n, kd);
    for (int c = 0; c < n; ++c) {
      for (int r = c + 1; r <= std::min(n - 1, c + kd); ++r) a.add(r, c, u(rng));
      a.add(c, c, 2.0 * kd + 1.0);  // diagonally dominant
    }
    const Eigen::MatrixXd dense = a.dense();
    Eigen::VectorXd b(n);
    for (int k = 0; k < n; ++k) b[k] = u(rng);
    chs::BandedCholesky llt;
    ASSERT_TRUE(llt.factorize(a));
    const Eigen::VectorXd x = llt.solve(b), reference = dense.llt().solve(b);
    const double error = (x - reference).norm() / reference.norm();
    std::printf("banded Cholesky, n %d, kd %d: relative difference from dense LLT %.2e\n", n, kd,
                error);
    EXPECT_LT(error, 1e-13);
    a.add(n / 2, n / 2, -4.0 * kd - 2.0);  // a negative pivot
    EXPECT_FALSE(llt.factorize(a));
    EXPECT_THROW(llt.solve(b), std::logic_error);
  }
  chs::SymmetricBandMatrix singular(2, 1);  // [1 1; 1 1]
  singular.add(0, 0, 1.0);
  singular.add(1, 1, 1.0);
  singular.add(1, 0, 1.0);
  chs::BandedCholesky llt;
  EXPECT_FALSE(llt.factorize(singular));
  ASSERT_TRUE(llt.factorize(singular, 1e-3));
  const Eigen::Vector2d x = llt.solve(Eigen::Vector2d(1.0, 0.0));
  EXPECT_NEAR(x[0], 1.001 / (1.001 * 1.001 - 1.0), 1e-6);
  EXPECT_THROW(singular.add(3, 1, 1.0), std::logic_error);  // beyond the matrix
}

// Root vertex, first edge and its angle held: a clamp.
std::vector<char> clampedRoot(const DiscreteElasticRod& rod) {
  std::vector<char> held(rod.numDofs(), 0);
  for (int k = 0; k < 7; ++k) held[k] = 1;
  return held;
}

// The gravity elastica of a cantilever clamped horizontally at s = 0, in units of L and with
// theta the tangent's angle below the horizontal: theta'' = -gamma (1 - s) cos theta,
// theta(0) = 0, theta'(1) = 0, gamma = rho g A L^3 / EI; shot on theta'(0) in [0, gamma / 2]
// (RK4, bisection). Returns the tip (x, -z) / L.
Eigen::Vector2d gravityElasticaTip(double gamma) {
  const int n = 4000;
  Eigen::Vector2d tip;
  auto shoot = [&](double k0) {
    double y[4] = {0.0, k0, 0.0, 0.0};  // theta, theta', x, depth
    auto rhs = [&](double s, const double* v, double* d) {
      d[0] = v[1];
      d[1] = -gamma * (1.0 - s) * std::cos(v[0]);
      d[2] = std::cos(v[0]);
      d[3] = std::sin(v[0]);
    };
    const double h = 1.0 / n;
    for (int i = 0; i < n; ++i) {
      const double s = i * h;
      double k1[4], k2[4], k3[4], k4[4], t[4];
      rhs(s, y, k1);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k1[j];
      rhs(s + 0.5 * h, t, k2);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k2[j];
      rhs(s + 0.5 * h, t, k3);
      for (int j = 0; j < 4; ++j) t[j] = y[j] + h * k3[j];
      rhs(s + h, t, k4);
      for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    tip = {y[2], y[3]};
    return y[1];
  };
  double lo = 0.0, hi = 0.5 * gamma;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid) < 0.0 ? lo : hi) = mid;
  }
  shoot(0.5 * (lo + hi));
  return tip;
}

// Real hair (E = 3.5 GPa, r = 40 um), its length chosen for the gravity number, 40 segments,
// loaded in increments of gravity (10, or 50 at gamma = 100) from a straight horizontal start. A
// clamp holds the first edge (its vertices and frame); the bending of vertex 1 spans the Voronoi
// region from that edge's midpoint, which is therefore where the elastic rod begins: the strand is
// built with its root vertex half a segment behind the clamp point x = 0, its free length L beyond
// it.
TEST(RodElasticity, HeavyCantileverMatchesGravityElastica) {
  const RodMaterial hair = humanHair();
  const double g = 9.81, B = hair.bendingStiffness1();
  for (double gamma : {0.1, 1.0, 10.0, 100.0}) {
    const double L = std::cbrt(gamma * B / (hair.linearDensity() * g));
    const int n = 40;
    const double h = L / (n - 0.5);
    DiscreteElasticRod rod(straightStrand(Vec3(-0.5 * h, 0, 0), Vec3::UnitX(), n * h, n), hair);
    StrandLoads loads;
    loads.held = clampedRoot(rod);
    int iterations = 0;
    bool converged = true;
    const int increments = std::max(10, static_cast<int>(gamma / 2));
    for (int step = 1; step <= increments; ++step) {
      loads.gravity = Vec3(0, 0, -g * step / increments);
      StrandNewtonSettings s;
      s.max_iterations = 60;
      const StrandNewtonResult r = solveStrand(rod, loads, s);
      iterations += r.iterations;
      converged = converged && r.converged;
    }
    EXPECT_TRUE(converged) << "gamma " << gamma;
    const Vec3 tip = rod.positions().back();
    const Eigen::Vector2d ref = gravityElasticaTip(gamma);
    const double error = std::hypot(tip.x() / L - ref.x(), -tip.z() / L - ref.y());
    std::printf(
        "gravity elastica gamma %6.1f (L = %.1f mm): tip (%.5f, %.5f) L, shooting (%.5f, %.5f) "
        "L, linear w %.5f L; |error| %.2e L, %d Newton iterations\n",
        gamma, L * 1e3, tip.x() / L, -tip.z() / L, ref.x(), ref.y(), gamma / 8.0, error,
        iterations);
    EXPECT_LT(error, 0.01);
    if (gamma <= 0.1) {
      EXPECT_NEAR(-tip.z() / L, gamma / 8.0, 0.02 * gamma / 8.0);
    }
  }
}

// First bending mode of a clamped hair: released from the static shape under a small uniform
// load, the tip oscillates at omega_1 = 1.8751^2 sqrt(EI / (rho A L^4)) (Euler-Bernoulli). Steps
// of 1e-3 s resolve the period (about 0.54 s) to O((omega dt)^2) = 1e-4; backward Euler's damping
// shrinks the amplitude but hardly moves the zero crossings. Period from the tip's first and
// fourth upward crossings of its rest height.
TEST(RodElasticity, CantileverFirstNaturalFrequency) {
  const RodMaterial hair = humanHair();
  const double L = 0.1;
  const int n = 40;
  const double h = L / (n - 0.5);
  DiscreteElasticRod rod(straightStrand(Vec3(-0.5 * h, 0, 0), Vec3::UnitX(), n * h, n), hair);
  StrandLoads loads;
  loads.held = clampedRoot(rod);
  loads.gravity = Vec3(0, 0, -0.01);  // a small load: a linear static shape, close to mode 1
  solveStrand(rod, loads);
  loads.gravity.setZero();
  loads.dt = 1e-3;
  Eigen::VectorXd q_prev = rod.configuration();
  std::vector<double> crossings;
  double z_prev = rod.positions().back().z();
  for (int step = 1; step <= 3000 && crossings.size() < 4; ++step) {
    const Eigen::VectorXd q = rod.configuration();
    loads.inertial_target = 2.0 * q - q_prev;
    q_prev = q;
    solveStrand(rod, loads);
    const double z = rod.positions().back().z();
    if (z_prev < 0.0 && z >= 0.0)  // upward through the rest height, interpolated
      crossings.push_back(loads.dt * (step - 1 + -z_prev / (z - z_prev)));
    z_prev = z;
  }
  ASSERT_EQ(crossings.size(), 4u);
  const double period = (crossings[3] - crossings[0]) / 3.0;
  const double omega = std::pow(1.8751, 2) * std::sqrt(hair.bendingStiffness1() /
                                                       (hair.linearDensity() * std::pow(L, 4)));
  const double reference = 2 * M_PI / omega;
  std::printf(
      "clamped 10 cm hair, first mode: period %.5f s, Euler-Bernoulli %.5f s, error "
      "%.2f %%\n",
      period, reference, 100.0 * (period / reference - 1.0));
  EXPECT_NEAR(period, reference, 0.01 * reference);
}
// MuJoCo's CantileverIntoCircle: the end moment M = 2 pi EI / L bends a clamped rod into a
// full circle (radius L / 2 pi, the tip back at the root with the root's tangent). The elastic
// length runs from the midpoint of the clamped first edge to the midpoint of the last edge, on
// whose angle the moment acts (see the cantilever); the edge midpoints are compared with the
// circle.
TEST(RodElasticity, EndMomentClosesCircle) {
  const RodMaterial hair = humanHair();
  const double L = 0.05;
  const int n = 50;
  const double h = L / (n - 1);
  DiscreteElasticRod rod(straightStrand(Vec3(-0.5 * h, 0, 0), Vec3::UnitX(), n * h, n), hair);
  StrandLoads loads;
  loads.held = clampedRoot(rod);
  // In the plane y = 0: a moment about a fixed axis is conservative (the potential -M phi of
  // the tip's angle) only for planar bending.
  for (int i = 0; i <= n; ++i) loads.held[DiscreteElasticRod::vertexDof(i) + 1] = 1;
  loads.tip_moment_axis = Vec3::UnitY();
  double tip_angle = 0.0;
  const int increments = 24;
  bool converged = true;
  for (int step = 1; step <= increments; ++step) {
    loads.tip_moment = 2.0 * M_PI * hair.bendingStiffness1() / L * step / increments;
    StrandNewtonSettings s;
    s.max_iterations = 60;
    converged = solveStrand(rod, loads, s, &tip_angle).converged && converged;
  }
  EXPECT_TRUE(converged);
  const auto& x = rod.positions();
  const Vec3 tip = 0.5 * (x[n - 1] + x[n]);
  const double R = L / (2 * M_PI);
  // The circle's centre lies at distance R from the clamp point, normal to the root tangent.
  const Vec3 centre = R * Vec3(0, 0, tip_angle > 0 ? -1 : 1);
  double radius_error = 0.0;
  for (int j = 0; j < n; ++j)
    radius_error = std::max(radius_error, std::abs((0.5 * (x[j] + x[j + 1]) - centre).norm() - R));
  const Vec3 t_tip = rod.tangent(rod.numEdges() - 1);
  std::printf(
      "end moment 2 pi EI / L: tip %.3e L from the root, tip tangent . root tangent %.6f, tip "
      "rotation %.4f rad (2 pi = %.4f), max |r - L / 2 pi| %.3e L\n",
      tip.norm() / L, t_tip.x(), tip_angle, 2 * M_PI, radius_error / L);
  EXPECT_LT(tip.norm() / L, 0.01);
  EXPECT_NEAR(std::abs(tip_angle), 2 * M_PI, 0.01 * 2 * M_PI);
  EXPECT_LT(radius_error / L, 0.01);
}

// A curl (helix of radius 5 mm, pitch 8 mm) is its own rest shape: implicit steps without
// gravity leave it where it is, frames and all.
TEST(RodElasticity, HelicalRestShapeStaysAtRest) {
  DiscreteElasticRod rod(helicalStrand(Vec3::Zero(), Vec3::UnitZ(), 0.005, 0.008, 0.1, 60),
                         humanHair());
  const Eigen::VectorXd q0 = rod.configuration();
  StrandLoads loads;
  loads.dt = 1.0 / 240.0;
  loads.held = clampedRoot(rod);
  Eigen::VectorXd q_prev = q0;
  for (int step = 0; step < 50; ++step) {
    const Eigen::VectorXd q = rod.configuration();
    loads.inertial_target = 2.0 * q - q_prev;  // q + dt qdot
    q_prev = q;
    solveStrand(rod, loads);
  }
  const double drift = (rod.configuration() - q0).cwiseAbs().maxCoeff();
  std::printf(
      "helical rest shape after 50 steps of 1/240 s: max drift %.3e (m or rad), energy "
      "%.3e J\n",
      drift, rod.elasticEnergy());
  EXPECT_LT(drift, 1e-12);
  EXPECT_LT(rod.elasticEnergy(), 1e-20);
}

// Michell's instability (anchors.md): a ring of a naturally straight rod with total twist Phi
// buckles out of its plane at Phi_c = 2 pi sqrt(3) B / GJ = 2 pi sqrt(3) (1 + nu) for a round
// section. The twisted circle is an equilibrium for every Phi (by symmetry); it is stable while
// the Hessian of the energy has no negative eigenvalue beyond the ring's seven zero modes (three
// translations, three rotations, a uniform turn of the frames). The twist enters as the natural
// twist -Phi / n of each vertex of the untwisted ring (the energy depends on m - m~ only).
// Hair's moduli give nu = E / 2G - 1 = 0.966; the section is thickened so that the stretching
// and bending eigenvalues stay within the eigen-solver's resolution.
TEST(RodElasticity, MichellTwistedRingInstability) {
  RodMaterial m = humanHair();
  m.radius_1 = 1e-3;
  const double L = 0.2;
  const int n = 80;
  std::vector<Vec3> ring(n);
  const double R = L / (2 * M_PI);
  for (int i = 0; i < n; ++i)
    ring[i] = R * Vec3(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.0);
  DiscreteElasticRod rod(ring, m, Vec3::UnitZ(), true);
  const std::vector<Eigen::Vector2d> straight(n, Eigen::Vector2d::Zero());
  // The polygon's own equilibrium radius (bending pulls it in against its stretching).
  rod.setNaturalShape(straight, std::vector<double>(n, 0.0));
  StrandNewtonSettings s;
  s.max_iterations = 50;
  const StrandNewtonResult relaxed = solveStrand(rod, StrandLoads{}, s);
  EXPECT_TRUE(relaxed.converged);
  const double scale = m.bendingStiffness1() / (L * L * L);
  const auto lowest = [&](double phi) {
    rod.setNaturalShape(straight, std::vector<double>(n, -phi / n));
    chs::SymmetricBandMatrix H(rod.numDofs(), rod.hessianBandwidth());
    rod.addElasticDerivatives(nullptr, &H, false);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(H.dense(), Eigen::EigenvaluesOnly);
    return es.eigenvalues()[0] / scale;
  };
  const double threshold = -1e-6;
  EXPECT_GT(lowest(0.0), threshold);
  const double reference = 2 * M_PI * std::sqrt(3.0) * (1.0 + m.poissonRatio());
  double lo = 0.0, hi = 2.0 * reference;
  ASSERT_LT(lowest(hi), threshold);
  for (int it = 0; it < 24; ++it) {
    const double mid = 0.5 * (lo + hi);
    (lowest(mid) < threshold ? hi : lo) = mid;
  }
  const double critical = 0.5 * (lo + hi);
  std::printf(
      "Michell ring (n = %d, nu = %.3f): critical twist %.4f rad, 2 pi sqrt(3) (1 + nu) = "
      "%.4f rad, error %.2f %%\n",
      n, m.poissonRatio(), critical, reference, 100.0 * (critical / reference - 1.0));
  EXPECT_NEAR(critical, reference, 0.02 * reference);
}

TEST(RodElasticity, BadInputIsRefused) {
  const RodMaterial hair = humanHair();
  const auto refused = [](auto&& f, const char* what) {
    try {
      f();
      ADD_FAILURE() << "accepted " << what;
    } catch (const InputError& e) {
      std::printf("%-24s -> InputError: %s\n", what, e.what());
    }
  };
  std::vector<Vec3> line = straightStrand(Vec3::Zero(), Vec3::UnitX(), 0.1, 4);
  refused([&] { DiscreteElasticRod({Vec3::Zero()}, hair); }, "one vertex");
  auto dup = line;
  dup[2] = dup[1];
  refused([&] { DiscreteElasticRod(dup, hair); }, "duplicate vertices");
  auto nan = line;
  nan[3].y() = std::nan("");
  refused([&] { DiscreteElasticRod(nan, hair); }, "NaN vertex");
  auto folded = line;
  folded[2] = folded[0];
  refused([&] { DiscreteElasticRod(folded, hair); }, "folded segment");
  RodMaterial m = hair;
  m.radius_1 = -1e-5;
  refused([&] { DiscreteElasticRod(line, m); }, "negative radius");
  m = hair;
  m.radius_1 = 2.0;
  refused([&] { DiscreteElasticRod(line, m); }, "radius of 2 m");
  m = hair;
  m.youngs_modulus = 0.0;
  refused([&] { DiscreteElasticRod(line, m); }, "zero Young's modulus");
  m = hair;
  m.shear_modulus = std::nan("");
  refused([&] { DiscreteElasticRod(line, m); }, "NaN shear modulus");
  m = hair;
  m.density = 1e9;
  refused([&] { DiscreteElasticRod(line, m); }, "density 1e9");
  refused([&] { straightStrand(Vec3::Zero(), Vec3::Zero(), 0.1, 4); }, "zero direction");
  refused([&] { humanHair(0.0); }, "zero ellipticity");
}

}  // namespace
}  // namespace chs::rod
