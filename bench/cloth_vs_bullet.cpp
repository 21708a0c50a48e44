// Side-by-side benchmark (a table, not Google Benchmark): the same scene in Bullet 3.24's
// position-based btSoftBody and in the hybrid Lagrangian/MPM shell (Han chapter 5). A square
// cloth is dropped from `drop` above the top of a static sphere and simulated for `seconds` of
// simulated time with output at `fps`. Every frame records the wall time it took, the deepest
// penetration into the sphere (Bullet: its nodes; ours: the tessellated limit surface) and the
// largest stretch of the cloth's grid edges (length / rest length - 1). A run is "stable" when
// it stays finite, stays on the sphere, and neither sinks nor stretches grossly.
//
// Bullet is tuned fairly: several solver settings are run and the best stable one is named.
// Its soft body is single-threaded; the hybrid shell runs with TBB on --threads threads.
//
//   cloth_vs_bullet [--seconds 2] [--cells 32] [--every 10] [--threads N] [--single-thread-too]
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include "bench_machine.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"

namespace {

using Vec3 = Eigen::Vector3d;
using chs::bench::Clock;
using chs::bench::secondsSince;

struct DropScene {
  double size = 1.0;    // side of the square cloth [m]
  int cells = 32;       // cells per side: (cells + 1)^2 vertices
  double radius = 0.5;  // sphere at the origin [m]
  double drop = 0.1;    // initial gap between cloth and sphere top [m]
  double seconds = 2.0;
  double fps = 60.0;
  double friction = 0.3;  // Coulomb mu between cloth and sphere, in both simulators
  chs::ShellMaterial material = *chs::materialPreset("cotton_eischen");

  double height() const { return radius + drop; }
  int frames() const { return static_cast<int>(std::lround(seconds * fps)); }
  int side() const { return cells + 1; }
};

// Edges of a (side x side) vertex grid, vertex (i, j) at j * side + i, with their rest lengths.
struct GridEdges {
  std::vector<std::array<int, 2>> ends;
  std::vector<double> rest;

  GridEdges(int side, const std::vector<Vec3>& rest_positions) {
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const int v = j * side + i;
        if (i + 1 < side) ends.push_back({v, v + 1});
        if (j + 1 < side) ends.push_back({v, v + side});
      }
    for (const auto& e : ends) rest.push_back((rest_positions[e[1]] - rest_positions[e[0]]).norm());
  }

  double maxStretch(const std::vector<Vec3>& x) const {
    double s = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < ends.size(); ++k)
      s = std::max(s, (x[ends[k][1]] - x[ends[k][0]]).norm() / rest[k] - 1.0);
    return s;
  }
};

struct FrameSample {
  double wall_ms;
  double gap;  // signed distance of the cloth's closest point to the sphere (< 0: inside)
  double stretch;
  double penetration() const { return std::max(0.0, -gap); }
};

// Signed distance of the closest of the points to the sphere at the origin.
double closestGap(const std::vector<Vec3>& x, double radius) {
  double gap = std::numeric_limits<double>::infinity();
  for (const Vec3& p : x) gap = std::min(gap, p.norm() - radius);
  return gap;
}

struct Run {
  std::string name;
  std::vector<FrameSample> frames;
  std::string verdict;
  double centre_height = 0.0;  // of the cloth's middle vertex at the end [m]
  long steps = 0;              // solver steps over the whole run
};

bool allFinite(const std::vector<Vec3>& x) {
  return std::all_of(x.begin(), x.end(), [](const Vec3& p) { return p.allFinite(); });
}

// The verdict of a run: non-finite state, a cloth that ends below the sphere's equator (fell
// through or slid off), a sinking of more than a fifth of the radius or a stretch of more than
// 50 % (a cloth that pulls apart) are failures.
std::string verdictOf(const Run& r, const DropScene& scene, bool finite) {
  if (!finite) return "UNSTABLE: non-finite positions";
  if (r.centre_height < 0.0) return "FAILED: cloth fell through or off the sphere";
  double pen = 0.0, stretch = 0.0;
  for (const FrameSample& f : r.frames) {
    pen = std::max(pen, f.penetration());
    stretch = std::max(stretch, f.stretch);
  }
  if (pen > 0.2 * scene.radius) return "FAILED: sank into the sphere";
  if (stretch > 0.5) return "FAILED: over-stretched";
  return "stable";
}

