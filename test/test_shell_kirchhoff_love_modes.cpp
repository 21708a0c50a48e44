// Stability and accuracy of the Kirchhoff-Love quadrature on Catmull-Clark limit surfaces: the
// stiffness (the Hessian of Psi^KL (5.31) at the flat reference state) of a free sheet must have
// exactly the 6 rigid-body modes as zero modes, or the rule lets the shell deform for free
// (hourglassing). The default 2 x 2 Gauss rule and 3 x 3 are checked against 4 x 4 (exact on
// regular faces) on a regular sheet and on an O-grid disc with extraordinary vertices; 1 x 1 shows
// that the check catches spurious modes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// Eigenvalues (ascending) of the Kirchhoff-Love stiffness at the reference state, by central
// differences of the exact gradient, 1 mm thick, E = 1 MPa, nu = 0.3.
Eigen::VectorXd stiffnessSpectrum(const QuadMesh& mesh, int order) {
  const LimitSurface surface(mesh);
  KirchhoffLoveQuadrature rule;
  rule.in_plane_order = order;
  const auto points = buildKirchhoffLovePoints(
      surface.numFaces(), [&](int f, double u, double v) { return surface.stencil(f, u, v); },
      mesh.vertices, 1e-3, rule);
  const HenckyLamina lamina(1e6, 0.3);
  const int n = 3 * mesh.numVertices();
  Eigen::MatrixXd K(n, n);
  std::vector<Vec3> x = mesh.vertices, plus, minus;
  const double h = 1e-7;
  for (int i = 0; i < n; ++i) {
    x[i / 3][i % 3] += h;
    kirchhoffLoveEnergy(points, lamina, x, &plus);
    x[i / 3][i % 3] -= 2.0 * h;
    kirchhoffLoveEnergy(points, lamina, x, &minus);
    x[i / 3][i % 3] += h;
    for (int j = 0; j < n; ++j) K(j, i) = (plus[j / 3][j % 3] - minus[j / 3][j % 3]) / (2.0 * h);
  }
  const Eigen::MatrixXd symmetric = 0.5 * (K + K.transpose());
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues();
}

int zeroModes(const Eigen::VectorXd& spectrum) {
  const double largest = spectrum.cwiseAbs().maxCoeff();
  return static_cast<int>((spectrum.array().abs() < 1e-9 * largest).count());
}

// Largest relative error of modes [6, 6 + count) against the reference rule.
double modeError(const Eigen::VectorXd& rule, const Eigen::VectorXd& exact, int count) {
  double e = 0.0;
  for (int k = 6; k < 6 + count; ++k) e = std::max(e, std::abs(rule[k] / exact[k] - 1.0));
  return e;
}

// 4 x 4 Gauss integrates the small-strain stiffness of a bicubic face exactly (degree 7 per
// direction): it is the reference (near extraordinary vertices, where the patches are not one
// polynomial, a close one). The long waves (the 10 softest deformation modes) carry
// drape; shorter ones, two or three faces long, are already coarse in the mesh itself.
void checkRule(const char* name, const QuadMesh& mesh) {
  const Eigen::VectorXd two = stiffnessSpectrum(mesh, 2), three = stiffnessSpectrum(mesh, 3),
                        exact = stiffnessSpectrum(mesh, 4);
  const int last = static_cast<int>(exact.size()) - 1;
  std::printf(
      "[figure] %s (%d dofs): zero modes 2 x 2: %d, 3 x 3: %d, 4 x 4: %d; error of the 10 / 20 "
      "softest deformation modes against 4 x 4: 2 x 2 %.1e / %.1e, 3 x 3 %.1e / %.1e; stiffest "
      "mode 2 x 2 / 4 x 4 = %.4f, 3 x 3 / 4 x 4 = %.4f\n",
      name, static_cast<int>(exact.size()), zeroModes(two), zeroModes(three), zeroModes(exact),
      modeError(two, exact, 10), modeError(two, exact, 20), modeError(three, exact, 10),
      modeError(three, exact, 20), two[last] / exact[last], three[last] / exact[last]);
  EXPECT_EQ(zeroModes(two), 6);
  EXPECT_EQ(zeroModes(three), 6);
  EXPECT_LT(modeError(two, exact, 10), 1.5e-2);
  EXPECT_LT(modeError(two, exact, 20), 5e-2);
  // Under-integration only softens: the stable step it allows is never shorter.
  EXPECT_LE(two[last], exact[last] * (1.0 + 1e-9));
}

TEST(ShellKirchhoffLoveModes, TwoByTwoRuleHasOnlyRigidZeroModesOnARegularSheet) {
  const QuadMesh sheet = makeRectangleMesh(0.1, 0.1, 6, 6);
  checkRule("6 x 6 sheet", sheet);
  // The 1 x 1 rule does not: the check sees spurious modes.
  const int spurious = zeroModes(stiffnessSpectrum(sheet, 1)) - 6;
  std::printf("[figure] 6 x 6 sheet, 1 x 1 rule: %d spurious zero modes\n", spurious);
  EXPECT_GT(spurious, 0);
}

TEST(ShellKirchhoffLoveModes, TwoByTwoRuleHasOnlyRigidZeroModesNearExtraordinaryVertices) {
  checkRule("O-grid disc, 8 cells across", makeDiscMesh(0.05, 8));
}

}  // namespace
}  // namespace chs
