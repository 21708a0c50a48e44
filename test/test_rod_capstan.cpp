// The capstan (Euler-Eytelwein): a flexible strand wrapped over a rigid cylinder by theta with
// Coulomb friction mu, pulled at one end by T1, is held at the other end by no less than
// T2 = T1 e^{-mu theta} while it slides. The friction acts inside each strand's implicit solve
// (rod/obstacle_contact.h), where the tension is solved; the hair body in a world, no gravity.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

struct CapstanResult {
  double hold = 0.0;    // T2 the clamp applies while the strand slides [N]
  double spread = 0.0;  // its largest relative deviation over the averaging window
  int iterations = 0;   // most Newton iterations (all lag passes) of a step
};

// A strand of human hair: a lead of `lead` m along +y onto a vertical cylinder of radius R at
// (R + r, 0), a wrap of theta about it (rising by `pitch` per turn: a helix for theta = 2 pi),
// and a lead off along the wrap's end tangent. Its root (the first lead's start) is clamped;
// the tip is pulled along the second lead by a force raised to T1 over 0.05 s. Naturally
// straight. After 0.1 s at rest the clamp feeds the strand towards the cylinder at 1 cm/s; T2 is
// the clamp's pull, averaged over the last 0.05 s of 0.2 s of sliding.
CapstanResult capstan(double theta, double mu, double pitch) {
  const double R = 0.015, lead = 0.02, h = 1e-3, T1 = 0.1, dt = 1.0 / 240.0, feed = 0.01;
  const RodMaterial hair = humanHair();
  const double rc = R + hair.radius_1;
  std::vector<Vec3> x;
  const int n_lead = static_cast<int>(std::round(lead / h));
  for (int k = 0; k < n_lead; ++k) x.emplace_back(rc, -lead + k * h, 0.0);
  const int n_arc = static_cast<int>(std::round(theta * rc / h));
  for (int k = 0; k <= n_arc; ++k) {
    const double phi = theta * k / n_arc;
    x.emplace_back(rc * std::cos(phi), rc * std::sin(phi), pitch * phi / (2.0 * M_PI));
  }
  const Vec3 out(-std::sin(theta), std::cos(theta), 0.0);
  for (int k = 1; k <= n_lead; ++k) x.push_back(x[n_lead + n_arc] + k * h * out);

  WorldSettings ws;
  ws.grid_spacing = 0.01;
  World world(ws);
  HairSettings hs;
  hs.grid_spacing = ws.grid_spacing;
  hs.gravity.setZero();
  auto body = std::make_shared<HairDynamics>(hs);
  world.add("hair", body);
  const int s = body->addStrand(x, hair, true);
  const int nv = static_cast<int>(x.size());
  body->setNaturalShape(s, std::vector<Eigen::Vector2d>(nv, Eigen::Vector2d::Zero()),
                        std::vector<double>(nv, 0.0));
  world.setColliders({std::make_shared<CylinderSurface>(Eigen::Vector2d::Zero(), R, -0.05, 0.05)},
                     {}, {mu});

  CapstanResult r;
  const int ramp = 12, settle = 24, slide = 48, window = 12;
  std::vector<double> pulls;
  for (int step = 1; step <= settle + slide; ++step) {
    body->setVertexForce(s, nv - 1, std::min(1.0, double(step) / ramp) * T1 * out);
    if (step > settle) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation() = Vec3(0.0, feed * (step - settle) * dt, 0.0);
      body->setRootFrame(s, pose);
    }
    world.step(dt);
    r.iterations = std::max(r.iterations, body->lastNewtonIterations());
    if (step > settle + slide - window) pulls.push_back(-body->clampWrench(s).force.y());
  }
  for (double p : pulls) r.hold += p / pulls.size();
  for (double p : pulls) r.spread = std::max(r.spread, std::abs(p - r.hold) / r.hold);
  return r;
}

// The half wrap at mu = 0.2, 0.3, 0.5 (mu theta up to 1.6); mu = 0 is the check that the
// normal contact alone passes T1 through unchanged. The lagged normal forces are relaxed between
// passes (ObstacleContactSettings). The full wrap: HelicalFullWrapOnOneThread.
TEST(Capstan, HoldRatioIsExpMuTheta) {
  const double T1 = 0.1;
  struct Case {
    double theta, pitch;
  };
  for (const Case c : {Case{M_PI, 0.0}})
    for (double mu : {0.0, 0.2, 0.3, 0.5}) {
      const CapstanResult r = capstan(c.theta, mu, c.pitch);
      const double ratio = T1 / r.hold, expected = std::exp(mu * c.theta);
      const double error = std::abs(ratio - expected) / expected;
      std::printf(
          "capstan theta = %.4f rad (pitch %.1f mm), mu = %.2f: T1 = %.4f N, T2 = %.5e N "
          "(spread %.1e), T1/T2 = %.4f, e^(mu theta) = %.4f, error %.2f %%; Newton <= %d\n",
          c.theta, 1e3 * c.pitch, mu, T1, r.hold, r.spread, ratio, expected, 100.0 * error,
          r.iterations);
      EXPECT_LT(error, 0.05);
    }
}

// The helical full wrap (theta = 2 pi, pitch 1 mm), on one thread. At mu = 0.3 the round-off of
// the grid transfer's sums decides whether the strand stays on the cylinder: when those sums
// followed the threads' work stealing, it left it (T2 = T1) in 2 runs of 3 on two threads. The
// transfer now sums in an order fixed by the number of threads (mpm/transfers.cpp), so a run is
// the same on every run with as many threads; on one thread the figure is also the same on every
// machine.
TEST(Capstan, HelicalFullWrapOnOneThread) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const double T1 = 0.1, theta = 2.0 * M_PI;
  for (double mu : {0.2, 0.3}) {
    const CapstanResult r = capstan(theta, mu, 1e-3);
    const double ratio = T1 / r.hold, expected = std::exp(mu * theta);
    const double error = std::abs(ratio - expected) / expected;
    std::printf(
        "helical capstan theta = 2 pi (pitch 1 mm), mu = %.2f, one thread: T1/T2 = %.4f, "
        "e^(mu theta) = %.4f, error %.2f %% (spread %.1e); Newton <= %d\n",
        mu, ratio, expected, 100.0 * error, r.spread, r.iterations);
    EXPECT_LT(error, 0.05);
  }
}

}  // namespace
}  // namespace chs::rod
