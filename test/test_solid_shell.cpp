// Solid-shell element of seed 001 section 2: tangent consistency, rigid motion, the membrane
// patch test, locking-free thin cantilevers against Euler-Bernoulli and the large-deflection
// cantilever against the elastica; the woven fabric's orthotropy and its bad input.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_element.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"
#include "elastica_reference.h"
#include "plate_material.h"

namespace chs {
namespace {

using fixtures::plate;

// Random nodal displacements U_o, U_n.
SolidShellState randomState(double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SolidShellState s;
  for (auto& d : s) d = amplitude * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return s;
}

const std::array<Eigen::Vector3d, 4> kQuad = {
    Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.1, 0.1, 0), Eigen::Vector3d(1.2, 0.9, 0),
    Eigen::Vector3d(-0.1, 1, 0)};
const std::array<Eigen::Vector3d, 4> kUp = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(),
                                            Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()};

void checkDerivatives(ThicknessStrain kind) {
  const SolidShellElement el({0, 1, 2, 3}, kQuad, kUp, Eigen::Vector3d(1, 0.3, 0),
                             isotropicRigidity(plate(2e5, 0.3, 0.05)), kind);
  const SolidShellState s = randomState(0.15, 3);
  SolidShellVector f;
  SolidShellMatrix K;
  el.evaluate(s, &f, &K);
  const double eps = 1e-6;
  SolidShellMatrix Kfd;
  SolidShellVector ffd;
  for (int j = 0; j < 24; ++j) {
    SolidShellState plus = s, minus = s;
    plus[j / 3][j % 3] += eps;
    minus[j / 3][j % 3] -= eps;
    SolidShellVector fp, fm;
    const double up = el.evaluate(plus, &fp, nullptr), um = el.evaluate(minus, &fm, nullptr);
    Kfd.col(j) = (fp - fm) / (2 * eps);
    ffd[j] = (up - um) / (2 * eps);
  }
  const double ef = (f - ffd).norm() / ffd.norm(), eK = (K - Kfd).norm() / Kfd.norm();
  std::printf(
      "%s thickness strain: force vs energy differences %.2e, tangent vs force %.2e, "
      "tangent asymmetry %.2e\n",
      kind == ThicknessStrain::kGreen ? "Green" : "quasi-engineering", ef, eK,
      (K - K.transpose()).norm() / K.norm());
  EXPECT_LT(ef, 1e-7);
  EXPECT_LT(eK, 1e-6);
}

TEST(SolidShellElement, ForceAndTangentAreExactDerivativesGreen) {
  checkDerivatives(ThicknessStrain::kGreen);
}
TEST(SolidShellElement, ForceAndTangentAreExactDerivativesQuasiEngineering) {
  checkDerivatives(ThicknessStrain::kQuasiEngineering);
}

TEST(SolidShellElement, RigidMotionIsStressFree) {
  const SolidShellElement el({0, 1, 2, 3}, kQuad, kUp, Eigen::Vector3d::UnitX(),
                             isotropicRigidity(plate(2e5, 0.3, 0.05)));
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  SolidShellState s;
  for (int i = 0; i < 4; ++i) {
    s[2 * i] = Q * kQuad[i] + Eigen::Vector3d(0.3, -2, 5) - kQuad[i];
    s[2 * i + 1] = Q * kUp[i] - kUp[i];
  }
  SolidShellVector f;
  const double u = el.evaluate(s, &f, nullptr);
  std::printf("after a rigid rotation of 2.5 rad: energy %.2e, force %.2e\n", u, f.norm());
  EXPECT_LT(f.norm(), 1e-9);
}