void printFrame(const std::string& name, int frame, const FrameSample& f) {
  std::printf("  %-34s frame %4d  %9.2f ms  penetration %7.2f mm  gap %7.2f mm  stretch %6.2f %%\n",
              name.c_str(), frame, f.wall_ms, 1e3 * f.penetration(), 1e3 * f.gap, 1e2 * f.stretch);
  std::fflush(stdout);
}

// ---------------------------------------------------------------------------------------------
// Bullet 3.24 soft body.

struct BulletSettings {
  int piterations = 10;
  double margin = 0.01;        // soft body collision margin [m]
  double substep = 1.0 / 240;  // Bullet's fixed internal step [s]
  std::string label() const {
    char s[96];
    std::snprintf(s, sizeof s, "Bullet piter %d margin %.2f dt 1/%.0f", piterations, margin,
                  1.0 / substep);
    return s;
  }
};

Run runBullet(const DropScene& scene, const BulletSettings& b, int every) {
  btSoftBodyRigidBodyCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, 0, -9.81));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity.setValue(0, 0, -9.81);
  info.air_density = 0;  // no aerodynamics: the hybrid shell has none either
  info.m_sparsesdf.Initialize();

  btSphereShape sphere_shape(scene.radius);
  btRigidBody::btRigidBodyConstructionInfo sphere_info(0.0, nullptr, &sphere_shape);
  btRigidBody sphere(sphere_info);
  // Soft-rigid friction is kDF x the rigid body's friction (btSoftBodyInternals.h).
  sphere.setFriction(1.0);
  world.addRigidBody(&sphere);

  const double h = scene.height(), a = 0.5 * scene.size;
  std::unique_ptr<btSoftBody> cloth(btSoftBodyHelpers::CreatePatch(
      info, btVector3(-a, -a, h), btVector3(a, -a, h), btVector3(-a, a, h), btVector3(a, a, h),
      scene.side(), scene.side(), 0, true));
  cloth->m_materials[0]->m_kLST = 1.0;  // stiffest stretch Bullet offers: stretch limited
  cloth->m_cfg.piterations = b.piterations;
  cloth->m_cfg.kDF = scene.friction;
  cloth->getCollisionShape()->setMargin(b.margin);
  cloth->setTotalMass(scene.material.areal_density * scene.size * scene.size);
  world.addSoftBody(cloth.get());

  auto nodes = [&] {
    std::vector<Vec3> x(cloth->m_nodes.size());
    for (int k = 0; k < cloth->m_nodes.size(); ++k) {
      const btVector3& p = cloth->m_nodes[k].m_x;
      x[k] = Vec3(p.x(), p.y(), p.z());
    }
    return x;
  };
  const GridEdges edges(scene.side(), nodes());

  Run r;
  r.name = b.label();
  const int per_frame = static_cast<int>(std::lround(1.0 / (scene.fps * b.substep)));
  bool finite = true;
  for (int frame = 1; frame <= scene.frames() && finite; ++frame) {
    const auto start = Clock::now();
    world.stepSimulation(1.0 / scene.fps, per_frame + 1, b.substep);
    const double wall = secondsSince(start);
    r.steps += per_frame;
    const std::vector<Vec3> x = nodes();
    finite = allFinite(x);
    r.frames.push_back({1e3 * wall, closestGap(x, scene.radius), edges.maxStretch(x)});
    if (frame % every == 0) printFrame(r.name, frame, r.frames.back());
  }
  r.centre_height = nodes()[(scene.side() / 2) * scene.side() + scene.side() / 2].z();
  r.verdict = verdictOf(r, scene, finite);
  world.removeSoftBody(cloth.get());
  world.removeRigidBody(&sphere);
  return r;
}

// ---------------------------------------------------------------------------------------------
// The hybrid Lagrangian/MPM shell.

