// SurfaceCollisions (mpm/surface_collisions.h): samples of a surface, combinations of control
// points, pushed out of a collider by moving the points; closed forms on a plane.
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/mpm/surface_collisions.h"

namespace {

using chs::mpm::ColliderImpulse;
using chs::mpm::GridCollider;
using chs::mpm::SurfaceCollisions;
using Vec3 = Eigen::Vector3d;

// A row of n points along x, 1 cm apart, at height z; samples at each point (weights 1/6, 2/3,
// 1/6 of it and its neighbours, as a cubic B-spline's limit points) for the inner points.
struct Row {
  std::vector<Vec3> x, v, x_start;
  std::vector<double> mass;
  std::vector<char> movable;
  std::vector<chs::SurfaceStencil> samples;
};

Row makeRow(int n, double z) {
  Row r;
  for (int i = 0; i < n; ++i) {
    r.x.emplace_back(0.01 * i, 0.0, z);
    r.v.push_back(Vec3::Zero());
    r.mass.push_back(1e-3);
    r.movable.push_back(1);
  }
  r.x_start = r.x;
  for (int i = 1; i + 1 < n; ++i) {
    chs::SurfaceStencil s;
    s.points = {i - 1, i, i + 1};
    s.w = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
    r.samples.push_back(s);
  }
  return r;
}

std::vector<GridCollider> floorAtZero(double friction) {
  GridCollider g;
  g.surface = std::make_shared<chs::PlaneSurface>(Vec3::Zero(), Vec3::UnitZ());
  g.friction = friction;
  return {g};
}

double deepestSample(const Row& r) {
  double deepest = 0.0;
  for (const chs::SurfaceStencil& s : r.samples) deepest = std::max(deepest, -s.position(r.x).z());
  return deepest;
}

chs::mpm::SurfaceCollisionResult apply(Row& r, const std::vector<GridCollider>& colliders,
                                       double dt, std::vector<ColliderImpulse>& impulses) {
  std::vector<chs::mpm::Clearance> clearance;
  for (const Vec3& x : r.x) clearance.push_back(chs::mpm::clearanceOf(x, colliders));
  SurfaceCollisions c(r.samples);
  return c.apply(r.x, r.v, r.x_start, r.mass, r.movable, clearance, colliders, dt, impulses);
}

TEST(SurfaceCollisions, DepthFromBeforeTheStepIsRemovedWithoutAKick) {
  Row r = makeRow(8, -1e-3);  // inside by 1 mm from the start, at rest
  std::vector<ColliderImpulse> impulses;
  const auto result = apply(r, floorAtZero(0.5), 1e-3, impulses);
  std::printf(
      "[figure] resting 1 mm deep: %d of %d samples inside, %d passes, deepest left %.2e m\n",
      result.samples_inside, static_cast<int>(r.samples.size()), result.iterations,
      deepestSample(r));
  EXPECT_EQ(result.samples_inside, 6);
  EXPECT_LE(deepestSample(r), 1e-6);
  EXPECT_NEAR(result.deepest, deepestSample(r), 1e-12);  // what it reports is what is left
  for (const Vec3& v : r.v) EXPECT_EQ(v, Vec3::Zero());
  EXPECT_EQ(impulses[0].linear, Vec3::Zero());
}

TEST(SurfaceCollisions, AnApproachEndsOnTheSurfaceAndItsMomentumGoesToTheCollider) {
  const double dt = 1e-3;
  Row r = makeRow(8, -1e-3);
  for (std::size_t i = 0; i < r.x.size(); ++i) {  // came down 1.5 mm in this step
    r.v[i] = Vec3(0.0, 0.0, -1.5);
    r.x_start[i] = r.x[i] - dt * r.v[i];
  }
  std::vector<ColliderImpulse> impulses;
  apply(r, floorAtZero(0.0), dt, impulses);
  double momentum = 0.0;
  for (std::size_t i = 0; i < r.x.size(); ++i) momentum += r.mass[i] * (r.v[i].z() + 1.5);
  std::printf(
      "[figure] approach at 1.5 m/s ending 1 mm deep: deepest left %.2e m, collider "
      "impulse %.4e N s, points' momentum change %.4e N s\n",
      deepestSample(r), impulses[0].linear.z(), momentum);
  EXPECT_LE(deepestSample(r), 1e-6);
  EXPECT_NEAR(impulses[0].linear.z(), momentum, 1e-15);
  EXPECT_GT(momentum, 0.0);
  // Position-based: each moved point's velocity is its displacement over the step.
  for (std::size_t i = 0; i < r.x.size(); ++i) {
    EXPECT_NEAR(r.v[i].z(), (r.x[i].z() - r.x_start[i].z()) / dt, 1e-9);
  }
}

TEST(SurfaceCollisions, FrictionStopsASlideAsCoulombAllows) {
  const double dt = 1e-3, depth = 1e-3, slide = 0.4e-3;
  for (double mu : {0.2, 1.0}) {
    Row r = makeRow(8, -depth);
    for (std::size_t i = 0; i < r.x.size(); ++i) {  // came down 1 mm and slid 0.4 mm along x
      r.x_start[i] = r.x[i] - Vec3(slide, 0.0, -depth);
      r.v[i] = (r.x[i] - r.x_start[i]) / dt;
    }
    std::vector<ColliderImpulse> impulses;
    apply(r, floorAtZero(mu), dt, impulses);
    // The middle sample's slide: cut by mu times the 1 mm push, or stopped.
    const chs::SurfaceStencil& s = r.samples[3];
    const double left = (s.position(r.x) - s.position(r.x_start)).x();
    const double expected = std::max(0.0, slide - mu * depth);
    std::printf("[figure] mu %.1f: slide %.3f mm left of 0.4 mm (Coulomb: %.3f mm)\n", mu,
                1e3 * left, 1e3 * expected);
    EXPECT_NEAR(left, expected, 0.02 * slide);
  }
}

TEST(SurfaceCollisions, ASampleHeldMostlyByPinnedPointsIsLeftToThem) {
  Row r = makeRow(3, -1e-3);
  r.movable[1] = 0;  // the sample's 2/3 weight is prescribed
  const std::vector<Vec3> before = r.x;
  std::vector<ColliderImpulse> impulses;
  const auto result = apply(r, floorAtZero(0.5), 1e-3, impulses);
  EXPECT_EQ(result.samples_inside, 1);
  EXPECT_EQ(r.x, before);
}

}  // namespace
