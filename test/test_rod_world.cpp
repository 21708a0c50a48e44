// Hair as a body of the world (core/rod/hair_dynamics.h, Han section 4.2): the stages of a step
// conserve momentum, a strand on a table reports its weight through World::colliderLoads(),
// axial stick-slip on a plane follows Coulomb's law (PyElastica's friction validation case),
// real hair (E = 3.5 GPa, r = 40 um) steps stably at 1/240 s and 1/60 s, clamps follow a moving
// root frame, a curl stays at rest and sags to its static equilibrium under gravity, a strand
// rests on a garment of the same world, snapshots restore, bodies stepped side by side end as
// each stepped alone, the clamp carries the strand's weight and moment, strands draped over a
// horizontal capsule (a comb) load it with their weight, a bar appearing deep in hair is left at
// the recovery speed, a grip carries a lock's weight and moment as it lifts it and lets it fall
// when removed, and bad input is refused.
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/io/state_stream.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/rod/strand_newton_solver.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"
#include "cloth_hair_sim/core/world/world.h"
#include "cloth_test_material.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kDx = 0.01;  // grid spacing [m]
constexpr double kG = 9.81;

struct HairWorld {
  World world;
  std::shared_ptr<HairDynamics> hair;
};

std::unique_ptr<HairWorld> hairWorld(const HairSettings& settings) {
  WorldSettings ws;
  ws.grid_spacing = kDx;
  auto w = std::make_unique<HairWorld>(HairWorld{World(ws), nullptr});
  w->hair = std::make_shared<HairDynamics>(settings);
  w->world.add("hair", w->hair);
  return w;
}

HairSettings settings(const Vec3& gravity = Vec3(0, 0, -kG)) {
  HairSettings s;
  s.grid_spacing = kDx;
  s.gravity = gravity;
  return s;
}

Vec3 centreOfMass(const HairDynamics& hair, int s) {
  const DiscreteElasticRod& rod = hair.strand(s);
  Vec3 c = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < rod.numVertices(); ++i) {
    c += rod.vertexMass(i) * rod.positions()[i];
    m += rod.vertexMass(i);
  }
  return c / m;
}

// A free wavy strand without gravity or obstacles, thrown with random vertex velocities: the
// implicit rod update, the APIC transfers and the blend (4.12) keep its linear momentum.
TEST(HairWorld, MomentumThroughGridStages) {
  auto w = hairWorld(settings(Vec3::Zero()));
  const int s = w->hair->addStrand(
      wavyStrand(Vec3(0.02, 0.03, 0.05), Vec3::UnitX(), Vec3::UnitZ(), 0.005, 0.02, 0.06, 30),
      humanHair(), false);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.05);
  std::vector<Vec3> v(w->hair->strand(s).numVertices());
  for (Vec3& u : v) u = Vec3(n(rng), n(rng), n(rng));
  w->hair->setVelocities(s, v);
  const Vec3 p0 = w->hair->linearMomentum();
  double worst = 0.0;
  for (int step = 0; step < 20; ++step) {
    w->world.step(1.0 / 240.0);
    worst = std::max(worst, (w->hair->linearMomentum() - p0).norm() / p0.norm());
  }
  std::printf("hair momentum over 20 world steps: max relative change %.3e (|p| %.3e kg m/s)\n",
              worst, p0.norm());
  EXPECT_LT(worst, 1e-9);
}

// The world steps its bodies' stages side by side (World::forEachBody): a body's stage must touch
// nothing but its own state. Two tufts of hair half a metre apart (no shared grid node), with
// strand collisions and random velocities, stepped together end bit for bit where each ends
// stepped alone in a world of its own.
TEST(HairWorld, BodiesSideBySideStepAsAlone) {
  HairSettings hs = settings();
  hs.strand_collisions.enabled = true;
  const auto tuft = [&](const Vec3& root, unsigned seed) {
    auto hair = std::make_shared<HairDynamics>(hs);
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 0.2);
    for (int k = 0; k < 6; ++k) {
      const Vec3 at = root + Vec3(0.002 * k, 0.001 * (k % 2), 0.0);
      const int s = hair->addStrand(straightStrand(at, Vec3(0.3, 0.1, -1).normalized(), 0.05, 12),
                                    humanHair());
      std::vector<Vec3> v(hair->strand(s).numVertices());
      for (Vec3& u : v) u = Vec3(n(rng), n(rng), n(rng));
      hair->setVelocities(s, v);
    }
    return hair;
  };
  WorldSettings ws;
  ws.grid_spacing = kDx;
  World both(ws), first(ws), second(ws);
  const Vec3 a(0.0, 0.0, 0.2), b(0.5, 0.0, 0.2);
  auto a1 = tuft(a, 1), b1 = tuft(b, 2), a2 = tuft(a, 1), b2 = tuft(b, 2);
  both.add("a", a1);
  both.add("b", b1);
  first.add("a", a2);
  second.add("b", b2);
  const std::vector<Vec3> tip_start = a2->strand(0).positions();
  for (int step = 0; step < 20; ++step) {
    both.step(1.0 / 240.0);
    first.step(1.0 / 240.0);
    second.step(1.0 / 240.0);
  }
  double apart = 0.0;
  for (const auto& [together, alone] : {std::pair{a1, a2}, std::pair{b1, b2}})
    for (int s = 0; s < together->numStrands(); ++s)
      for (int i = 0; i < together->strand(s).numVertices(); ++i)
        apart = std::max(
            apart, (together->strand(s).positions()[i] - alone->strand(s).positions()[i]).norm());
  const double moved = (a2->strand(0).positions().back() - tip_start.back()).norm();
  std::printf(
      "two tufts stepped side by side against each alone: %.3e m apart (a tip moved "
      "%.2e m)\n",
      apart, moved);
  EXPECT_EQ(apart, 0.0);
  EXPECT_GT(moved, 0.0);
}

