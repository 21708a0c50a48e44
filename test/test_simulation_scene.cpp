// Simulation scene files (io/simulation_scene.h): what a valid scene becomes, and that bad input
// is refused with the offending key named.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/simulation_scene.h"

namespace chs {
namespace {

const char* kScene = R"(
name: pair
duration: 0.5
frame_rate: 20
world: {grid_spacing: 0.02, body_friction: 0.4, integration: backward_euler, damping: 1.5,
        elastic_max_iterations: 12, cfl_between_layers_only: true,
        lagrangian_gravity_fraction: 0.01}
bodies:
  - name: towel
    rectangle: {size: [0.2, 0.1], cells: [4, 2]}
    position: [0, 0, 1]
    rotation: [0, 0, 1.5707963267948966]
    material: {preset: cotton_eischen, areal_density: 0.3}
    pins: [{nearest: [0, -0.1, 1]}, 0]
    velocity: [0, 0, -1]
colliders:
  - table: {size: [1, 1], depth: 0.2}
  - name: ball
    sphere: {radius: 0.1}
    friction: 0.1
    motion:
      keyframes:
        - {time: 0, position: [0, 0, 0]}
        - {time: 1, position: [1, 0, 0], rotation: [0, 0, 1]}
)";

std::string refusal(const std::string& text) {
  try {
    parseSimulationScene(text, CHS_SOURCE_DIR, "scene");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

// The valid scene with `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kScene;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(SimulationScene, ParsesBodiesWorldAndScriptedColliders) {
  const SimulationScene s = parseSimulationScene(kScene, CHS_SOURCE_DIR, "fallback");
  EXPECT_EQ(s.name, "pair");
  EXPECT_EQ(s.numFrames(), 10);
  EXPECT_DOUBLE_EQ(s.world.grid_spacing, 0.02);
  EXPECT_DOUBLE_EQ(s.shell.grid_spacing, 0.02);
  EXPECT_DOUBLE_EQ(s.world.body_friction, 0.4);
  EXPECT_EQ(s.shell.integration, TimeIntegration::kBackwardEuler);
  EXPECT_DOUBLE_EQ(s.shell.damping, 1.5);
  EXPECT_EQ(s.shell.elastic_max_iterations, 12);
  EXPECT_TRUE(s.shell.cfl_between_layers_only);
  EXPECT_DOUBLE_EQ(s.shell.lagrangian_gravity_fraction, 0.01);
  ASSERT_EQ(s.bodies.size(), 1u);
  const SimulationBody& b = s.bodies[0];
  EXPECT_EQ(b.name, "towel");
  EXPECT_EQ(b.material_name, "cotton_eischen (modified)");
  EXPECT_DOUBLE_EQ(b.problem.material.areal_density, 0.3);
  EXPECT_EQ(b.problem.mesh.numVertices(), 15);
  // Turned a quarter about z and lifted: the 0.2 m side now lies along y, at z = 1.
  Eigen::Vector3d lo = b.problem.mesh.vertices[0], hi = lo;
  for (const auto& v : b.problem.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  EXPECT_NEAR(hi.y() - lo.y(), 0.2, 1e-12);
  EXPECT_NEAR(hi.x() - lo.x(), 0.1, 1e-12);
  EXPECT_NEAR(lo.z(), 1.0, 1e-12);
  ASSERT_EQ(b.problem.bc.pinned.size(), 2u);  // vertex 0 and the one nearest (0, -0.1, 1)
  EXPECT_EQ(b.problem.bc.pinned[0], 0);
  EXPECT_NEAR(
      (b.problem.mesh.vertices[b.problem.bc.pinned[1]] - Eigen::Vector3d(0, -0.1, 1)).norm(), 0.0,
      1e-9);
  EXPECT_EQ(b.velocity, Eigen::Vector3d(0, 0, -1));

  ASSERT_EQ(s.colliders.size(), 2u);
  const SimulationCollider& table = s.colliders[0];
  EXPECT_EQ(table.name, "table0");
  EXPECT_FALSE(table.motion.moves());
  // The table's top face is centred on its frame.
  EXPECT_NEAR(table.surfaceAt(0.0)->project(Eigen::Vector3d(0.1, 0.1, 0.05)).gap, 0.05, 1e-9);
  const SimulationCollider& ball = s.colliders[1];
  EXPECT_EQ(ball.name, "ball");
  EXPECT_DOUBLE_EQ(ball.friction, 0.1);
  ASSERT_TRUE(ball.motion.moves());
  EXPECT_NEAR((ball.poseAt(0.25).translation() - Eigen::Vector3d(0.25, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((ball.poseAt(5.0).translation() - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);
  // The velocity of one substep carries the ball from its pose at t0 to the one at t1.
  const SurfaceVelocity u = ball.motion.velocity(ball.pose, 0.5, 0.6);
  EXPECT_NEAR((u.linear - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR((u.angular - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-9);
  EXPECT_NEAR((u.origin - ball.poseAt(0.6).translation()).norm(), 0, 1e-12);
}

TEST(SimulationScene, ConstantVelocityMotion) {
  const SimulationScene s = parseSimulationScene(
      edited("motion:\n      keyframes:\n        - {time: 0, position: [0, 0, 0]}\n"
             "        - {time: 1, position: [1, 0, 0], rotation: [0, 0, 1]}",
             "motion: {linear_velocity: [0, 2, 0]}"),
      CHS_SOURCE_DIR, "x");
  const SimulationCollider& ball = s.colliders[1];
  EXPECT_NEAR((ball.poseAt(0.5).translation() - Eigen::Vector3d(0, 1, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((ball.motion.velocity(ball.pose, 0.1, 0.2).linear - Eigen::Vector3d(0, 2, 0)).norm(),
              0, 1e-9);
}

TEST(SimulationScene, RefusesBadInputNamingTheKey) {
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {edited("frame_rate: 20", "frame_rate: 20\nframerate: 3"), "framerate: unknown key"},
      {edited("areal_density: 0.3", "areal_density: -0.3"),
       "bodies[0].material.areal_density: must not be negative"},
      {edited("rectangle: {size: [0.2, 0.1], cells: [4, 2]}", "mesh: {file: no/such.obj}"),
       "bodies[0].mesh.file: no such file"},
      {edited("pins: [{nearest: [0, -0.1, 1]}, 0]", "pins: [15]"),
       "bodies[0].pins[0]: vertex 15 is out of range (the mesh has 15 vertices)"},
      {edited("integration: backward_euler", "integration: leapfrog"),
       "must be symplectic_euler, backward_euler, lagrangian_implicit or lagrangian_bdf2"},
      {edited("sphere: {radius: 0.1}", "sphere: {radius: 0.1, colour: red}"),
       "colliders[1].sphere.colour: unknown key"},
      {edited("sphere: {radius: 0.1}", "cube: {size: 1}"),
       "colliders[1]: needs one of: plane, sphere, box"},
      {edited("time: 1, position", "time: 0, position"),
       "colliders[1].motion.keyframes[1].time: must exceed the previous keyframe's time"},
      {edited("name: ball",
              "name: wall\n    plane: {}\n  - name: wall\n    plane: {}\n  - name: ball"),
       "colliders[2].name: 'wall' is used twice"},
      {edited("duration: 0.5", "duration: -1"), "duration: must be positive"},
      {edited("elastic_max_iterations: 12", "elastic_max_iterations: 0"),
       "world.elastic_max_iterations: must be"},
      {edited("elastic_max_iterations: 12", "elastic_max_iterations: 12, flip_blend: 1.5"),
       "world.flip_blend: must lie in [0, 1]"},
      {edited("lagrangian_gravity_fraction: 0.01", "lagrangian_gravity_fraction: -0.1"),
       "world.lagrangian_gravity_fraction: must lie in [0, 1)"},
      {edited("cells: [4, 2]", "cells: [4, 2.5]"),
       "bodies[0].rectangle.cells: must be positive integers"},
      {edited("material: {preset: cotton_eischen, areal_density: 0.3}", "material: silk"),
       "bodies[0].material: unknown material preset 'silk'"},
      {"name: x\nduration: 1\n", "bodies: the scene needs at least one body or hair"},
  };
  for (const Case& c : cases) {
    const std::string message = refusal(c.text);
    EXPECT_NE(message.find(c.expect), std::string::npos)
        << "expected '" << c.expect << "' in: " << message;
  }
}

// Hair: a groom on a collider that carries its roots, and the refusals.
const char* kHair = R"(
name: hair
hair:
  - name: scalp
    groom: {strands: 12, length: 0.05, segments: 5, radii: 0.05, cone_angle: 0.8, seed: 2}
    position: [0, 0, 1]
    roots: head
    continuum: {friction: 0.5}
colliders:
  - name: head
    sphere: {radius: 0.05}
    position: [0, 0, 1]
)";

std::string hairEdited(const std::string& from, const std::string& to) {
  std::string s = kHair;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(SimulationScene, ParsesHair) {
  const SimulationScene s = parseSimulationScene(kHair, CHS_SOURCE_DIR, "x");
  ASSERT_EQ(s.hair.size(), 1u);
  const SimulationHair& h = s.hair[0];
  EXPECT_TRUE(s.bodies.empty());
  EXPECT_EQ(h.name, "scalp");
  ASSERT_EQ(h.strands.size(), 12u);
  EXPECT_EQ(h.strands[0].size(), 6u);
  for (const auto& strand : h.strands)  // rooted on the sphere at the groom's pose
    EXPECT_NEAR((strand.front() - Eigen::Vector3d(0, 0, 1)).norm(), 0.05, 1e-12);
  EXPECT_EQ(h.roots, "head");
  EXPECT_EQ(h.root_collider, 0);
  EXPECT_EQ(h.material_name, "human_hair");
  EXPECT_TRUE(h.continuum.enabled);  // a continuum section turns it on
  EXPECT_DOUBLE_EQ(h.continuum.friction, 0.5);
  // A strand file (the text format of io/strand_file.h), resampled.
  const std::string file =
      (std::filesystem::temp_directory_path() / "chs_scene_strands.txt").string();
  std::ofstream(file) << "3\n0 0 0\n0 0 -0.05\n0 0 -0.1\n";
  const SimulationScene f = parseSimulationScene(
      "hair:\n  - file: {file: " + file + ", segments: 4, scale: 2}\n    roots: loose\n", "", "y");
  ASSERT_EQ(f.hair.size(), 1u);
  EXPECT_EQ(f.hair[0].name, "hair0");
  ASSERT_EQ(f.hair[0].strands[0].size(), 5u);
  EXPECT_NEAR(f.hair[0].strands[0].back().z(), -0.2, 1e-12);
  EXPECT_FALSE(f.hair[0].continuum.enabled);
  // A groom on a head model's scalp: an octahedron of radius 5 (cm) scaled to 5 cm; the patch
  // about +z takes its four upper faces, the roots lie on them, posed 1 m up.
  const std::string head = (std::filesystem::temp_directory_path() / "chs_scene_head.obj").string();
  std::ofstream(head) << "v 5 0 0\nv -5 0 0\nv 0 5 0\nv 0 -5 0\nv 0 0 5\nv 0 0 -5\n"
                         "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\n"
                         "f 1 4 6\n";
  const SimulationScene m = parseSimulationScene(
      "hair:\n  - groom: {mesh: {file: " + head +
          ", scale: 0.01}, strands: 30, length: 0.05, segments: 5, cone_angle: 1.0}\n"
          "    position: [0, 0, 1]\n",
      "", "z");
  ASSERT_EQ(m.hair.size(), 1u);
  ASSERT_EQ(m.hair[0].strands.size(), 30u);
  for (const auto& strand : m.hair[0].strands) {  // on the upper faces: |x| + |y| + z = 0.05
    const Eigen::Vector3d r = strand.front() - Eigen::Vector3d(0, 0, 1);
    EXPECT_NEAR(std::abs(r.x()) + std::abs(r.y()) + r.z(), 0.05, 1e-12);
    EXPECT_GE(r.z(), 0.0);
  }
}

TEST(SimulationScene, RefusesBadHair) {
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {hairEdited("roots: head", "roots: neck"),
       "hair[0].roots: 'neck' is neither fixed, loose nor a collider's name"},
      {hairEdited("roots: head", "roots: head\n    material: wig"),
       "hair[0].material: unknown preset 'wig'"},
      {hairEdited("roots: head", "roots: head\n    material: {preset: human_hair, radius: -1e-5}"),
       "hair[0].material: material: radius"},
      {hairEdited("strands: 12", "strands: 0"), "hair[0].groom.strands"},
      {hairEdited("friction: 0.5", "friction: -0.5"), "hair[0].continuum"},
      {hairEdited("groom: {strands: 12, length: 0.05, segments: 5, radii: 0.05, cone_angle: "
                  "0.8, seed: 2}",
                  "file: no/such.hair"),
       "hair[0].file"},
      {hairEdited("name: scalp", "name: head"), ""},  // a hair and a collider may share a name
      {hairEdited("name: scalp", "name: scalp\n    comb: true"), "hair[0].comb: unknown key"},
      {hairEdited("radii: 0.05", "radii: 0.05, mesh: {file: head.obj}"),
       "hair[0].groom.radii: goes with an ellipsoid, not with mesh"},
      {hairEdited("radii: 0.05", "mesh: {file: no/such/head.obj}"), "no/such/head.obj"},
      {hairEdited("radii: 0.05", "mesh: {scale: 2}"), "hair[0].groom.mesh.file: missing"},
  };
  for (const Case& c : cases) {
    const std::string message = refusal(c.text);
    if (c.expect.empty()) {
      EXPECT_EQ(message, "(accepted)");
      continue;
    }
    std::printf("refused: %s\n", message.c_str());
    EXPECT_NE(message.find(c.expect), std::string::npos)
        << "expected '" << c.expect << "' in: " << message;
  }
}

TEST(SimulationScene, LoadNamesTheFile) {
  try {
    loadSimulationScene("/no/such/scene.yaml");
    FAIL() << "accepted a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/scene.yaml: no such scene file"),
              std::string::npos);
  }
  int shipped = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(CHS_SOURCE_DIR) + "/scenes")) {
    if (entry.path().stem().string().rfind("simulate_", 0) != 0) continue;
    const SimulationScene s = loadSimulationScene(entry.path().string());
    EXPECT_FALSE(s.bodies.empty() && s.hair.empty()) << entry.path();
    EXPECT_LE(s.duration, 1.0) << entry.path();  // shipped scenes run in reasonable time
    ++shipped;
  }
  EXPECT_GE(shipped, 4);
}

}  // namespace
}  // namespace chs
