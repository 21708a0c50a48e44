// The CFL speed from the motion (core/mpm/approach_speed.h): zero for a body that moves as a whole
// (Galilean invariance) or with the obstacle it lies on, the relative speed where a particle may
// reach an obstacle or another body within the longest step, and nothing beyond that reach; within
// a body whose field acts between layers only, only the speed at which one layer closes in.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/mpm/approach_speed.h"

namespace chs::mpm {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kSupport = 0.03;  // (degree + 1) dx for dx = 1 cm, quadratic kernel
constexpr double kStep = 1.0 / 60.0;

// A 10 x 10 sheet of particles 1 cm apart in the plane z = z0, all with velocity v.
MotionGroup sheet(double z0, const Vec3& v, bool self) {
  MotionGroup g;
  g.self = self;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      g.x.emplace_back(0.01 * i, 0.01 * j, z0);
      g.v.push_back(v);
    }
  return g;
}

GridCollider floorMoving(const Vec3& v) {
  GridCollider c;
  c.surface = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ());
  c.velocity.linear = v;
  return c;
}

TEST(ApproachSpeed, ABodyMovingAsAWholeApproachesNothing) {
  const Vec3 v(1.2, -0.4, 3.0);
  const double w = approachSpeed({sheet(0.5, v, true)}, {}, kSupport, kStep);
  std::printf("uniform translation at %.2f m/s: approach speed %.3g m/s\n", v.norm(), w);
  EXPECT_EQ(w, 0.0);
}

TEST(ApproachSpeed, ARotatingBodyApproachesItselfAtItsVelocityDifferences) {
  // Spinning about z at 2 rad/s: two particles d apart differ by 2 d in velocity. Neighbouring
  // cells span at most twice the cell (support + 2 * fastest * step) per axis.
  MotionGroup g = sheet(0.0, Vec3::Zero(), true);
  const double omega = 2.0;
  double fastest = 0.0;
  for (std::size_t p = 0; p < g.x.size(); ++p) {
    g.v[p] = Vec3(0, 0, omega).cross(g.x[p]);
    fastest = std::max(fastest, g.v[p].norm());
  }
  const double w = approachSpeed({g}, {}, kSupport, kStep);
  const double cell = kSupport + 2.0 * fastest * kStep;
  std::printf("rotation at %.1f rad/s over a 9 cm sheet: approach speed %.3g m/s (cells %.3g m)\n",
              omega, w, cell);
  EXPECT_GT(w, omega * 0.01);                           // at least neighbouring particles'
  EXPECT_LE(w, std::sqrt(3.0) * omega * 0.09 + 1e-12);  // at most the box of all velocities
  // The same motion does not count within a body whose field has no forces between its particles.
  g.self = false;
  EXPECT_EQ(approachSpeed({g}, {}, kSupport, kStep), 0.0);
}

TEST(ApproachSpeed, AnObstacleCountsWhereItCanBeReached) {
  // Resting 1 cm above a floor that moves with the sheet: no approach.
  const Vec3 v(0.0, 0.0, -2.0);
  EXPECT_EQ(approachSpeed({sheet(0.01, v, false)}, {floorMoving(v)}, kSupport, kStep), 0.0);
  // Falling at 2 m/s onto a still floor 1 cm below: 2 m/s.
  EXPECT_DOUBLE_EQ(
      approachSpeed({sheet(0.01, v, false)}, {floorMoving(Vec3::Zero())}, kSupport, kStep), 2.0);
  // 5 cm above it: the support (3 cm) plus 2 m/s over 1/60 s (3.3 cm) still reaches it.
  EXPECT_DOUBLE_EQ(
      approachSpeed({sheet(0.05, v, false)}, {floorMoving(Vec3::Zero())}, kSupport, kStep), 2.0);
  // 10 cm above it: out of reach within the longest step, so no bound from it.
  EXPECT_EQ(approachSpeed({sheet(0.10, v, false)}, {floorMoving(Vec3::Zero())}, kSupport, kStep),
            0.0);
}

TEST(ApproachSpeed, TwoBodiesCountWhereTheyCanMeet) {
  const Vec3 down(0.0, 0.0, -1.5);
  // A sheet falling at 1.5 m/s onto one at rest 2 cm below: at least 1.5, at most sqrt 3 x 1.5.
  const double near = approachSpeed({sheet(0.02, down, false), sheet(0.0, Vec3::Zero(), false)}, {},
                                    kSupport, kStep);
  std::printf("sheet falling at 1.5 m/s, 2 cm above another: approach speed %.3g m/s\n", near);
  EXPECT_GE(near, 1.5);
  EXPECT_LE(near, 1.5 * std::sqrt(3.0) + 1e-12);
  // Both falling together: nothing.
  EXPECT_EQ(approachSpeed({sheet(0.02, down, false), sheet(0.0, down, false)}, {}, kSupport, kStep),
            0.0);
  // 30 cm apart: beyond the support and twice the fastest travel (3 + 5 cm), no bound.
  EXPECT_EQ(approachSpeed({sheet(0.30, down, false), sheet(0.0, Vec3::Zero(), false)}, {}, kSupport,
                          kStep),
            0.0);
}