// MacNeal-Harder membrane patch (0.24 x 0.12, five distorted quads): the boundary nodes follow
// x = F X with their directors unchanged, the four inner nodes (positions and directors) are
// free. Green strains of bilinear quads reproduce a homogeneous deformation exactly, so the
// solved inner nodes must sit at F X and the energy must be the homogeneous one.
TEST(SolidShellPatch, UniformMembraneStrainIsExact) {
  const std::vector<Eigen::Vector3d> X = {{0, 0, 0},       {0.24, 0, 0},    {0.24, 0.12, 0},
                                          {0, 0.12, 0},    {0.04, 0.02, 0}, {0.18, 0.03, 0},
                                          {0.16, 0.08, 0}, {0.08, 0.08, 0}};
  const std::vector<std::array<int, 4>> quads = {
      {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
  const ShellMaterial m = plate(1e6, 0.3, 1e-3);
  std::vector<SolidShellElement> els;
  for (const auto& q : quads)
    els.emplace_back(q, std::array<Eigen::Vector3d, 4>{X[q[0]], X[q[1]], X[q[2]], X[q[3]]}, kUp,
                     Eigen::Vector3d::UnitX(), isotropicRigidity(m));
  Eigen::Matrix3d F;
  F << 1.05, 0.02, 0, -0.01, 1.03, 0, 0, 0, 1;  // stretch in both directions: no wrinkling
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  // Nodal unknowns x_o, x_n of the 8 nodes; inner nodes start at the reference.
  std::vector<Eigen::Vector3d> xo(8), xn(8, Q * Eigen::Vector3d::UnitZ());
  for (int v = 0; v < 8; ++v) xo[v] = v < 4 ? Eigen::Vector3d(Q * F * X[v]) : X[v];
  auto energy = [&](Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    double u = 0.0;
    if (g) g->setZero(48);
    if (H) H->setZero(48, 48);
    for (const auto& el : els) {
      SolidShellState s;
      for (int i = 0; i < 4; ++i) {
        const int v = el.nodes()[i];
        s[2 * i] = xo[v] - X[v];
        s[2 * i + 1] = xn[v] - Eigen::Vector3d::UnitZ();
      }
      SolidShellVector f;
      SolidShellMatrix K;
      u += el.evaluate(s, &f, &K);
      for (int a = 0; a < 24; ++a) {
        const int A = 6 * el.nodes()[a / 6] + a % 6;
        if (g) (*g)[A] += f[a];
        if (H)
          for (int b = 0; b < 24; ++b) (*H)(A, 6 * el.nodes()[b / 6] + b % 6) += K(a, b);
      }
    }
    return u;
  };
  for (int it = 0; it < 20; ++it) {  // Newton on the 24 inner unknowns
    Eigen::VectorXd g;
    Eigen::MatrixXd H;
    energy(&g, &H);
    const Eigen::VectorXd d = H.bottomRightCorner(24, 24).fullPivLu().solve(-g.tail(24));
    for (int v = 4; v < 8; ++v)
      xo[v] += d.segment<3>(6 * (v - 4)), xn[v] += d.segment<3>(6 * (v - 4) + 3);
    if (d.norm() < 1e-14) break;
  }
  double err = 0.0;
  for (int v = 4; v < 8; ++v) err = std::max(err, (xo[v] - Q * F * X[v]).norm());
  const Eigen::Matrix2d E =
      0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity()).topLeftCorner<2, 2>();
  const Eigen::Vector3d e(E(0, 0), E(1, 1), 2 * E(0, 1));
  const double exact = 0.5 * e.dot(isotropicRigidity(m).membrane * e) * 0.24 * 0.12;
  const double u = energy(nullptr, nullptr);
  std::printf("membrane patch test: inner nodes off F X by %.2e m, energy %.10e (exact %.10e)\n",
              err, u, exact);
  EXPECT_LT(err, 1e-10);
  EXPECT_NEAR(u, exact, 1e-9 * exact);
}

// A strip of n x 1 quads along x, z = 0, clamped at x = 0, weightless.
DrapeProblem strip(int n, double L, double b, const ShellMaterial& m) {
  DrapeProblem p;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= n; ++i) p.mesh.vertices.emplace_back(L * i / n, b * (j - 0.5), 0.0);
  for (int i = 0; i < n; ++i) p.mesh.quads.push_back({i, i + 1, n + 2 + i, n + 1 + i});
  p.material = m;
  p.gravity.setZero();
  p.bc.clamped = {0, n + 1};
  return p;
}

SolidShellSettings newton() {
  SolidShellSettings s;
  s.multiplier = 1e9;  // lambda = 1: plain Newton-Raphson
  s.tolerance = 1e-7;
  s.max_iterations = 10;
  return s;
}

double tipDeflection(const DrapeProblem& p, const SolidShellSettings& s, int n) {
  const DrapeResult r = solveSolidShell(p, s);
  EXPECT_TRUE(r.converged) << r.status;
  std::printf("  (%d Newton iterations, |P - F| / |P| = %.1e)\n", r.iterations, r.residual);
  return -0.5 * (r.positions[n].z() + r.positions[2 * n + 1].z());
}

// Thin cantilevers, tip load in the linear range: no shear locking (ANS (4)) and no thickness
// locking (plane-stress enforcement) from L/t = 100 to 1000 against the Euler-Bernoulli beam
// P L^3 / (3 E I), I = b t^3 / 12. With nu = 0.3 the narrow strip (b = L / 10) bends
// anticlastically; the clamp holds that back near the root, which stiffens it by ~0.7 %.
// Thickness locking would instead stiffen it by 1 / (1 - nu^2) or more.
TEST(SolidShellBeam, ThinCantileverHasNoShearOrThicknessLocking) {
  const double L = 1.0, b = 0.1, E = 1e7;
  const int n = 20;
  for (double nu : {0.0, 0.3})
    for (double slender : {100.0, 300.0, 1000.0}) {
      const double t = L / slender;
      const ShellMaterial m = plate(E, nu, t);
      const double EI = E * b * t * t * t / 12.0;
      const double P = 1e-4 * 3 * EI / (L * L * L);  // deflection 1e-4 L
      DrapeProblem p = strip(n, L, b, m);
      for (int v : {n, 2 * n + 1})
        p.bc.loads.push_back({v, Eigen::Vector3d(0, 0, -0.5 * P), Eigen::Vector3d::Zero()});
      const double w = tipDeflection(p, newton(), n), ref = P * L * L * L / (3 * EI);
      std::printf(
          "cantilever L/t = %5.0f nu = %.1f, %d elements: tip %.6e, reference %.6e, "
          "error %+.3f %%\n",
          slender, nu, n, w, ref, 100 * (w / ref - 1));
      EXPECT_NEAR(w / ref, 1.0, 0.02);
    }
}

