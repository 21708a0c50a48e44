// SimulationRun (core/simulation/simulation_run.h): a scripted collider hands its velocity to the
// grid and carries the cloth with it; a step that diverges is rolled back, halved, and then stops
// the run at the last good state.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/io/simulation_scene.h"
#include "cloth_hair_sim/core/simulation/simulation_run.h"

namespace chs {
namespace {

// A 4 x 4 cm sheet of 1 cm cells lying on a 10 x 10 cm box top at z = 0.
std::string sheetOnBox(const std::string& motion) {
  return R"(
duration: 0.1
frame_rate: 20
world: {grid_spacing: 0.01}
bodies:
  - name: sheet
    rectangle: {size: [0.04, 0.04], cells: [4, 4]}
    position: [0, 0, 0.0025]
    material: cotton_eischen
colliders:
  - name: lift
    box: {size: [0.1, 0.1, 0.05]}
    position: [0, 0, -0.025]
    friction: 0.5
)" + motion;
}

double meanZ(const HybridShellDynamics& d) {
  double z = 0.0;
  for (const auto& x : d.positions()) z += x.z();
  return z / d.numVertices();
}

TEST(SimulationRun, MovingColliderCarriesTheCloth) {
  const double v = 0.5;  // [m/s] up, from rest at t = 0
  const SimulationScene scene = parseSimulationScene(
      sheetOnBox("    motion: {linear_velocity: [0, 0, " + std::to_string(v) + "]}\n"), "", "x");
  SimulationRun run(scene);
  const double z0 = meanZ(run.body(0));
  while (!run.finished()) run.advanceFrame();
  ASSERT_FALSE(run.stopped()) << run.stopReason();
  const HybridShellDynamics& d = run.body(0);
  double vz = 0.0;
  for (const auto& u : d.velocities()) vz += u.z();
  vz /= d.numVertices();
  const double rise = meanZ(d) - z0, box_rise = v * scene.duration;
  std::printf("[figure] box rose %.1f mm, sheet %.2f mm, sheet speed %.3f m/s (box %.3f)\n",
              1e3 * box_rise, 1e3 * rise, vz, v);
  // Lifted with the box (less the first instants' catching up), neither left behind nor
  // tunnelled through.
  EXPECT_NEAR(rise, box_rise, 0.1 * box_rise);
  EXPECT_NEAR(vz, v, 0.1 * v);
  const double top = run.colliderPoses()[0].translation().z() + 0.025;
  for (const auto& x : d.positions()) EXPECT_GT(x.z(), top - 1e-3);
}

// Hair whose roots ride on a collider: a head sphere moving at 0.2 m/s in x carries every
// strand's clamped root with it (the clamp reaches the collider's pose at each step's end).
TEST(SimulationRun, HairRootsRideTheirCollider) {
  const SimulationScene scene = parseSimulationScene(R"(
duration: 0.25
frame_rate: 20
world: {grid_spacing: 0.01}
hair:
  - name: scalp
    groom: {strands: 8, length: 0.05, segments: 5, radii: 0.05, cone_angle: 0.6}
    position: [0, 0, 1]
    roots: head
colliders:
  - name: head
    sphere: {radius: 0.05}
    position: [0, 0, 1]
    motion: {linear_velocity: [0.2, 0, 0]}
)",
                                                     "", "x");
  SimulationRun run(scene);
  ASSERT_EQ(run.numHair(), 1);
  FrameRecord last;
  while (!run.finished()) last = run.advanceFrame();
  ASSERT_FALSE(run.stopped()) << run.stopReason();
  double worst = 0.0;
  const Eigen::Vector3d shift(0.2 * 0.25, 0, 0);
  for (int s = 0; s < run.hair(0).numStrands(); ++s)
    worst = std::max(
        worst,
        (run.hair(0).strand(s).positions()[0] - (scene.hair[0].strands[s][0] + shift)).norm());
  std::printf(
      "[figure] head moved %.1f mm; roots off their place on it by at most %.2e m; hair "
      "kinetic energy %.3e J, stretch %.5f, penetration %.2e m\n",
      1e3 * shift.x(), worst, last.bodies[0].kinetic_energy, last.bodies[0].largest_stretch,
      last.bodies[0].deepest_penetration);
  EXPECT_LT(worst, 1e-9);
  ASSERT_EQ(last.bodies.size(), 1u);
  EXPECT_GT(last.bodies[0].kinetic_energy, 0.0);  // carried along and swinging
  EXPECT_LT(last.bodies[0].largest_stretch, 1.01);
}

// A step whose state is not finite is rolled back, halved down to max_halvings levels, and then
// stops the run at the last good state.
TEST(SimulationRun, DivergedStepIsRolledBackAndStops) {
  SimulationScene scene = parseSimulationScene(sheetOnBox(""), "", "x");
  // One step under this gravity leaves speeds whose kinetic energy overflows.
  scene.bodies[0].problem.gravity = Eigen::Vector3d(0, 0, -1e300);
  SimulationRun run(scene, 3);
  const FrameRecord rec = run.advanceFrame();
  ASSERT_TRUE(run.stopped());
  EXPECT_NE(run.stopReason().find("diverged"), std::string::npos) << run.stopReason();
  EXPECT_EQ(rec.rollbacks, 4);  // the step, its first half, quarter and eighth
  EXPECT_EQ(run.framesDone(), 0);
  EXPECT_DOUBLE_EQ(run.world().time(), 0.0);
}

}  // namespace
}  // namespace chs
