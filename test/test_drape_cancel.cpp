// Cancelling a static drape (CancelFlag): both solvers stop at the next iteration after the flag
// is set, report cancelled and return their last good state.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"
#include "cloth_hair_sim/core/io/scene.h"
#include "cloth_hair_sim/core/particle/particle_static_solver.h"

namespace chs {
namespace {

bool allFinite(const std::vector<Eigen::Vector3d>& x) {
  return std::all_of(x.begin(), x.end(), [](const Eigen::Vector3d& p) { return p.allFinite(); });
}

// The load-stepping cases run seed 000's path-following solver (the scene's default for a drape
// is the energy minimiser, cancelled in its own case below).
Scene tablecloth(const char* file) {
  Scene s = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/" + file);
  s.fem_shell.solver = FemShellMethod::kArcLength;
  s.fem_shell.edge_contact = false;  // as these cases were measured; quicker
  return s;
}

TEST(DrapeCancel, FemShellEnergyMinimisationReturnsTheLastAcceptedIterate) {
  Scene scene = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/tablecloth_fem.yaml");
  CancelFlag cancel{false};
  scene.fem_shell.cancel = &cancel;
  int events_after_cancel = 0;
  const DrapeResult r = solveFemShell(scene.problem, scene.fem_shell, [&](const ProgressEvent& e) {
    if (cancel) ++events_after_cancel;
    if (e.iteration == 5) cancel = true;
  });
  std::printf("cancelled: %s\n", r.status.c_str());
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.status.find("cancelled"), std::string::npos) << r.status;
  EXPECT_EQ(events_after_cancel, 0);
  EXPECT_EQ(r.iterations, 5);
  EXPECT_FALSE(r.stability.assessed);
  ASSERT_TRUE(allFinite(r.positions));
}

// A nested start (fem_shell.coarse_levels) cancelled while it drapes the coarse grid: the fine
// sheet is returned as it started, flat, with the coarse grid's iterations.
TEST(DrapeCancel, FemShellNestedStartCancelledOnTheCoarseGrid) {
  Scene scene = loadScene(std::string(CHS_SOURCE_DIR) + "/scenes/pedestal_square_48.yaml");
  ASSERT_EQ(scene.fem_shell.coarse_levels, 1);
  CancelFlag cancel{false};
  scene.fem_shell.cancel = &cancel;
  int events_after_cancel = 0;
  const DrapeResult r = solveFemShell(scene.problem, scene.fem_shell, [&](const ProgressEvent& e) {
    if (cancel) ++events_after_cancel;
    if (e.iteration == 3) cancel = true;
  });
  std::printf("cancelled: %s\n", r.status.c_str());
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.status.find("coarser grid"), std::string::npos) << r.status;
  EXPECT_EQ(events_after_cancel, 0);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.coarse_iterations, 3);
  ASSERT_EQ(r.positions.size(), scene.problem.mesh.vertices.size());
  for (std::size_t v = 0; v < r.positions.size(); ++v)
    EXPECT_EQ(r.positions[v], scene.problem.mesh.vertices[v]) << "vertex " << v;
}

TEST(DrapeCancel, FemShellStopsAtOnceAndReturnsTheLastConvergedLoadStep) {
  Scene scene = tablecloth("tablecloth_fem.yaml");
  CancelFlag cancel{false};
  scene.fem_shell.cancel = &cancel;
  int events_after_cancel = 0;
  const DrapeResult r = solveFemShell(scene.problem, scene.fem_shell, [&](const ProgressEvent& e) {
    if (cancel) ++events_after_cancel;
    if (e.load_step == 3) cancel = true;  // the first iteration of the third load step
  });
  std::printf("cancelled: %s\n", r.status.c_str());
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.status.find("cancelled"), std::string::npos) << r.status;
  EXPECT_EQ(events_after_cancel, 0) << "iterations ran after the cancel request";
  EXPECT_EQ(r.load_steps, 2);
  ASSERT_TRUE(allFinite(r.positions));

  // The same solve limited to two load steps stops at the same state.
  Scene limited = tablecloth("tablecloth_fem.yaml");
  limited.fem_shell.max_load_steps = 2;
  const DrapeResult two = solveFemShell(limited.problem, limited.fem_shell);
  ASSERT_FALSE(two.cancelled);
  ASSERT_EQ(two.positions.size(), r.positions.size());
  EXPECT_DOUBLE_EQ(two.load_factor, r.load_factor);
  double deviation = 0.0;
  for (size_t i = 0; i < r.positions.size(); ++i)
    deviation = std::max(deviation, (r.positions[i] - two.positions[i]).norm());
  EXPECT_EQ(deviation, 0.0);
}

TEST(DrapeCancel, FemShellWhileSettlingReturnsTheStateOfLeastResidual) {
  // The stabilised drape reaches load factor 1 in load step S; the pseudo-time settling that
  // follows reports as step S + 1.
  Scene scene = tablecloth("tablecloth_fem.yaml");
  ASSERT_GT(scene.fem_shell.stabilization, 0.0);
  CancelFlag cancel{false};
  scene.fem_shell.cancel = &cancel;
  int full_load_step = 0, events_after_cancel = 0;
  const DrapeResult r = solveFemShell(scene.problem, scene.fem_shell, [&](const ProgressEvent& e) {
    if (cancel) ++events_after_cancel;
    if (e.load_factor == 1.0 && full_load_step == 0) full_load_step = e.load_step;
    if (full_load_step > 0 && e.load_step > full_load_step && e.iteration == 2) cancel = true;
  });
  std::printf("cancelled: %s\n", r.status.c_str());
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.status.find("cancelled while settling"), std::string::npos) << r.status;
  EXPECT_EQ(events_after_cancel, 0);
  EXPECT_EQ(r.load_factor, 1.0);
  EXPECT_EQ(r.load_steps, full_load_step);
  EXPECT_TRUE(allFinite(r.positions));
}

TEST(DrapeCancel, ParticleStopsAtTheNextIteration) {
  Scene scene = tablecloth("tablecloth_particle.yaml");
  CancelFlag cancel{false};
  scene.particle.cancel = &cancel;
  scene.particle.progress_interval = 100;
  int last_total = 0;
  const DrapeResult r =
      solveParticleStatic(scene.problem, scene.particle, [&](const ProgressEvent& e) {
        EXPECT_GT(e.total_iterations, last_total);
        last_total = e.total_iterations;
        if (e.iteration >= 300) cancel = true;
      });
  std::printf("cancelled: %s\n", r.status.c_str());
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.status.find("cancelled"), std::string::npos) << r.status;
  EXPECT_EQ(r.iterations, 300);
  EXPECT_TRUE(allFinite(r.positions));
}

TEST(DrapeCancel, AFlagSetBeforehandLeavesTheReferenceState) {
  CancelFlag cancel{true};
  Scene fem = tablecloth("tablecloth_fem.yaml");
  fem.fem_shell.cancel = &cancel;
  const DrapeResult f = solveFemShell(fem.problem, fem.fem_shell);
  EXPECT_TRUE(f.cancelled);
  EXPECT_EQ(f.load_steps, 0);
  EXPECT_EQ(f.positions, fem.problem.mesh.vertices);

  Scene particle = tablecloth("tablecloth_particle.yaml");
  particle.particle.cancel = &cancel;
  const DrapeResult p = solveParticleStatic(particle.problem, particle.particle);
  EXPECT_TRUE(p.cancelled);
  EXPECT_EQ(p.iterations, 0);
  EXPECT_EQ(p.positions, particle.problem.mesh.vertices);
}

}  // namespace
}  // namespace chs
