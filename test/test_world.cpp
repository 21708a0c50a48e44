// One world, many bodies (core/world): bodies meet on one grid with a velocity field each, and
// contact with Coulomb friction between the fields (world/field_contact.h) lets one body rest
// on, slide on and collide with another. The scene of test_hybrid_layer_friction (a 4 x 4 cm
// sheet on an 8 x 8 cm sheet, the bottom one on a plane with mu = 1), but the two sheets are two
// bodies: the case that one shell's single velocity field could not pass (the layers stuck
// whatever their c_F).
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/world/world.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kG = 9.81;
constexpr double kH = 0.01;  // control spacing = grid spacing dx [m]
constexpr int kBottomN = 8, kTopN = 4;
// As in test_hybrid_layer_friction: the plane a quarter cell below the node plane z = 0, so that
// the top sheet never reaches a node inside the plane (whose Coulomb condition has mu = 1).
// The top sheet starts just beyond the contact distance (a quarter cell) above the bottom one.
constexpr double kPlaneZ = -0.25 * kH, kBottomZ = kPlaneZ + 1e-4, kTopZ = kBottomZ + 0.3 * kH;
constexpr double kSettleDamping = 200.0;  // [1/s]
constexpr double kSettleTime = 0.2;       // [s]

DrapeProblem sheet(int n, double z, const Vec3& gravity) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(n * kH, n * kH, n, n, Vec3(0, 0, z));
  p.material = testCloth();
  p.gravity = gravity;
  return p;
}

// A sheet held in place on every axis: its control points keep their mass on the grid (pins
// would not: a pin is a Dirichlet condition), so its field meets the other body's. The axes are
// held after the grid stages, where its field still yields to what presses on it: without
// gravity of its own (its field would slide downhill on the grid and drag the top sheet along)
// and a hundred times as heavy as the top sheet, so that it yields as little as a support does.
// (As heavy as the top sheet, its field gives way by half a step's impulse each step and mu = 0.6
// reads as 0.56.)
DrapeProblem heldSheet(int n, double z) {
  DrapeProblem p = sheet(n, z, Vec3::Zero());
  p.material.areal_density *= 100.0;
  for (int v = 0; v < p.mesh.numVertices(); ++v)
    for (int axis = 0; axis < 3; ++axis) p.bc.fixed_components.push_back({v, axis});
  return p;
}

HybridShellSettings shellSettings(double damping, bool lagrangian = false) {
  HybridShellSettings s;
  s.grid_spacing = kH;
  s.friction = 1.0;  // the plane under the bottom sheet
  s.damping = damping;
  if (lagrangian) {
    s.integration = TimeIntegration::kLagrangianImplicit;
    s.max_time_step = 1.0 / 60.0;
  }
  return s;
}

// The two sheets as two bodies of one world, with Coulomb mu between them: the bottom one lying on
// the plane (mu = 1), or held in place on every axis without a plane. The plane's condition acts
// on every body's nodes inside it, the top sheet's too when it lies within a cell and a half.
struct Pair {
  World world;
  HybridShellDynamics *bottom = nullptr, *top = nullptr;
};

std::unique_ptr<Pair> stackedPair(double mu, const Vec3& gravity, double damping,
                                  bool held_bottom = false, bool lagrangian = false) {
  WorldSettings ws;
  ws.grid_spacing = kH;
  ws.body_friction = mu;
  auto pair = std::make_unique<Pair>(Pair{World(ws)});
  auto bottom = std::make_unique<HybridShellDynamics>(
      held_bottom ? heldSheet(kBottomN, kBottomZ) : sheet(kBottomN, kBottomZ, gravity),
      shellSettings(damping, lagrangian));
  auto top = std::make_unique<HybridShellDynamics>(sheet(kTopN, kTopZ, gravity),
                                                   shellSettings(damping, lagrangian));
  pair->bottom = bottom.get();
  pair->top = top.get();
  pair->world.add("bottom", std::move(bottom));
  pair->world.add("top", std::move(top));
  if (!held_bottom)
    pair->world.setColliders({std::make_shared<PlaneSurface>(Vec3(0, 0, kPlaneZ), Vec3::UnitZ())},
                             {}, {1.0});
  return pair;
}

void runUntil(World& w, double t) {
  while (w.time() < t - 1e-12) {
    const WorldStepReport r = w.step(std::min(w.stableTimeStep(), t - w.time()));
    ASSERT_TRUE(r.diverged.empty());
  }
}

struct Motion {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
  double mass = 0.0;
};
Motion meanMotion(const HybridShellDynamics& d) {
  Motion m;
  for (int i = 0; i < d.numVertices(); ++i) {
    m.x += d.masses()[i] * d.positions()[i];
    m.v += d.masses()[i] * d.velocities()[i];
    m.mass += d.masses()[i];
  }
  m.x /= m.mass;
  m.v /= m.mass;
  return m;
}

