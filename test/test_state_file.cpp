// Saved simulations (io/state_file.h, ClothDynamics::writeState/readState): a state read into a
// freshly built backend steps on exactly as the original does, and broken files are refused by
// name with the receiving state left as it was.
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/io/state_file.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/particle/particle_dynamics.h"
#include "cloth_test_material.h"

namespace chs {
namespace {

using Vec3 = Eigen::Vector3d;

// The message of the InputError f throws ("" if none).
std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A 10 cm square n x n quads 2 cm above a floor with friction, held at two corners.
DrapeProblem hangingSquare(int n, const ShellMaterial& material) {
  DrapeProblem p;
  p.mesh = makeRectangleMesh(0.1, 0.1, n, n);
  for (auto& x : p.mesh.vertices) x.z() = 0.02;
  p.material = material;
  p.gravity = Vec3(0, 0, -9.81);
  p.bc.pinned = {0, n};
  return p;
}

RigidSurfaces floorSurface() {
  return {std::make_shared<PlaneSurface>(Vec3(0, 0, 0), Vec3(0, 0, 1))};
}

// The corner 0 pulled sideways at 0.2 m/s: the pins' moving targets are part of the state.
void stepWithMovingPin(ClothDynamics& d, int steps, double dt) {
  for (int i = 0; i < steps; ++i) {
    d.pin(0, d.positions()[0] + Vec3(0.2 * dt, 0.0, 0.0));
    d.step(dt);
  }
}

std::string stateOf(const ClothDynamics& d) {
  StateWriter w;
  d.writeState(w);
  return w.data();
}

double maxDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).cwiseAbs().maxCoeff());
  return m;
}

// Saves `original` to a file, reads it into `restored`, and steps both on.
void expectIdenticalContinuation(ClothDynamics& original, ClothDynamics& restored, double dt,
                                 const char* name) {
  const std::string path = ::testing::TempDir() + "/chs_state_" + name + ".chs";
  writeStateFile(path, stateOf(original));
  original.dropSolverCaches();
  StateReader in(readStateFile(path), path);
  restored.readState(in);
  in.expectEnd();
  restored.setColliders(original.colliders());
  EXPECT_TRUE(stateOf(restored) == stateOf(original)) << "the read state is not the written one";
  EXPECT_EQ(restored.time(), original.time());
  stepWithMovingPin(original, 40, dt);
  stepWithMovingPin(restored, 40, dt);
  const double dx = maxDifference(restored.positions(), original.positions());
  const double dv = maxDifference(restored.velocities(), original.velocities());
  std::printf("[figure] %s: 40 steps after the restore, max |dx| %.3e m, max |dv| %.3e m/s\n", name,
              dx, dv);
  EXPECT_EQ(dx, 0.0);
  EXPECT_EQ(dv, 0.0);
  EXPECT_TRUE(stateOf(restored) == stateOf(original)) << "the states differ after the steps";
}

HybridShellSettings plasticShell() {
  HybridShellSettings s;
  s.yield_stress = 200.0;  // [Pa] the sag yields the lamina: the plastic state is saved too
  s.friction = 0.4;
  return s;
}

// TBB's thread-local force sums add in a scheduling-dependent order; one thread makes two runs
// comparable bit for bit.
class StateFile : public ::testing::Test {
 protected:
  tbb::global_control one_thread_{tbb::global_control::max_allowed_parallelism, 1};
};

TEST_F(StateFile, HybridShellContinuesBitForBit) {
  const DrapeProblem p = hangingSquare(6, testCloth());
  HybridShellDynamics original(p, plasticShell());
  original.setColliders(floorSurface());
  const double dt = original.stableTimeStep();
  stepWithMovingPin(original, 120, dt);
  // The lamina has yielded: an elastic twin hangs elsewhere.
  HybridShellSettings elastic = plasticShell();
  elastic.yield_stress = std::numeric_limits<double>::infinity();
  HybridShellDynamics twin(p, elastic);
  twin.setColliders(floorSurface());
  stepWithMovingPin(twin, 120, dt);
  EXPECT_GT(maxDifference(twin.positions(), original.positions()), 1e-9);
  HybridShellDynamics restored(p, plasticShell());
  expectIdenticalContinuation(original, restored, dt, "hybrid_shell");
}

// The Lagrangian step keeps solver caches between steps (the kept factor, quasi-Newton pairs,
// warm starts); a save drops them (ClothDynamics::dropSolverCaches), so that the saved run and
// its reload continue from the same start.
TEST_F(StateFile, LagrangianHybridShellContinuesBitForBit) {
  const DrapeProblem p = hangingSquare(6, testCloth());
  HybridShellSettings s = plasticShell();
  s.integration = TimeIntegration::kLagrangianImplicit;
  HybridShellDynamics original(p, s);
  original.setColliders(floorSurface());
  const double dt = 1.0 / 240.0;
  stepWithMovingPin(original, 60, dt);
  HybridShellDynamics restored(p, s);
  expectIdenticalContinuation(original, restored, dt, "hybrid_shell_lagrangian");
}

