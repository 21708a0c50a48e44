// Drape metrics against closed forms: Cusick drape coefficient of a flat disc (1) and of a disc
// whose hanging part is a vertical cylinder skirt (0), fold count of synthetic skirts with
// r(theta) = R0 + a cos(n theta). Each case prints its measured figure.
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/drape/drape_metrics.h"
#include "cloth_hair_sim/core/io/collider_spec.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"

namespace {

using chs::DrapeMetrics;
using chs::DrapeSupport;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 0.127, kRd = 0.0635;  // seed 001: 25.4 cm disc on a 12.7 cm pedestal

DrapeSupport pedestal(double radius) {
  DrapeSupport s;
  s.area = kPi * radius * radius;
  return s;
}

// Draped positions of a flat disc: the part beyond rd is mapped by skirt(theta, s) (s = distance
// hanging past the rim) to a point, the rest left on the top.
template <class Skirt>
std::vector<Vector3d> drapeDisc(const chs::QuadMesh& mesh, double rd, const Skirt& skirt) {
  std::vector<Vector3d> p;
  for (const auto& v : mesh.vertices) {
    const double r = v.head<2>().norm(), theta = std::atan2(v.y(), v.x());
    p.push_back(r <= rd ? v : skirt(theta, r - rd));
  }
  return p;
}

TEST(DrapeMetrics, FlatDiscHasCoefficientOne) {
  const chs::QuadMesh mesh = chs::makeDiscMesh(kR, 32);
  const DrapeMetrics m = chs::measureDrape(mesh, mesh.vertices, pedestal(kRd));
  std::cout << "  flat disc: A_D " << m.flat_area << " (pi R^2 " << kPi * kR * kR << "), A_s "
            << m.shadow_area << " +- " << m.shadow_area_error_bound << ", DC "
            << m.drape_coefficient << ", folds " << m.folds << "\n";
  // Raster error 2048 cells across: the bound is P h sqrt(2) = 0.11 %; the measured error is
  // well inside it, and the coefficient must be 1 within 2e-3.
  EXPECT_NEAR(m.shadow_area, m.flat_area, m.shadow_area_error_bound);
  EXPECT_NEAR(m.drape_coefficient, 1.0, 2e-3);
  EXPECT_EQ(m.folds, 0);  // a round outline: no maximum stands out by 2 % of its radius
  EXPECT_NEAR(m.lowest_z, 0.0, 1e-15);
  EXPECT_NEAR(m.max_radius, kR, 1e-12);
}

TEST(DrapeMetrics, ShadowOfUnitSquareAndOverlap) {
  // Two unit squares overlapping by half: the union is 1.5, not the sum 2.
  chs::QuadMesh mesh;
  mesh.vertices = {{0, 0, 0},    {1, 0, 0},    {1, 1, 0},    {0, 1, 0},
                   {0.5, 0, -1}, {1.5, 0, -1}, {1.5, 1, -1}, {0.5, 1, -1}};
  mesh.quads = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  double bound = 0.0;
  const double a = chs::shadowArea(mesh, mesh.vertices, 2048, &bound);
  std::cout << "  overlapping squares: shadow " << a << " (exact 1.5), bound " << bound << "\n";
  EXPECT_NEAR(a, 1.5, bound);
  EXPECT_NEAR(a, 1.5, 1e-3);
  EXPECT_NEAR(chs::surfaceArea(mesh, mesh.vertices), 2.0, 1e-12);
}

TEST(DrapeMetrics, VerticalSkirtHasCoefficientZero) {
  const chs::QuadMesh mesh = chs::makeDiscMesh(kR, 32);
  const auto p = drapeDisc(mesh, kRd, [](double theta, double s) {
    return Vector3d(kRd * std::cos(theta), kRd * std::sin(theta), -s);
  });
  const DrapeMetrics m = chs::measureDrape(mesh, p, pedestal(kRd));
  std::cout << "  cylinder skirt: A_s " << m.shadow_area << " (A_d " << m.support_area << "), DC "
            << m.drape_coefficient << ", lowest " << m.lowest_z << " (exact " << -(kR - kRd)
            << ")\n";
  // The shadow is the polygon through the rim's 4 m nodes, inscribed in the support circle:
  // short of pi rd^2 by ~(2 pi / 4m)^2 / 6 plus the raster error, i.e. DC ~ -1e-3.
  EXPECT_NEAR(m.drape_coefficient, 0.0, 3e-3);
  EXPECT_NEAR(m.lowest_z, -(kR - kRd), 1e-12);
  EXPECT_NEAR(m.max_radius, kRd, 1e-12);
  EXPECT_EQ(m.folds, 0);
}

TEST(DrapeMetrics, ConicalSkirtCoefficient) {
  // Hanging part on a cone at angle alpha from the vertical: the shadow is a disc of radius
  // rd + (R - rd) sin(alpha), so DC = ((rd + (R - rd) sin a)^2 - rd^2) / (R^2 - rd^2).
  const double alpha = 0.5;
  const chs::QuadMesh mesh = chs::makeDiscMesh(kR, 64);
  const auto p = drapeDisc(mesh, kRd, [&](double theta, double s) {
    const double r = kRd + s * std::sin(alpha);
    return Vector3d(r * std::cos(theta), r * std::sin(theta), -s * std::cos(alpha));
  });
  const DrapeMetrics m = chs::measureDrape(mesh, p, pedestal(kRd));
  const double rs = kRd + (kR - kRd) * std::sin(alpha);
  const double exact = (rs * rs - kRd * kRd) / (kR * kR - kRd * kRd);
  std::cout << "  conical skirt: DC " << m.drape_coefficient << " (exact " << exact << ")\n";
  // The mesh is a polygon of the disc: O(1e-3) area defect on both A_s and A_D.
  EXPECT_NEAR(m.drape_coefficient, exact, 5e-3);
}

// Synthetic fold pattern: outline r(theta) = R0 + a cos(n theta), hanging skirt below the rim.
DrapeMetrics sinusoidalSkirt(int n, double a, double phase = 0.3, int cells = 48) {
  const chs::QuadMesh mesh = chs::makeDiscMesh(kR, cells);
  const double r0 = 0.09;
  const auto p = drapeDisc(mesh, kRd, [&](double theta, double s) {
    const double t = s / (kR - kRd);  // 0 at the rim, 1 at the hem: folds grow downwards
    const double r = kRd + t * (r0 - kRd + a * std::cos(n * (theta - phase)));
    return Vector3d(r * std::cos(theta), r * std::sin(theta), -s * 0.8);
  });
  return chs::measureDrape(mesh, p, pedestal(kRd));
}

TEST(DrapeMetrics, SinusoidalSkirtFoldCount) {
  for (int n : {4, 6, 8, 10, 12}) {
    const DrapeMetrics m = sinusoidalSkirt(n, 0.01);
    std::cout << "  r = R0 + 1 cm cos(" << n << " theta): " << m.folds << " folds, outline r "
              << m.min_outline_radius << " - " << m.max_outline_radius << ", DC "
              << m.drape_coefficient << "\n";
    EXPECT_EQ(m.folds, n);
    // Crests evenly spaced at phase + 2 pi k / n, within two bins plus the smoothing's symmetry.
    for (double angle : m.fold_angles) {
      const double k = (angle - 0.3) * n / (2 * kPi);
      EXPECT_NEAR(k, std::round(k), n * 0.02 / (2 * kPi) * 2 + 1e-9) << "crest at " << angle;
    }
  }
}

TEST(DrapeMetrics, FoldThresholdRejectsRipples) {
  // 0.5 mm ripples sit below the 1 mm / 2 % prominence floor: no folds; 4 mm ones count.
  EXPECT_EQ(sinusoidalSkirt(8, 0.00025).folds, 0);
  EXPECT_EQ(sinusoidalSkirt(8, 0.002).folds, 8);
  // 12 folds survive on a coarse 24-across disc whose rim has few nodes per fold.
  const DrapeMetrics coarse = sinusoidalSkirt(12, 0.01, 0.3, 24);
  std::cout << "  12 folds on a 24-across disc: " << coarse.folds << "\n";
  EXPECT_EQ(coarse.folds, 12);
}

TEST(DrapeMetrics, PeriodicPeaksProminence) {
  // One big peak, a second one and its shoulder of prominence 0.05, and the wrap-around.
  // Equal peaks do not shadow each other (so all n crests of a sinusoid count).
  const std::vector<double> s = {0, 1, 0, 0.5, 0.4, 0.45, 0.0};
  EXPECT_EQ(chs::periodicPeaks(s, 0.02), (std::vector<int>{1, 3, 5}));
  EXPECT_EQ(chs::periodicPeaks(s, 0.1), (std::vector<int>{1, 3}));
  EXPECT_EQ(chs::periodicPeaks({1, 0, 0, 0.2, 0}, 0.1), (std::vector<int>{0, 3}));
  EXPECT_TRUE(chs::periodicPeaks({1, 1, 1, 1}, 0.0).empty());
}

TEST(DrapeMetrics, SupportAndPenetration) {
  chs::ColliderSpec c;
  c.type = chs::ColliderSpec::Type::kCylinder;
  c.axis_xy = Eigen::Vector2d(0.1, 0.2);
  c.radius = 0.1;
  c.z_bottom = -0.5;
  c.z_top = 0.0;
  EXPECT_NEAR(chs::supportOf(c).area, kPi * 0.01, 1e-15);
  EXPECT_EQ(chs::supportOf(c).axis_xy, c.axis_xy);
  chs::ColliderSpec box;
  box.type = chs::ColliderSpec::Type::kBox;
  box.lo = Vector3d(-0.05, -0.1, -0.2);
  box.hi = Vector3d(0.05, 0.1, 0.0);
  EXPECT_NEAR(chs::supportOf(box).area, 0.02, 1e-15);
  const chs::RigidSurfaces surfaces = {c.makeSurface()};
  EXPECT_NEAR(chs::maxPenetration({{0.1, 0.2, 0.001}, {0.1, 0.2, -0.003}}, surfaces), 0.003, 1e-12);
  EXPECT_EQ(chs::maxPenetration({{0.1, 0.2, 0.001}}, surfaces), 0.0);
}

}  // namespace