TEST(World, OneBodyRestsOnAnother) {
  auto p = stackedPair(0.3, Vec3(0, 0, -kG), kSettleDamping);
  runUntil(p->world, kSettleTime);
  const Motion top = meanMotion(*p->top), bottom = meanMotion(*p->bottom);
  const double separation = top.x.z() - bottom.x.z();
  std::printf(
      "[figure] two bodies settled %.2f s: separation %.3f mm (%.3f dx; contact distance 0.25 "
      "dx), top sheet vertical speed %.2e m/s\n",
      p->world.time(), 1e3 * separation, separation / kH, top.v.z());
  EXPECT_GT(separation, 0.1 * kH);
  EXPECT_LT(separation, 0.5 * kH);
  EXPECT_LT(std::abs(top.v.z()), 1e-3);
  for (int i = 0; i < p->top->numVertices(); ++i)
    EXPECT_GT(p->top->positions()[i].z(), bottom.x.z() + 0.1 * kH) << "vertex " << i;
}

// The same pair resting for a second on the Lagrangian step at 1/60 s, lightly damped: each step
// gravity presses the top sheet g dt^2 = 2.7 mm (0.27 dx) onto the bottom one, and the fields'
// contact must hand it back. A contact that only stops the approach let the gap drift shut by
// interpolation a little each step (a 6 cm sheet on a 12 cm one on a table sank onto the table
// within a second); within the contact distance the fields now separate again.
TEST(World, RestingGapHoldsOnTheLagrangianStep) {
  auto p = stackedPair(0.3, Vec3(0, 0, -kG), 2.0, false, true);
  const auto separation = [&p] { return meanMotion(*p->top).x.z() - meanMotion(*p->bottom).x.z(); };
  runUntil(p->world, 0.5);
  const double halfway = separation();
  double closest = halfway;
  while (p->world.time() < 1.0 - 1e-12) {
    const WorldStepReport r =
        p->world.step(std::min(p->world.stableTimeStep(), 1.0 - p->world.time()));
    ASSERT_TRUE(r.diverged.empty());
    closest = std::min(closest, separation());
  }
  const double end = separation();
  const double speed = meanMotion(*p->top).v.z();
  std::printf(
      "[figure] two bodies resting on the Lagrangian step (1/60 s): separation %.3f dx at 0.5 s, "
      "%.3f dx at 1 s, closest %.3f dx in between (contact distance 0.25 dx); top sheet "
      "vertical speed %.2e m/s\n",
      halfway / kH, end / kH, closest / kH, speed);
  EXPECT_GT(closest, 0.05 * kH);
  EXPECT_LT(std::abs(end - halfway), 0.02 * kH);
  EXPECT_LT(end, 0.5 * kH);
  EXPECT_LT(std::abs(speed), 1e-3);
}

struct SlideRun {
  double travel, acceleration, bottom_travel;
};

// Gravity tilted by theta about y (downhill +x), the bottom sheet held: settled under
// g cos(theta) with damping, then run undamped for t_end under the full tilted gravity.
SlideRun slideTop(double mu, double theta, double t_end) {
  auto settle = stackedPair(mu, Vec3(0, 0, -kG * std::cos(theta)), kSettleDamping, true);
  runUntil(settle->world, kSettleTime);
  const World::Snapshot settled = settle->world.snapshot();
  auto p = stackedPair(mu, kG * Vec3(std::sin(theta), 0.0, -std::cos(theta)), 0.0, true);
  p->world.restore(settled);
  const double t0 = p->world.time();
  const Motion top0 = meanMotion(*p->top), bottom0 = meanMotion(*p->bottom);
  runUntil(p->world, t0 + t_end / 3.0);
  const double v1 = meanMotion(*p->top).v.x(), t1 = p->world.time();
  runUntil(p->world, t0 + t_end);
  const Motion top = meanMotion(*p->top);
  return {top.x.x() - top0.x.x(), (top.v.x() - v1) / (p->world.time() - t1),
          meanMotion(*p->bottom).x.x() - bottom0.x.x()};
}