TEST_F(StateFile, ParticleNetworkContinuesBitForBit) {
  const DrapeProblem p = hangingSquare(6, *materialPreset("cotton_eischen"));
  ParticleDynamicsSettings s;
  s.friction = 0.4;
  ParticleDynamics original(p, s);
  original.setColliders(floorSurface());
  const double dt = original.stableTimeStep();
  stepWithMovingPin(original, 200, dt);
  ParticleDynamics restored(p, s);
  expectIdenticalContinuation(original, restored, dt, "particle");
}

TEST_F(StateFile, BrokenFilesAreRefusedByName) {
  const DrapeProblem p = hangingSquare(4, testCloth());
  HybridShellDynamics d(p);
  const std::string file = encodeStateFile(stateOf(d));
  EXPECT_EQ(decodeStateFile(file, "f"), stateOf(d));

  const std::string truncated = refusal([&] { decodeStateFile(file.substr(0, 500), "f"); });
  EXPECT_NE(truncated.find("f: truncated"), std::string::npos) << truncated;
  std::string flipped = file;
  flipped[flipped.size() / 2] ^= 0x10;
  const std::string corrupt = refusal([&] { decodeStateFile(flipped, "f"); });
  EXPECT_NE(corrupt.find("CRC-32"), std::string::npos) << corrupt;
  std::string older = file;
  older[8] = 0;  // the version field
  const std::string version = refusal([&] { decodeStateFile(older, "f"); });
  EXPECT_NE(version.find("state format version 0, this build reads version " +
                         std::to_string(kStateFormatVersion)),
            std::string::npos)
      << version;
  const std::string alien = refusal([&] { decodeStateFile("{\"json\": 1}", "f"); });
  EXPECT_NE(alien.find("not a cloth_hair_sim state file"), std::string::npos) << alien;
  const std::string longer = refusal([&] { decodeStateFile(file + "x", "f"); });
  EXPECT_NE(longer.find("1 bytes after"), std::string::npos) << longer;
  const std::string missing = refusal([&] { readStateFile(::testing::TempDir() + "/none.chs"); });
  EXPECT_NE(missing.find("cannot be read"), std::string::npos) << missing;
  std::printf("refusals:\n  %s\n  %s\n  %s\n  %s\n", truncated.c_str(), corrupt.c_str(),
              version.c_str(), alien.c_str());
}

TEST_F(StateFile, StateOfAnotherModelIsRefusedAndNothingChanges) {
  const DrapeProblem p = hangingSquare(4, testCloth());
  HybridShellDynamics d(p);
  d.setColliders(floorSurface());
  stepWithMovingPin(d, 10, d.stableTimeStep());
  const std::string before = stateOf(d);
  auto readInto = [&](ClothDynamics& target, const std::string& payload) {
    return refusal([&] {
      StateReader in(payload, "f");
      target.readState(in);
    });
  };

  // Another mesh: a wrong body count.
  HybridShellDynamics finer(hangingSquare(6, testCloth()));
  const std::string count = readInto(d, stateOf(finer));
  EXPECT_NE(count.find("control point positions: 49 saved, 25 here"), std::string::npos) << count;
  // Another backend.
  ParticleDynamics particle(p);
  const std::string backend = readInto(d, stateOf(particle));
  EXPECT_NE(backend.find("expected 'hybrid shell', found 'particle network'"), std::string::npos)
      << backend;
  const std::string reverse = readInto(particle, before);
  EXPECT_NE(reverse.find("expected 'particle network', found 'hybrid shell'"), std::string::npos)
      << reverse;
  // A payload cut inside a record (the file's checksum would catch this first).
  const std::string cut = readInto(d, before.substr(0, before.size() - 4));
  EXPECT_NE(cut.find("f: truncated in hybrid shell time"), std::string::npos) << cut;
  // A non-finite value.
  StateWriter nan;
  nan.text("particle network");
  nan.vectors(std::vector<Vec3>(particle.numVertices(), Vec3(0, 0, std::nan(""))));
  const std::string finite = readInto(particle, nan.data());
  EXPECT_NE(finite.find("non-finite value in particle positions"), std::string::npos) << finite;
  std::printf("refusals:\n  %s\n  %s\n  %s\n  %s\n", count.c_str(), backend.c_str(), cut.c_str(),
              finite.c_str());

  EXPECT_TRUE(stateOf(d) == before) << "a refused read changed the state";
}

}  // namespace
}  // namespace chs