// A straight strand lying on a table (its centreline a radius above it): its weight reaches the
// table through the contact in the implicit solve, and it stays where it lies.
TEST(HairWorld, StrandOnTableReportsWeight) {
  auto w = hairWorld(settings());
  const int s = w->hair->addStrand(
      straightStrand(Vec3(0.0, 0.0, humanHair().radius_1), Vec3::UnitX(), 0.05, 20), humanHair(),
      false);
  w->world.setColliders({std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ())}, {}, {0.5});
  const std::vector<Vec3> x0 = w->hair->strand(s).positions();
  for (int step = 0; step < 60; ++step) w->world.step(1.0 / 240.0);
  const Vec3 f = w->world.colliderLoads()[0].force;
  const double weight = w->hair->totalMass() * kG;
  double moved = 0.0;
  for (int i = 0; i < static_cast<int>(x0.size()); ++i)
    moved = std::max(moved, (w->hair->strand(s).positions()[i] - x0[i]).norm());
  std::printf(
      "strand on a table: load (%.4e, %.4e, %.4e) N, weight %.4e N, error %.2e; moved "
      "%.2e m\n",
      f.x(), f.y(), f.z(), weight, std::abs(-f.z() - weight) / weight, moved);
  EXPECT_NEAR(-f.z(), weight, 0.01 * weight);
  EXPECT_LT(std::hypot(f.x(), f.y()), 1e-6 * weight);
  EXPECT_LT(moved, 1e-7);
}

// PyElastica's axial friction case: a strand on a plane with mu = 0.4 pulled along its axis at
// one end by F. Below mu m g it stays put; above, its centre accelerates at (F - mu m g) / m.
// The friction acts in the implicit solve (obstacle_contact.h); a stuck strand creeps at a
// fraction of its eps_v, 1e-7 m/s.
TEST(HairWorld, AxialStickSlip) {
  const double mu = 0.4, dt = 1.0 / 240.0;
  for (double ratio : {0.5, 0.9, 1.5, 3.0}) {
    auto w = hairWorld(settings());
    const int s = w->hair->addStrand(
        straightStrand(Vec3(0.0, 0.0, humanHair().radius_1), Vec3::UnitX(), 0.05, 20), humanHair(),
        false);
    w->world.setColliders({std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitZ())}, {}, {mu});
    const double m = w->hair->totalMass(), F = ratio * mu * m * kG;
    w->hair->setVertexForce(s, w->hair->strand(s).numVertices() - 1, Vec3(F, 0, 0));
    const Vec3 c0 = centreOfMass(*w->hair, s);
    const int steps = 120;
    double v_half = 0.0;
    for (int step = 1; step <= steps; ++step) {
      w->world.step(dt);
      if (step == steps / 2) v_half = w->hair->linearMomentum().x() / m;
    }
    const double v_end = w->hair->linearMomentum().x() / m;
    const double a = (v_end - v_half) / (0.5 * steps * dt);
    const double expected = std::max(0.0, (F - mu * m * kG) / m);
    const double slid = (centreOfMass(*w->hair, s) - c0).x();
    std::printf(
        "stick-slip F = %.1f mu m g: acceleration %.5f m/s^2, Coulomb %.5f m/s^2; slid "
        "%.3e m in %.2f s\n",
        ratio, a, expected, slid, steps * dt);
    if (ratio < 1.0) {
      EXPECT_LT(std::abs(slid), 1e-7);
    } else {
      EXPECT_NEAR(a, expected, 0.02 * expected);
    }
  }
}