// The case one shell could not pass (docs/VALIDATION.md, HybridLayerFriction): stick while
// tan(theta) <= mu, slide with g (sin theta - mu cos theta) beyond, within a degree of onset.
TEST(World, SlidesOnAnotherBodyIffTanThetaExceedsMu) {
  constexpr double t = 0.3, degree = M_PI / 180.0;
  for (double mu : {0.3, 0.6}) {
    const double onset = std::atan(mu), below = onset - degree, above = onset + degree;
    const double a_above = kG * (std::sin(above) - mu * std::cos(above));
    const double free_travel = 0.5 * a_above * t * t;
    const SlideRun stick = slideTop(mu, below, t);
    const SlideRun slide = slideTop(mu, above, t);
    std::printf(
        "[figure] bodies mu = %.1f (onset %.2f deg), %.1f s: at onset - 1 deg travel %.3e m "
        "(%.2f %% of the %.3e m of onset + 1 deg in theory); at onset + 1 deg acceleration %.4f "
        "m/s^2 vs g (sin - mu cos) = %.4f (ratio %.3f); bottom sheet travel %.1e / %.1e m\n",
        mu, onset / degree, t, stick.travel, 100 * stick.travel / free_travel, free_travel,
        slide.acceleration, a_above, slide.acceleration / a_above, stick.bottom_travel,
        slide.bottom_travel);
    EXPECT_LT(std::abs(stick.travel), 0.05 * free_travel);
    EXPECT_NEAR(slide.acceleration / a_above, 1.0, 0.1);
  }
  const double theta = 20.0 * degree, a_free = kG * std::sin(theta);
  const SlideRun frictionless = slideTop(0.0, theta, 0.1);
  std::printf(
      "[figure] bodies mu = 0 at 20 deg, 0.1 s: acceleration %.4f m/s^2 vs g sin = %.4f "
      "(ratio %.3f)\n",
      frictionless.acceleration, a_free, frictionless.acceleration / a_free);
  EXPECT_NEAR(frictionless.acceleration / a_free, 1.0, 0.1);
}

// Two sheets meeting in free space (no gravity, no obstacles): the contact between their fields
// moves momentum from one to the other and conserves the total.
TEST(World, CollisionBetweenBodiesConservesMomentum) {
  WorldSettings ws;
  ws.grid_spacing = kH;
  ws.body_friction = 0.5;
  World w(ws);
  auto bottom =
      std::make_unique<HybridShellDynamics>(sheet(kBottomN, 0.0, Vec3::Zero()), shellSettings(0.0));
  auto top = std::make_unique<HybridShellDynamics>(sheet(kTopN, 2.0 * kH, Vec3::Zero()),
                                                   shellSettings(0.0));
  // Down and sideways, so that friction acts too.
  top->setVelocities(std::vector<Vec3>(top->numVertices(), Vec3(0.1, 0.0, -0.5)));
  HybridShellDynamics& b = *bottom;
  HybridShellDynamics& t = *top;
  w.add("bottom", std::move(bottom));
  w.add("top", std::move(top));
  const Vec3 p0 = b.linearMomentum() + t.linearMomentum();
  int contact_steps = 0;
  double lowest_gap = 1.0;
  while (w.time() < 0.1) {
    const WorldStepReport r = w.step(w.stableTimeStep());
    contact_steps += r.contact.contact_nodes > 0;
    lowest_gap = std::min(lowest_gap, meanMotion(t).x.z() - meanMotion(b).x.z());
  }
  const Vec3 p1 = b.linearMomentum() + t.linearMomentum();
  std::printf(
      "[figure] bodies colliding in free space, 0.1 s: momentum drift %.2e of |p0| = %.3e "
      "kg m/s; %d steps with contact; bottom sheet took %.1f %% of the top's momentum; lowest "
      "mean gap %.3f dx\n",
      (p1 - p0).norm() / p0.norm(), p0.norm(), contact_steps,
      100.0 * -b.linearMomentum().z() / -p0.z(), lowest_gap / kH);
  EXPECT_LT((p1 - p0).norm(), 1e-10 * p0.norm());
  EXPECT_GT(contact_steps, 0);
  EXPECT_GT(-b.linearMomentum().z(), 0.3 * -p0.z());  // the bottom sheet was pushed
  EXPECT_GT(lowest_gap, 0.0);                         // and not passed through
}

// Mean of the plane's load over [t0, t1] (the stiff sheets ring at kHz: one step's reading is
// one sample of that).
ColliderLoad meanLoad(World& w, double t0, double t1) {
  runUntil(w, t0);
  ColliderLoad sum;
  while (w.time() < t1 - 1e-12) {
    const double dt = std::min(w.stableTimeStep(), t1 - w.time());
    w.step(dt);
    const ColliderLoad l = w.colliderLoads().at(0);
    sum.force += dt * l.force;
    sum.moment += dt * l.moment;
  }
  sum.force /= t1 - t0;
  sum.moment /= t1 - t0;
  return sum;
}