// Seed 000 section 4.1's tip-loaded elastica (EI = 2 sqrt(3) 1e-9, L = 1), here with the solid
// shell and the seed 001 multiplier scheme: lambda_P = P L^2 / EI = 1 .. 10.
TEST(SolidShellBeam, TipLoadedCantileverMatchesElastica) {
  const double h = 2.0 * std::sqrt(3.0) * 1e-3, EI = h * h * h / 12.0;
  const int n = 16;
  double worst = 0.0;
  SolidShellSettings s;
  s.multiplier = 0.05;
  s.tolerance = 1e-8;
  for (int lam : {1, 2, 4, 7, 10}) {
    DrapeProblem p = strip(n, 1.0, 1.0, plate(1.0, 0.0, h));
    for (int v : {n, 2 * n + 1})
      p.bc.loads.push_back({v, Eigen::Vector3d(0, 0, -0.5 * lam * EI), Eigen::Vector3d::Zero()});
    const DrapeResult r = solveSolidShell(p, s);
    EXPECT_TRUE(r.converged) << r.status;
    const Eigen::Vector3d tip = 0.5 * (r.positions[n] + r.positions[2 * n + 1]);
    const auto ref = reference::tipLoadedElastica(lam);
    const double err =
        std::max(std::abs(1.0 - tip.x() - ref.shortening), std::abs(-tip.z() - ref.deflection));
    worst = std::max(worst, err);
    std::printf(
        "elastica lambda_P = %2d: u/L %.5f (ref %.5f), w/L %.5f (ref %.5f), %d iterations\n", lam,
        1.0 - tip.x(), ref.shortening, -tip.z(), ref.deflection, r.iterations);
  }
  std::printf("tip-loaded elastica, %d solid-shell elements: max error %.3f %% of L\n", n,
              100 * worst);
  EXPECT_LT(worst, 0.005);
}

// The woven fabric's bending rigidity follows its warp: narrow strips cut along warp and weft
// deflect as P L^3 / (3 B b) with the strip's rigidity B = 1 / (C_b^-1)_11 or _22, i.e.
// B1 (1 - nu^2) and B2 (1 - nu^2) (free anticlastic bending, as above).
TEST(SolidShellWoven, WarpAndWeftStripsFollowTheirRigidities) {
  const double L = 0.05, b = 0.005;
  const int n = 10;
  WovenFabric f = *wovenFabricPreset("wool_suiting_kes");
  for (int cut = 0; cut < 2; ++cut) {
    DrapeProblem p = strip(n, L, b, plate(1e5, 0.3, f.thickness));
    f.warp = cut == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    p.fabric = f;
    const double B = 1.0 / f.bendingRigidity().inverse()(cut, cut);
    const double P = 1e-4 * 3 * B * b / (L * L * L);
    for (int v : {n, 2 * n + 1})
      p.bc.loads.push_back({v, Eigen::Vector3d(0, 0, -0.5 * P), Eigen::Vector3d::Zero()});
    const double w = tipDeflection(p, newton(), n), ref = P * L * L * L / (3 * B * b);
    std::printf("%s strip: tip %.6e m, P L^3 / (3 B b) = %.6e m, error %+.3f %%\n",
                cut == 0 ? "warp" : "weft", w, ref, 100 * (w / ref - 1));
    EXPECT_NEAR(w / ref, 1.0, 0.02);
  }
}

TEST(SolidShellWoven, FabricWithoutWarpDirectionIsBadInput) {
  DrapeProblem p = strip(4, 0.05, 0.01, plate(1e5, 0.3, 1e-3));
  p.fabric = *wovenFabricPreset("wool_suiting_kes");  // warp left at zero
  try {
    solveSolidShell(p, SolidShellSettings());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    std::printf("orthotropic fabric without directions: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("warp direction"), std::string::npos);
  }
  p.fabric->warp = Eigen::Vector3d::UnitZ();  // normal to the garment
  EXPECT_THROW(solveSolidShell(p, SolidShellSettings()), InputError);
}

}  // namespace
}  // namespace chs