double potentialEnergy(const HairDynamics& hair) {
  double e = 0.0;
  for (int s = 0; s < hair.numStrands(); ++s) {
    const DiscreteElasticRod& rod = hair.strand(s);
    e += rod.elasticEnergy();
    for (int i = 0; i < rod.numVertices(); ++i)
      e -= rod.vertexMass(i) * hair.settings().gravity.dot(rod.positions()[i]);
  }
  return e;
}

// Real hair, 10 cm clamped horizontally and released: an explicit step would need about
// l / c = 2.5 mm / 1640 m/s = 1.5 us. The implicit update steps at 1/240 s and 1/60 s: finite,
// no energy gained (backward Euler only dissipates), the strand inextensible to 1e-5.
TEST(HairWorld, StiffHairStableAtLargeSteps) {
  for (double dt : {1.0 / 240.0, 1.0 / 60.0}) {
    auto w = hairWorld(settings());
    const int s = w->hair->addStrand(straightStrand(Vec3(0.0, 0.0, 0.2), Vec3::UnitX(), 0.1, 40),
                                     humanHair(), true);
    const double e0 = potentialEnergy(*w->hair);
    double gained = -1e300, strain = 0.0;
    int newton = 0;
    bool finite = true;
    for (double t = 0.0; t < 1.0; t += dt) {
      const WorldStepReport r = w->world.step(dt);
      finite = finite && r.diverged.empty();
      newton = std::max(newton, w->hair->lastNewtonIterations());
      gained = std::max(gained, potentialEnergy(*w->hair) + w->hair->kineticEnergy() - e0);
      const DiscreteElasticRod& rod = w->hair->strand(s);
      for (int j = 0; j < rod.numEdges(); ++j)
        strain = std::max(strain, std::abs((rod.positions()[j + 1] - rod.positions()[j]).norm() /
                                               rod.restLength(j) -
                                           1.0));
    }
    const Vec3 tip = w->hair->strand(s).positions().back();
    std::printf(
        "hair swinging at dt = 1/%.0f s for 1 s: tip (%.4f, %.4f, %.4f) m, max energy "
        "gain %.3e J (of %.3e J drop), max strain %.2e, max Newton iterations %d\n",
        1.0 / dt, tip.x(), tip.y(), tip.z(), gained, w->hair->totalMass() * kG * 0.1, strain,
        newton);
    EXPECT_TRUE(finite);
    EXPECT_LT(gained, 1e-6 * w->hair->totalMass() * kG * 0.1);
    EXPECT_LT(strain, 1e-5);
    EXPECT_LT(tip.z(), 0.2);  // it fell
  }
}

// The clamp follows its root frame: turned a quarter turn about z and lifted over 60 steps, the
// root vertex, first edge and first material director are where the frame puts them.
TEST(HairWorld, ClampFollowsMovingRootFrame) {
  auto w = hairWorld(settings());
  const std::vector<Vec3> rest = straightStrand(Vec3(0.0, 0.0, 0.1), Vec3::UnitX(), 0.05, 20);
  const int s = w->hair->addStrand(rest, humanHair(), true, Vec3::UnitZ());
  const Vec3 m1_0 = w->hair->strand(s).materialDirector1(0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int step = 1; step <= 60; ++step) {
    const double f = step / 60.0;
    pose = Eigen::Translation3d(0, 0, 0.02 * f) * Eigen::AngleAxisd(0.5 * M_PI * f, Vec3::UnitZ());
    w->hair->setRootFrame(s, pose);
    w->world.step(1.0 / 240.0);
  }
  const DiscreteElasticRod& rod = w->hair->strand(s);
  const double e0 = (rod.positions()[0] - pose * rest[0]).norm();
  const double e1 = (rod.positions()[1] - pose * rest[1]).norm();
  const double ed = (rod.materialDirector1(0) - pose.linear() * m1_0).norm();
  std::printf("clamp after a quarter turn: root %.2e m, second vertex %.2e m, director %.2e off\n",
              e0, e1, ed);
  EXPECT_LT(e0, 1e-12);
  EXPECT_LT(e1, 1e-12);
  EXPECT_LT(ed, 1e-9);
}

// A curl in the world without gravity: no stage moves it.
TEST(HairWorld, CurlStaysAtRest) {
  auto w = hairWorld(settings(Vec3::Zero()));
  const int s = w->hair->addStrand(
      helicalStrand(Vec3(0.05, 0.05, 0.15), Vec3(0, 0, -1), 0.004, 0.01, 0.12, 60), humanHair(),
      true);
  const std::vector<Vec3> x0 = w->hair->strand(s).positions();
  for (int step = 0; step < 60; ++step) w->world.step(1.0 / 240.0);
  double drift = 0.0;
  for (int i = 0; i < static_cast<int>(x0.size()); ++i)
    drift = std::max(drift, (w->hair->strand(s).positions()[i] - x0[i]).norm());
  std::printf("curl (r 4 mm, pitch 10 mm) after 60 world steps: max drift %.3e m\n", drift);
  EXPECT_LT(drift, 1e-12);
}