// The tactile reading: what the plane carries is the weight of what rests on it.
TEST(World, ColliderCarriesTheWeightOfTheBodiesOnIt) {
  auto p = stackedPair(0.3, Vec3(0, 0, -kG), kSettleDamping);
  const ColliderLoad load = meanLoad(p->world, 2.0 * kSettleTime, 3.0 * kSettleTime);
  const double weight = kG * (meanMotion(*p->bottom).mass + meanMotion(*p->top).mass);
  const Vec3 moment = load.momentAbout(meanMotion(*p->bottom).x);
  std::printf(
      "[figure] plane under two resting bodies, mean over %.1f s: force (%.2e, %.2e, %.5f) N vs "
      "weight %.5f N (ratio %.4f); moment about the centre %.2e N m\n",
      kSettleTime, load.force.x(), load.force.y(), load.force.z(), weight, -load.force.z() / weight,
      moment.norm());
  EXPECT_NEAR(-load.force.z() / weight, 1.0, 0.01);
  EXPECT_LT(load.force.head<2>().norm(), 0.01 * weight);
  EXPECT_LT(moment.norm(), 0.01 * weight * kBottomN * kH);
}

TEST(World, SnapshotRestoresTheWholeWorld) {
  auto p = stackedPair(0.3, Vec3(0, 0, -kG), 0.0);
  runUntil(p->world, 0.02);
  const World::Snapshot s = p->world.snapshot();
  runUntil(p->world, 0.04);
  const std::vector<Vec3> x = p->top->positions();
  const double t = p->world.time();
  p->world.restore(s);
  EXPECT_DOUBLE_EQ(p->world.time(), 0.02);
  runUntil(p->world, t);
  double diff = 0.0;
  for (int i = 0; i < p->top->numVertices(); ++i)
    diff = std::max(diff, (p->top->positions()[i] - x[i]).norm());
  // Parallel force sums add in a scheduling-dependent order: equal to rounding, not bit for bit.
  std::printf("[figure] world restored and rerun: largest position difference %.2e m\n", diff);
  EXPECT_LT(diff, 1e-12);
}

TEST(World, RefusesBodiesItCannotHold) {
  WorldSettings ws;
  ws.grid_spacing = kH;
  World w(ws);
  auto expectRefused = [&](const std::string& name, std::shared_ptr<Body> body,
                           const std::string& fragment) {
    try {
      w.add(name, std::move(body));
      ADD_FAILURE() << "accepted " << name;
    } catch (const InputError& e) {
      std::printf("  refused: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const DrapeProblem p = sheet(4, 0.0, Vec3(0, 0, -kG));
  HybridShellSettings coarse = shellSettings(0.0);
  coarse.grid_spacing = 2 * kH;
  expectRefused("coarse", std::make_unique<HybridShellDynamics>(p, coarse), "not the world's");
  HybridShellSettings cubic = shellSettings(0.0);
  cubic.kernel_degree = 3;
  expectRefused("cubic", std::make_unique<HybridShellDynamics>(p, cubic), "kernel degree");
  expectRefused("my sheet", std::make_unique<HybridShellDynamics>(p, shellSettings(0.0)),
                "a space");
  expectRefused("nothing", nullptr, "null");
  w.add("sheet", std::make_unique<HybridShellDynamics>(p, shellSettings(0.0)));
  expectRefused("sheet", std::make_unique<HybridShellDynamics>(p, shellSettings(0.0)),
                "a body of that name");
  EXPECT_EQ(w.numBodies(), 1);
  for (double dx : {1e-5, 5.0}) {
    WorldSettings bad;
    bad.grid_spacing = dx;
    try {
      World nonsense(bad);
      ADD_FAILURE() << "grid spacing " << dx << " accepted";
    } catch (const InputError& e) {
      std::printf("  refused: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find("lies outside"), std::string::npos);
    }
  }
  EXPECT_THROW(w.step(0.0), InputError);
  EXPECT_THROW(w.step(std::nan("")), InputError);
  EXPECT_TRUE(w.remove("sheet"));
  EXPECT_FALSE(w.remove("sheet"));
  // A particle budget: the first sheet fits, a second would go over it and is refused whole,
  // and the world it leaves steps on.
  WorldSettings small;
  small.grid_spacing = kH;
  const long per_sheet =
      static_cast<long>(HybridShellDynamics(p, shellSettings(0.0)).motion().x.size());
  small.max_particles = static_cast<int>(per_sheet + per_sheet / 2);
  World budget(small);
  budget.add("first", std::make_unique<HybridShellDynamics>(p, shellSettings(0.0)));
  try {
    budget.add("second", std::make_unique<HybridShellDynamics>(p, shellSettings(0.0)));
    ADD_FAILURE() << "a world over its particle budget accepted a body";
  } catch (const InputError& e) {
    std::printf("  refused: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("over max_particles"), std::string::npos) << e.what();
  }
  EXPECT_EQ(budget.numBodies(), 1);
  EXPECT_EQ(budget.numParticles(), per_sheet);
  const WorldStepReport report = budget.step(1e-4);
  EXPECT_TRUE(report.diverged.empty());
  EXPECT_TRUE(budget.body(0).finite());
  small.max_particles = 0;
  EXPECT_THROW(World{small}, InputError);
}

}  // namespace
}  // namespace chs