Run runHybrid(const DropScene& scene, chs::TimeIntegration integration, int threads, int every,
              const chs::HybridShellSettings& base) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  chs::DrapeProblem p;
  p.mesh = chs::makeRectangleMesh(scene.size, scene.size, scene.cells, scene.cells,
                                  Vec3(0, 0, scene.height()));
  p.material = scene.material;
  p.colliders = {std::make_shared<chs::SphereSurface>(Vec3::Zero(), scene.radius)};
  chs::HybridShellSettings s = base;
  s.friction = scene.friction;
  s.integration = integration;
  // One step per frame where the motion allows (CFL still shortens it).
  s.max_time_step = 1.0 / scene.fps;
  chs::HybridShellDynamics d(p, s);

  // The stretch on the limit surface at the control vertices (the same 33 x 33 grid as Bullet's
  // nodes), not on the control net.
  const std::vector<chs::SurfaceStencil> corners = chs::vertexStencils(p.mesh, d.limitSurface());
  const GridEdges edges(scene.side(), chs::evaluate(corners, d.positions()));

  Run r;
  r.name = "hybrid shell " + chs::timeIntegrationName(integration) + ", " +
           std::to_string(threads) + " thread(s)";
  bool finite = true;
  long newton = 0, factorizations = 0, unconverged = 0, evaluations = 0;
  for (int frame = 1; frame <= scene.frames() && finite; ++frame) {
    const double end = frame / scene.fps;
    const auto start = Clock::now();
    while (d.time() < end - 1e-12) {
      d.step(std::min(d.stableTimeStep(), end - d.time()));
      ++r.steps;
      newton += d.lastElasticSolve().iterations;
      factorizations += d.lastElasticSolve().factorizations;
      unconverged += (integration == chs::TimeIntegration::kLagrangianImplicit ||
                      integration == chs::TimeIntegration::kLagrangianBdf2) &&
                     !d.lastElasticSolve().converged;
      evaluations += d.lastImplicitSolve().residual_evaluations;
    }
    const double wall = secondsSince(start);
    finite = allFinite(d.positions());
    // The tessellated limit surface (the samples deepestPenetration() measures).
    r.frames.push_back({1e3 * wall, closestGap(d.surfacePoints(), scene.radius),
                        edges.maxStretch(chs::evaluate(corners, d.positions()))});
    if (frame % every == 0) printFrame(r.name, frame, r.frames.back());
  }
  const int centre = (scene.side() / 2) * scene.side() + scene.side() / 2;
  r.centre_height = corners[centre].position(d.positions()).z();
  // Where the time went: the hybrid shell's stages over the run.
  const chs::HybridStageTimes& t = d.stageTimes();
  std::printf(
      "  %s stages [s]: elastic solve %.2f, transfer to grid %.2f, shell forces %.2f, grid update "
      "%.2f, transfer to particles %.2f, plasticity %.2f\n",
      r.name.c_str(), t.elastic_solve, t.transfer_to_grid, t.shell_forces, t.grid_update,
      t.transfer_to_particles, t.plasticity);
  if (r.steps > 0)
    std::printf(
        "  per step: %.2f elastic Newton iterations, %.2f factorisations, %.1f force evaluations "
        "of the grid solve; %ld elastic solves short of the tolerance\n",
        double(newton) / r.steps, double(factorizations) / r.steps, double(evaluations) / r.steps,
        unconverged);
  r.verdict = verdictOf(r, scene, finite);
  return r;
}

// ---------------------------------------------------------------------------------------------

void printSummary(const std::vector<Run>& runs, const DropScene& scene) {
  std::printf(
      "\n| run | steps/frame | wall ms/frame (mean / max) | max penetration [mm] | final "
      "closest gap [mm] | max stretch [%%] | final stretch [%%] | centre z end [m] | verdict |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const Run& r : runs) {
    double sum = 0.0, worst = 0.0, pen = 0.0, stretch = 0.0;
    for (const FrameSample& f : r.frames) {
      sum += f.wall_ms;
      worst = std::max(worst, f.wall_ms);
      pen = std::max(pen, f.penetration());
      stretch = std::max(stretch, f.stretch);
    }
    const FrameSample& last = r.frames.back();
    std::printf("| %s | %.1f | %.2f / %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %s |\n",
                r.name.c_str(), static_cast<double>(r.steps) / r.frames.size(),
                sum / r.frames.size(), worst, 1e3 * pen, 1e3 * last.gap, 1e2 * stretch,
                1e2 * last.stretch, r.centre_height, r.verdict.c_str());
  }
  // Bullet's best: the stable setting with the shallowest penetration.
  const Run* best = nullptr;
  double best_pen = std::numeric_limits<double>::infinity();
  for (const Run& r : runs) {
    if (r.name.rfind("Bullet", 0) != 0 || r.verdict != "stable") continue;
    double pen = 0.0;
    for (const FrameSample& f : r.frames) pen = std::max(pen, f.penetration());
    if (pen < best_pen) best_pen = pen, best = &r;
  }
  std::printf("\nBullet's best stable setting (shallowest penetration): %s\n",
              best ? best->name.c_str() : "none was stable");
  std::printf("sphere radius %.2f m, %d frames of 1/%.0f s\n", scene.radius, scene.frames(),
              scene.fps);
}

}  // namespace