// Hair on cloth: a strand dropped 3 mm onto an 8 x 8 cm sheet (the hybrid shell) lying on a
// table meets it through the contact between their fields (world/field_contact.h) and lies
// on it, not through it, after 0.3 s. It does not rest yet: it sinks towards the sheet at
// about 0.7 mm/s (the figure printed; docs/VALIDATION.md), so this checks that the two bodies
// step together without diverging and that the contact holds the strand above the sheet for
// now. (Before the hair's field dropped nodes of vanishing mass, this case diverged at 0.022 s:
// nodes with 1e-23 kg of hair next to the cloth's went non-finite in the field contact.)
TEST(HairWorld, StrandOnClothStepsWithoutPassingThrough) {
  WorldSettings ws;
  ws.grid_spacing = kDx;
  ws.body_friction = 0.3;
  World world(ws);
  const double table = -0.25 * kDx, sheet_z = table + 1e-4;
  DrapeProblem cloth;
  cloth.mesh = makeRectangleMesh(0.08, 0.08, 8, 8, Vec3(0, 0, sheet_z));
  cloth.material = testCloth();
  cloth.gravity = Vec3(0, 0, -kG);
  HybridShellSettings ss;
  ss.grid_spacing = kDx;
  ss.friction = 1.0;
  ss.damping = 20.0;
  auto sheet = std::make_shared<HybridShellDynamics>(cloth, ss);
  world.add("cloth", sheet);
  auto hair = std::make_shared<HairDynamics>(settings());
  const int s =
      hair->addStrand(straightStrand(Vec3(0.015, 0.04, sheet_z + 3e-3), Vec3::UnitX(), 0.05, 20),
                      humanHair(), false);
  world.add("hair", hair);
  world.setColliders({std::make_shared<PlaneSurface>(Vec3(0, 0, table), Vec3::UnitZ())}, {}, {1.0});
  while (world.time() < 0.3) {
    const WorldStepReport r = world.step(std::min(world.stableTimeStep(), 1.0 / 240.0));
    ASSERT_TRUE(r.diverged.empty()) << r.diverged[0] << " diverged at " << world.time() << " s";
  }
  double sheet_top = -1e9, hair_low = 1e9, sink = 0.0;
  for (const Vec3& x : sheet->positions()) sheet_top = std::max(sheet_top, x.z());
  for (const Vec3& x : hair->strand(s).positions()) hair_low = std::min(hair_low, x.z());
  for (const Vec3& v : hair->velocities(s)) sink += v.z() / hair->strand(s).numVertices();
  std::printf(
      "strand on cloth after %.2f s: lowest hair vertex %.3f mm above the sheet's highest "
      "point (%.3f dx; contact distance 0.25 dx); mean vertical speed %.2e m/s "
      "(sinking: not at rest)\n",
      world.time(), 1e3 * (hair_low - sheet_top), (hair_low - sheet_top) / kDx, sink);
  EXPECT_GT(hair_low - sheet_top, 0.1 * kDx);
}

// A curl under gravity: a clamped helix (r 4 mm, pitch 10 mm, 6 cm, 40 segments) with its axis
// horizontal, stepped in the world at 1/60 s for 2 s, ends where a static solve of the same
// strand (ten load increments) puts it: the grid stages add nothing to an equilibrium. (A curl's
// modes are stiff, omega dt >> 1 at this step, so backward Euler stills it within a few steps.)
TEST(HairWorld, CurlSagsToStaticEquilibrium) {
  const std::vector<Vec3> rest =
      helicalStrand(Vec3(0.05, 0.05, 0.2), Vec3(1, 0, 0), 0.004, 0.01, 0.06, 40);
  DiscreteElasticRod statics(rest, humanHair());
  StrandLoads loads;
  loads.gravity = Vec3(0, 0, -kG);
  loads.held.assign(statics.numDofs(), 0);
  for (int k = 0; k < 7; ++k) loads.held[k] = 1;
  StrandNewtonSettings ns;
  ns.max_iterations = 100;
  const int increments = 10;
  bool converged = true;
  for (int i = 1; i <= increments; ++i) {
    loads.gravity = Vec3(0, 0, -kG * i / increments);
    converged = solveStrand(statics, loads, ns).converged && converged;
  }
  EXPECT_TRUE(converged);
  auto w = hairWorld(settings());
  const int s = w->hair->addStrand(rest, humanHair(), true);
  for (int step = 0; step < 120; ++step) w->world.step(1.0 / 60.0);
  double worst = 0.0, sag = 0.0;
  for (int i = 0; i < statics.numVertices(); ++i) {
    worst = std::max(worst, (w->hair->strand(s).positions()[i] - statics.positions()[i]).norm());
    sag = std::max(sag, (statics.positions()[i] - rest[i]).norm());
  }
  std::printf(
      "curl under gravity after 2 s at 1/60 s: largest distance from the static "
      "equilibrium %.3e m (the sag itself reaches %.3e m); speed %.2e m/s\n",
      worst, sag, std::sqrt(2.0 * w->hair->kineticEnergy() / w->hair->totalMass()));
  EXPECT_GT(sag, 1e-3);
  EXPECT_LT(worst, 1e-3 * sag);
}

