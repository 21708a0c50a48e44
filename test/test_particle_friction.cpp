// Coulomb friction in the dynamic particle model: a cloth patch lying on an incline stays put
// iff tan(theta) <= mu, and otherwise slides with acceleration g (sin theta - mu cos theta).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"

namespace chs {
namespace {

struct Slide {
  double speed;   // mean down-slope velocity [m/s]
  double travel;  // mean down-slope displacement [m]
};

Slide slideOnIncline(double theta, double mu, double duration) {
  const double g = 9.81;
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d normal = tilt * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d down = -(tilt * Eigen::Vector3d::UnitX());  // along the slope, downhill
  DrapeProblem p;
  const int n = 3;
  const double side = 0.06;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      p.mesh.vertices.push_back(tilt * Eigen::Vector3d(side * i / n, side * j / n, 0.0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      p.mesh.quads.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  p.material = *materialPreset("cotton_eischen");  // seed 000 section 4.4
  p.gravity = Eigen::Vector3d(0, 0, -g);
  p.colliders.push_back(std::make_shared<PlaneSurface>(Eigen::Vector3d::Zero(), normal));
  ParticleDynamicsSettings s;
  s.friction = mu;
  ParticleDynamics d(p, s);
  const double dt = d.stableTimeStep();
  const int steps = static_cast<int>(std::ceil(duration / dt));
  for (int k = 0; k < steps; ++k) d.step(duration / steps);
  Slide out{0.0, 0.0};
  for (int v = 0; v < d.numVertices(); ++v) {
    out.speed += d.velocities()[v].dot(down) / d.numVertices();
    out.travel += (d.positions()[v] - p.mesh.vertices[v]).dot(down) / d.numVertices();
  }
  return out;
}

TEST(ParticleFriction, InclineSlidesIffTanThetaExceedsMu) {
  const double mu = 0.4, theta_c = std::atan(mu), g = 9.81, t = 0.1;
  const double deg = M_PI / 180.0;
  const Slide below = slideOnIncline(theta_c - deg, mu, t);
  const Slide above = slideOnIncline(theta_c + deg, mu, t);
  const double th = theta_c + deg, acc = g * (std::sin(th) - mu * std::cos(th));
  std::printf(
      "mu %.2f (onset %.2f deg): onset - 1 deg: speed %.2e m/s, travel %.2e m; onset + 1 "
      "deg: speed %.5f m/s vs %.5f, travel %.6f m vs %.6f\n",
      mu, theta_c / deg, below.speed, below.travel, above.speed, acc * t, above.travel,
      0.5 * acc * t * t);
  EXPECT_LT(std::abs(below.speed), 1e-9);
  EXPECT_LT(std::abs(below.travel), 1e-9);
  EXPECT_NEAR(above.speed, acc * t, 1e-3 * acc * t);
  EXPECT_NEAR(above.travel, 0.5 * acc * t * t, 1e-2 * 0.5 * acc * t * t);
}

TEST(ParticleFriction, FrictionlessSlidesWithGSinTheta) {
  const double theta = 0.3, t = 0.05;
  const Slide s = slideOnIncline(theta, 0.0, t);
  std::printf("frictionless, 0.3 rad: speed %.6f m/s vs g sin(theta) t = %.6f\n", s.speed,
              9.81 * std::sin(theta) * t);
  EXPECT_NEAR(s.speed, 9.81 * std::sin(theta) * t, 1e-6);
}

TEST(ParticleFriction, RejectsNonsense) {
  DrapeProblem p;
  p.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  p.mesh.quads = {{0, 1, 2, 3}};
  p.material.young = 1e5;
  p.material.poisson = 0.3;
  p.material.thickness = 1e-3;
  p.material.areal_density = 0.2;
  ParticleDynamicsSettings s;
  s.friction = -0.1;
  EXPECT_THROW(ParticleDynamics(p, s), InputError);
  ParticleDynamics d(p);
  const RigidSurfaces one = {
      std::make_shared<PlaneSurface>(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ())};
  EXPECT_THROW(d.setColliders(one, {}, {0.2, 0.3}), InputError);
  EXPECT_THROW(d.setColliders(one, {}, {std::nan("")}), InputError);
}

}  // namespace
}  // namespace chs