TEST(ApproachSpeed, ALayerAwareBodyCountsOnlyItsOtherLayersClosingIn) {
  // The rotating sheet of the test above, its pairs all on one layer: nothing to bound.
  MotionGroup turning = sheet(0.0, Vec3::Zero(), true);
  for (std::size_t p = 0; p < turning.x.size(); ++p)
    turning.v[p] = Vec3(0, 0, 2.0).cross(turning.x[p]);
  turning.one_layer = [](int, int, double) { return true; };
  EXPECT_NEAR(approachSpeed({turning}, {}, kSupport, kStep), 0.0, 1e-15);
  // Shrinking towards its corner at 5 /s, it closes in on itself: pairs d apart at 5 d, those
  // that come within the support in the step, d (1 - 5 / 60) < 3 cm: the farthest such pair on
  // the 1 cm lattice is sqrt(10) cm apart.
  MotionGroup shrinking = turning;
  for (std::size_t p = 0; p < shrinking.x.size(); ++p) shrinking.v[p] = -5.0 * shrinking.x[p];
  const double closing = approachSpeed({shrinking}, {}, kSupport, kStep);
  std::printf("one layer shrinking at 5 /s: approach %.4g m/s (closed form %.4g)\n", closing,
              5.0 * std::sqrt(10.0) * 0.01);
  EXPECT_NEAR(closing, 5.0 * std::sqrt(10.0) * 0.01, 1e-12);

  // A folded sheet: particles 0-99 one layer, 100-199 the other, z0 above it.
  const auto folded = [](double z0, const Vec3& v) {
    MotionGroup g = sheet(z0, v, true);
    const MotionGroup lower = sheet(0.0, Vec3::Zero(), true);
    g.x.insert(g.x.end(), lower.x.begin(), lower.x.end());
    g.v.insert(g.v.end(), lower.v.begin(), lower.v.end());
    g.one_layer = [](int p, int q, double) { return (p < 100) == (q < 100); };
    return g;
  };
  const Vec3 down(0.0, 0.0, -1.5), across(1.5, 0.0, 0.0);
  // The upper layer falling at 1.5 m/s from 2 cm, or from 5 cm (it comes to 2.5 cm, within the
  // 3 cm support, in 1/60 s): its own speed, pair by pair, not the boxes' up to sqrt 3 times it.
  for (double z0 : {0.02, 0.05}) {
    const double w = approachSpeed({folded(z0, down)}, {}, kSupport, kStep);
    std::printf("upper layer %.0f cm above the lower, falling at 1.5 m/s: approach %.4g m/s\n",
                100 * z0, w);
    EXPECT_DOUBLE_EQ(w, 1.5);
  }
  // From 6 cm it stays 3.5 cm away; 20 cm above it sliding across it never closes in.
  EXPECT_EQ(approachSpeed({folded(0.06, down)}, {}, kSupport, kStep), 0.0);
  EXPECT_EQ(approachSpeed({folded(0.20, across)}, {}, kSupport, kStep), 0.0);
  // Sliding across it 2 cm above: within the support, so it counts.
  EXPECT_DOUBLE_EQ(approachSpeed({folded(0.02, across)}, {}, kSupport, kStep), 1.5);
}

TEST(MotionTimeStep, BoundsTheApproachNotTheSpeed) {
  const double travel = 0.3 * 0.01;  // cfl dx
  const Vec3 down(0.0, 0.0, -2.0);
  const GridCollider still = floorMoving(Vec3::Zero());
  // Falling at 2 m/s with nothing in reach, or onto a floor that falls with it: the longest step.
  EXPECT_EQ(motionTimeStep({sheet(0.5, down, true)}, {still}, kSupport, travel, kStep), kStep);
  EXPECT_EQ(motionTimeStep({sheet(0.01, down, true)}, {floorMoving(down)}, kSupport, travel, kStep),
            kStep);
  // Onto a still floor 1 cm or 5 cm below: cfl dx per step at 2 m/s, 1.5 ms.
  for (double z : {0.01, 0.05}) {
    const double h = motionTimeStep({sheet(z, down, true)}, {still}, kSupport, travel, kStep);
    std::printf("sheet %.0f cm above a still floor at 2 m/s: step %.4g s (longest %.4g s)\n",
                100 * z, h, kStep);
    EXPECT_DOUBLE_EQ(h, travel / 2.0);
  }
}

}  // namespace
}  // namespace chs::mpm