// The clamp feels the strand: a 5 cm hair clamped horizontally, settled in the world (1 s at
// 1/60 s), is held by a force equal to its weight and a moment that balances its weight's
// moment about the root, sum (x_i - x_0) x m_i g, from the positions it hangs in.
TEST(HairWorld, ClampCarriesTheStrandsWeight) {
  auto w = hairWorld(settings());
  const int s = w->hair->addStrand(straightStrand(Vec3(0.02, 0.02, 0.1), Vec3::UnitX(), 0.05, 20),
                                   humanHair(), true);
  for (int step = 0; step < 60; ++step) w->world.step(1.0 / 60.0);
  const HoldingWrench h = w->hair->clampWrench(s);
  const DiscreteElasticRod& rod = w->hair->strand(s);
  const Vec3 g(0, 0, -kG);
  Vec3 moment = Vec3::Zero();
  for (int i = 0; i < rod.numVertices(); ++i)
    moment += (rod.positions()[i] - rod.positions()[0]).cross(rod.vertexMass(i) * g);
  const Vec3 weight = -w->hair->totalMass() * g;
  std::printf(
      "clamp of a hanging hair: force (%.4e, %.4e, %.4e) N against its weight %.4e N; "
      "moment (%.4e, %.4e, %.4e) N m against %.4e N m\n",
      h.force.x(), h.force.y(), h.force.z(), weight.z(), h.torque.x(), h.torque.y(), h.torque.z(),
      -moment.y());
  EXPECT_LT((h.force - weight).norm(), 1e-6 * weight.norm());
  EXPECT_LT((h.torque + moment).norm(), 1e-6 * moment.norm());
}

// A comb's bar (a capsule of radius 5 mm) that appears 3 mm deep in hanging hair, as when the
// node holds a diverged strand still while the bar moves on, or a frame jumps: the stiff penalty
// and the end-of-step projection would move the vertices out within one step, at depth / dt
// (48 m/s at 1/16 ms, beyond the node's divergence speed), and the edges' recoil fling the
// strand. They leave at the recovery speed instead: no vertex is faster than the obstacle's
// recovery speed (0.1 m/s) with margin, and all are out (to the hair's radius) after the depth's
// recovery time, 30 ms, and twice that.
TEST(HairWorld, DeepObstacleIsLeftAtTheRecoverySpeed) {
  auto w = hairWorld(settings());
  for (double x : {-0.002, 0.0, 0.002})
    w->hair->addStrand(straightStrand(Vec3(x, 0.0, 0.1), -Vec3::UnitZ(), 0.1, 20), humanHair(),
                       true);
  const double r = 0.005, depth = 0.003;
  const Vec3 centre(0.0, r - depth, 0.05);  // its surface 3 mm past the strands' plane y = 0
  w->world.setColliders(
      {std::make_shared<CapsuleSurface>(centre - Vec3(0.05, 0, 0), centre + Vec3(0.05, 0, 0), r)},
      {}, {0.0});
  const CapsuleSurface bar(centre - Vec3(0.05, 0, 0), centre + Vec3(0.05, 0, 0), r);
  const double recovery = HairSettings().obstacle_contact.recovery_speed;
  const auto deepest = [&] {
    double d = 0.0;
    for (int s = 0; s < w->hair->numStrands(); ++s)
      for (const Vec3& x : w->hair->strand(s).positions()) d = std::max(d, -bar.project(x).gap);
    return d;
  };
  const double start_depth = deepest();
  double v_max = 0.0, t = 0.0, depth_at_recovery = 0.0;
  for (const double dt : {1e-3 / 16.0, 1.0 / 240.0}) {
    const double until = t + (dt < 1e-3 ? 0.005 : 0.055);
    for (; t < until; t += dt) {
      w->world.step(dt);
      for (int s = 0; s < w->hair->numStrands(); ++s)
        for (const Vec3& v : w->hair->velocities(s)) v_max = std::max(v_max, v.norm());
      if (t < depth / recovery) depth_at_recovery = deepest();
    }
  }
  const double end_depth = deepest();
  std::printf(
      "hanging hair with a bar appearing %.1f mm deep (deepest vertex %.2f mm): fastest vertex "
      "%.3f m/s (recovery speed %.2f m/s), deepest after %.0f ms %.3f mm, after %.0f ms %.4f mm\n",
      1e3 * depth, 1e3 * start_depth, v_max, recovery, 1e3 * depth / recovery,
      1e3 * depth_at_recovery, 1e3 * t, 1e3 * end_depth);
  EXPECT_GT(start_depth, 0.9 * depth);
  EXPECT_LT(v_max, 5.0 * recovery);
  EXPECT_LT(end_depth, humanHair().radius_1);
}