int main(int argc, char** argv) {
  DropScene scene;
  int every = 10;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  CLI::App app{"Cloth dropped on a sphere: Bullet soft body vs the hybrid MPM shell"};
  app.add_option("--seconds", scene.seconds, "simulated time [s]")->check(CLI::PositiveNumber);
  app.add_option("--cells", scene.cells, "cells per side of the cloth")->check(CLI::Range(2, 256));
  app.add_option("--every", every, "print every n-th frame")->check(CLI::PositiveNumber);
  app.add_option("--threads", threads, "TBB threads of the hybrid shell")
      ->check(CLI::PositiveNumber);
  bool single_thread_too = false;
  app.add_flag("--single-thread-too", single_thread_too, "also run the hybrid shell on 1 thread");
  std::vector<std::string> integrations = {"lagrangian_implicit", "symplectic_euler"};
  app.add_option("--integration", integrations,
                 "hybrid shell integrations to run: symplectic_euler, backward_euler, "
                 "lagrangian_implicit");
  chs::HybridShellSettings base;
  app.add_option("--lagrangian-tolerance", base.lagrangian_tolerance,
                 "the lagrangian_* steps' solve tolerance [m/s]")
      ->check(CLI::PositiveNumber);
  app.add_option("--contact-between-layers-only", base.contact_between_layers_only,
                 "lagrangian_*: the fibres' contact only where two layers meet (true, false)");
  app.add_option("--flip-blend", base.flip_blend,
                 "lagrangian_*: the transfer back's share of the elastic velocity the grid "
                 "averaged away, Han (4.12) (0: the grid's velocity alone)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--obstacle-stiffness", base.obstacle_stiffness,
                 "lagrangian_*: the sphere's penalty in the elastic solve (0: the grid alone)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  std::vector<chs::TimeIntegration> hybrid;
  try {
    for (const std::string& i : integrations) hybrid.push_back(chs::timeIntegrationFromName(i));
  } catch (const chs::InputError& e) {
    std::fprintf(stderr, "cloth_vs_bullet: %s\n", e.what());
    return 2;
  }

  chs::bench::printMachine(threads);
  std::printf(
      "scene: %.1f m cloth, %d x %d cells (%d vertices), dropped from %.2f m above a sphere of "
      "R = %.2f m, %.1f s at %.0f frames/s, friction %.2f\n"
      "material (both): areal density %.4f kg/m^2; hybrid shell E = %.4g Pa, h = %.3g mm, nu = "
      "%.2f (membrane stiffness %.1f N/m); Bullet kLST = 1 (stiffest), no bending links\n"
      "Bullet: single thread, btSoftRigidDynamicsWorld, SDF_RS collisions\n\n",
      scene.size, scene.cells, scene.cells, scene.side() * scene.side(), scene.drop, scene.radius,
      scene.seconds, scene.fps, scene.friction, scene.material.areal_density, scene.material.young,
      1e3 * scene.material.thickness, scene.material.poisson, scene.material.membraneStiffness());

  std::vector<Run> runs;
  const std::vector<BulletSettings> bullet = {
      {1, 0.25, 1.0 / 60},    // Bullet's defaults
      {10, 0.01, 1.0 / 240},  // libraries.md: ~1 ms/step, ~5 cm sink
      {20, 0.01, 1.0 / 240},
      {20, 0.01, 1.0 / 600},
  };
  for (const BulletSettings& b : bullet) runs.push_back(runBullet(scene, b, every));
  for (chs::TimeIntegration i : hybrid) {
    runs.push_back(runHybrid(scene, i, threads, every, base));
    if (single_thread_too && threads > 1) runs.push_back(runHybrid(scene, i, 1, every, base));
  }
  printSummary(runs, scene);
  return 0;
}