// Free strands draped across a horizontal capsule (a comb's bar, mu = 0.5), symmetric about it:
// they sag round it to rest, and the load the capsule takes is their weight, straight down.
TEST(HairWorld, StrandsOverCapsuleReportWeight) {
  auto w = hairWorld(settings());
  const double r = 0.01, lift = r + humanHair().radius_1;
  for (double y : {-0.02, 0.0, 0.02})
    w->hair->addStrand(straightStrand(Vec3(-0.04, y, lift), Vec3::UnitX(), 0.08, 32), humanHair(),
                       false);
  w->world.setColliders({std::make_shared<CapsuleSurface>(Vec3(0, -0.05, 0), Vec3(0, 0.05, 0), r)},
                        {}, {0.5});
  const double dt = 1.0 / 240.0;
  Vec3 mean = Vec3::Zero();
  int samples = 0;
  for (int step = 0; step < 720; ++step) {
    w->world.step(dt);
    if (step >= 600) {  // the last half second, at rest
      mean += w->world.colliderLoads()[0].force;
      ++samples;
    }
  }
  mean /= samples;
  const double weight = w->hair->totalMass() * kG;
  const Vec3 end = w->hair->strand(1).positions().back();
  std::printf(
      "3 strands over a capsule: load (%.4e, %.4e, %.4e) N, weight %.4e N, error %.2e; "
      "tip of the middle one at (%.4f, %.4f) m, kinetic energy %.2e J\n",
      mean.x(), mean.y(), mean.z(), weight, std::abs(-mean.z() - weight) / weight, end.x(), end.z(),
      w->hair->kineticEnergy());
  EXPECT_LT(end.z(), lift - 0.001);  // the overhangs bend down (stiff hair: by millimetres)
  EXPECT_NEAR(-mean.z(), weight, 0.01 * weight);
  EXPECT_LT(std::hypot(mean.x(), mean.y()), 0.01 * weight);
}

// A lock of three free strands hanging straight down, gripped at their top vertices and lifted
// 5 cm at 5 cm/s, then held: the gripped vertices are where the grip's motion puts them, and the
// grip carries the lock's weight, with the moment sum_i (x_i - o) x m_i g of the strands'
// weights about a point o beside it. Removed, the lock falls freely.
TEST(HairWorld, GripCarriesTheLock) {
  auto w = hairWorld(settings());
  std::vector<StrandVertex> top;
  std::vector<Vec3> top_x;
  for (double x : {-0.004, 0.0, 0.004}) {
    top_x.push_back(Vec3(x, 0.0, 0.1));
    top.push_back({w->hair->addStrand(straightStrand(top_x.back(), -Vec3::UnitZ(), 0.05, 20),
                                      humanHair(), false),
                   0});
  }
  // Within 3 mm of the middle top: it and the vertex 2.5 mm below it; gripped, only the latter.
  EXPECT_EQ(w->hair->freeVerticesNear(Vec3(0, 0, 0.1), 0.003).size(), 2u);
  const int grip = w->hair->addGrip(top);
  EXPECT_EQ(w->hair->freeVerticesNear(Vec3(0, 0, 0.1), 0.003).size(), 1u);
  EXPECT_EQ(w->hair->gripVertices(grip).size(), 3u);
  const double dt = 1.0 / 240.0, speed = 0.05;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  double off = 0.0;
  for (int step = 1; step <= 480; ++step) {
    motion.translation().z() = speed * std::min(step * dt, 1.0);
    w->hair->setGripFrame(grip, motion);
    w->world.step(dt);
    for (std::size_t k = 0; k < top.size(); ++k)
      off =
          std::max(off, (w->hair->strand(top[k].strand).positions()[0] - motion * top_x[k]).norm());
  }
  const Vec3 o(0.01, 0.0, 0.1 + speed);
  const HoldingWrench h = w->hair->gripWrench(grip, o);
  const Vec3 g(0, 0, -kG);
  Vec3 moment = Vec3::Zero();
  double mass = 0.0;
  for (const StrandVertex& sv : top) {
    double m = 0.0;
    for (int i = 0; i < w->hair->strand(sv.strand).numVertices(); ++i)
      m += w->hair->strand(sv.strand).vertexMass(i);
    moment += (w->hair->strand(sv.strand).positions()[0] - o).cross(-m * g);
    mass += m;
  }
  const Vec3 weight = -mass * g;
  std::printf(
      "grip of a 3-strand lock lifted 5 cm and held 1 s: force (%.4e, %.4e, %.4e) N against its "
      "weight %.4e N (error %.2e); moment (%.4e, %.4e, %.4e) N m against (%.4e, %.4e, %.4e); "
      "gripped vertices off their frame by %.2e m\n",
      h.force.x(), h.force.y(), h.force.z(), weight.z(), (h.force - weight).norm() / weight.norm(),
      h.torque.x(), h.torque.y(), h.torque.z(), moment.x(), moment.y(), moment.z(), off);
  EXPECT_LT(off, 1e-12);
  EXPECT_LT((h.force - weight).norm(), 1e-4 * weight.norm());
  EXPECT_LT((h.torque - moment).norm(), 1e-3 * moment.norm());
  // Removed: nothing holds it; its centre of mass falls at g (to 1 %) over 0.1 s.
  w->hair->removeGrip(grip);
  const Vec3 p0 = w->hair->linearMomentum();
  for (int step = 0; step < 24; ++step) w->world.step(dt);
  const double a = (w->hair->linearMomentum() - p0).z() / (mass * 24 * dt);
  std::printf("released lock: centre of mass acceleration %.4f m/s^2 (g %.2f)\n", a, -kG);
  EXPECT_NEAR(a, -kG, 0.01 * kG);
  EXPECT_THROW(w->hair->gripWrench(grip, o), InputError);
}

TEST(HairWorld, SnapshotRestores) {
  auto w = hairWorld(settings());
  w->world.setColliders({std::make_shared<PlaneSurface>(Vec3(0, 0, 0.02), Vec3::UnitZ())});
  const int s = w->hair->addStrand(
      wavyStrand(Vec3(0.0, 0.0, 0.1), Vec3::UnitX(), Vec3::UnitZ(), 0.004, 0.02, 0.08, 30),
      humanHair(), true);
  for (int step = 0; step < 20; ++step) w->world.step(1.0 / 240.0);
  const World::Snapshot snap = w->world.snapshot();
  for (int step = 0; step < 20; ++step) w->world.step(1.0 / 240.0);
  const std::vector<Vec3> a = w->hair->strand(s).positions();
  w->world.restore(snap);
  for (int step = 0; step < 20; ++step) w->world.step(1.0 / 240.0);
  const std::vector<Vec3> b = w->hair->strand(s).positions();
  double diff = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) diff = std::max(diff, (a[i] - b[i]).norm());
  // Not bit for bit: the particle-to-grid transfer sums its threads' shares in the order they
  // finish.
  std::printf("hair snapshot: replay differs by %.3e m\n", diff);
  EXPECT_LT(diff, 1e-15);
}

// The state a file holds (HairDynamics::writeState): read into a body built with the same
// strands, with the continuum on and a grip, it steps on as the original does; a record of
// another body is refused and leaves the body as it was.
TEST(HairWorld, StateRecordReadsBackAndStepsOn) {
  HairSettings hs = settings();
  hs.continuum.enabled = true;
  auto build = [&] {
    auto w = hairWorld(hs);
    for (int k = 0; k < 3; ++k)
      w->hair->addStrand(wavyStrand(Vec3(0.002 * k, 0.0, 0.1), Vec3::UnitX(), Vec3::UnitZ(), 0.004,
                                    0.02, 0.06, 20),
                         humanHair(), true);
    return w;
  };
  auto a = build();
  const int grip =
      a->hair->addGrip(a->hair->freeVerticesNear(a->hair->strand(1).positions()[19], 0.004));
  Eigen::Isometry3d lift = Eigen::Isometry3d::Identity();
  for (int step = 1; step <= 20; ++step) {
    lift.translation() = Vec3(0, 0, 0.0005 * step);
    a->hair->setGripFrame(grip, lift);
    a->world.step(1.0 / 240.0);
  }
  StateWriter out;
  a->hair->writeState(out);
  auto b = build();
  b->hair->addGrip(b->hair->freeVerticesNear(b->hair->strand(1).positions()[19], 0.004));
  StateReader in(out.data(), "record");
  b->hair->readState(in);
  in.expectEnd();
  double worst = 0.0;
  for (int step = 21; step <= 30; ++step) {
    lift.translation() = Vec3(0, 0, 0.0005 * step);
    for (auto* w : {a.get(), b.get()}) {
      w->hair->setGripFrame(grip, lift);
      w->world.step(1.0 / 240.0);
    }
  }
  for (int s = 0; s < 3; ++s)
    for (int i = 0; i < a->hair->strand(s).numVertices(); ++i)
      worst = std::max(
          worst, (a->hair->strand(s).positions()[i] - b->hair->strand(s).positions()[i]).norm());
  std::printf(
      "hair state record: %zu bytes; 10 steps on, read-back body %.3e m from the original "
      "(time %.6f / %.6f s)\n",
      out.data().size(), worst, a->hair->time(), b->hair->time());
  EXPECT_LT(worst, 1e-12);
  EXPECT_DOUBLE_EQ(a->hair->time(), b->hair->time());

  auto c = hairWorld(hs);  // one strand: another body
  c->hair->addStrand(straightStrand(Vec3(0, 0, 0.1), Vec3::UnitX(), 0.06, 20), humanHair(), true);
  const std::vector<Vec3> before = c->hair->strand(0).positions();
  StateReader other(out.data(), "record");
  try {
    c->hair->readState(other);
    ADD_FAILURE() << "a record of three strands was read into one";
  } catch (const InputError& e) {
    std::printf("refused: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("hair strands"), std::string::npos);
  }
  EXPECT_EQ(c->hair->strand(0).positions(), before);
}

TEST(HairWorld, BadInputIsRefused) {
  const auto refused = [](auto&& f, const char* what) {
    try {
      f();
      ADD_FAILURE() << "accepted " << what;
    } catch (const InputError& e) {
      std::printf("%-28s -> InputError: %s\n", what, e.what());
    }
  };
  HairSettings bad = settings();
  bad.pic_blend = 2.0;
  refused([&] { HairDynamics h(bad); }, "pic_blend 2");
  bad = settings();
  bad.grid_spacing = 0.0;
  refused([&] { HairDynamics h(bad); }, "zero grid spacing");
  bad = settings();
  bad.gravity.x() = std::nan("");
  refused([&] { HairDynamics h(bad); }, "NaN gravity");
  bad = settings();
  bad.obstacle_contact.stiffness = std::nan("");
  refused([&] { HairDynamics h(bad); }, "NaN contact stiffness");
  bad = settings();
  bad.obstacle_contact.slip_velocity = 0.0;
  refused([&] { HairDynamics h(bad); }, "zero friction eps_v");
  bad = settings();
  bad.obstacle_contact.lag_passes = 0;
  refused([&] { HairDynamics h(bad); }, "no lag pass");
  auto w = hairWorld(settings());
  std::vector<Vec3> dup = straightStrand(Vec3::Zero(), Vec3::UnitX(), 0.05, 5);
  dup[3] = dup[2];
  refused([&] { w->hair->addStrand(dup, humanHair()); }, "duplicate vertices");
  EXPECT_EQ(w->hair->numStrands(), 0);
  RodMaterial m = humanHair();
  m.radius_1 = 0.0;
  refused([&] { w->hair->addStrand(straightStrand(Vec3::Zero(), Vec3::UnitX(), 0.05, 5), m); },
          "zero radius");
  EXPECT_EQ(w->hair->numStrands(), 0);
  HairSettings few = settings();
  few.max_vertices = 10;
  HairDynamics small(few);
  refused(
      [&] { small.addStrand(straightStrand(Vec3::Zero(), Vec3::UnitX(), 0.05, 20), humanHair()); },
      "beyond max_vertices");
  refused([&] { w->hair->setRootFrame(3, Eigen::Isometry3d::Identity()); },
          "root frame of no strand");
  const int clamped =
      w->hair->addStrand(straightStrand(Vec3::Zero(), Vec3::UnitX(), 0.05, 5), humanHair(), true);
  refused([&] { w->hair->addGrip({{clamped, 0}, {clamped, 1}}); }, "grip of clamped vertices");
  refused([&] { w->hair->addGrip({{clamped, 9}}); }, "grip of no vertex");
  refused([&] { w->hair->addGrip({}); }, "grip of nothing");
  refused([&] { w->hair->setGripFrame(7, Eigen::Isometry3d::Identity()); }, "frame of no grip");
  refused([&] { w->hair->removeGrip(7); }, "removal of no grip");
  HairSettings other = settings();
  other.grid_spacing = 2 * kDx;
  refused([&] { w->world.add("other", std::make_shared<HairDynamics>(other)); },
          "world of another spacing");
}

}  // namespace
}  // namespace chs::rod
