// Hybrid shell benchmarks (run by hand, never by ctest): the cost of one explicit step of
// HybridShellDynamics on a square sheet of n x n quads lying on a sphere, split into the stages
// of stageTimes(), the Kirchhoff-Love energy gradient alone (the shell forces' core), one fibre's
// Hessian for the implicit step (closed form against the former forward differences), and two
// sheets lying on each other stepped as two bodies of one World against the same two each on a
// grid of its own (the price of contact between their velocity fields).
//
// Arguments: {quads per side, TBB threads} and, for the step, the in-plane Gauss order of the
// Kirchhoff-Love quadrature (KirchhoffLoveQuadrature::in_plane_order). Counters are per step: stage
// times in ms and the cost per particle / per Kirchhoff-Love point in ns of wall time. The step
// size is the stable one at the start, so every iteration does the same work a drape would.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/io/material_presets.h"
#include "cloth_hair_sim/core/mesh/grid_generators.h"
#include "cloth_hair_sim/core/mpm/hybrid_shell_dynamics.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_quadrature.h"
#include "cloth_hair_sim/core/shell/stencil_hessian.h"
#include "cloth_hair_sim/core/subdiv/limit_surface.h"
#include "cloth_hair_sim/core/world/world.h"

namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kSphereRadius = 0.3;

// A 1 m x 1 m cotton-like sheet of n x n quads, horizontal, just above a sphere's top.
chs::DrapeProblem sheetOverSphere(int n) {
  chs::DrapeProblem p;
  p.mesh = chs::makeRectangleMesh(1.0, 1.0, n, n);
  for (auto& x : p.mesh.vertices) x.z() = kSphereRadius + 2e-3;
  p.material.young = 2e5;
  p.material.poisson = 0.3;
  p.material.thickness = 5e-4;
  p.material.areal_density = 0.2;
  p.colliders.push_back(std::make_shared<chs::SphereSurface>(Vec3::Zero(), kSphereRadius));
  return p;
}

// Milliseconds per step of one stage over the timed steps.
double perStep(double before, double after, int steps) {
  return 1e3 * (after - before) / steps;
}

void hybridStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(1));
  chs::HybridShellSettings settings;
  settings.kirchhoff_love.in_plane_order = static_cast<int>(state.range(2));
  chs::HybridShellDynamics d(sheetOverSphere(n), settings);
  const double dt = d.stableTimeStep();
  for (int i = 0; i < 20; ++i) d.step(dt);  // the sheet settles onto the sphere
  const chs::HybridStageTimes t0 = d.stageTimes();
  for (auto _ : state) d.step(dt);
  const chs::HybridStageTimes t1 = d.stageTimes();
  const int steps = t1.steps - t0.steps;
  const int particles = d.numVertices() + d.numContactParticles();
  state.counters["quads"] = n * n;
  state.counters["particles"] = particles;
  state.counters["kl_points"] = d.numQuadraturePoints();
  state.counters["grid_nodes"] = d.numGridNodes();
  state.counters["p2g_ms"] = perStep(t0.transfer_to_grid, t1.transfer_to_grid, steps);
  state.counters["forces_ms"] = perStep(t0.shell_forces, t1.shell_forces, steps);
  state.counters["grid_ms"] = perStep(t0.grid_update, t1.grid_update, steps);
  state.counters["g2p_ms"] = perStep(t0.transfer_to_particles, t1.transfer_to_particles, steps);
  state.counters["plast_ms"] = perStep(t0.plasticity, t1.plasticity, steps);
  state.counters["p2g_ns_per_particle"] =
      1e6 * perStep(t0.transfer_to_grid, t1.transfer_to_grid, steps) / particles;
  state.counters["g2p_ns_per_particle"] =
      1e6 * perStep(t0.transfer_to_particles, t1.transfer_to_particles, steps) / particles;
  state.counters["forces_ns_per_kl_point"] =
      1e6 * perStep(t0.shell_forces, t1.shell_forces, steps) / d.numQuadraturePoints();
  state.counters["dt_us"] = 1e6 * dt;
}
BENCHMARK(hybridStep)
    ->ArgsProduct({{32, 90}, {1, 2}, {2, 3}})
    ->ArgNames({"quads", "threads", "kl_order"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// kirchhoffLoveEnergy with its gradient over all quadrature points of a bent n x n sheet.
void kirchhoffLoveGradient(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(1));
  const chs::QuadMesh mesh = chs::makeRectangleMesh(1.0, 1.0, n, n);
  const chs::LimitSurface surface(mesh);
  const auto points = chs::buildKirchhoffLovePoints(
      surface.numFaces(), [&](int f, double u, double v) { return surface.stencil(f, u, v); },
      mesh.vertices, 5e-4);
  std::vector<Vec3> x;
  for (const Vec3& X : mesh.vertices)  // stretched and bent over a cylinder
    x.push_back(Vec3(1.02 * std::sin(X.x()), X.y(), 1.02 * std::cos(X.x())));
  const chs::HenckyLamina lamina(2e5, 0.3);
  std::vector<Vec3> gradient;
  for (auto _ : state)
    benchmark::DoNotOptimize(chs::kirchhoffLoveEnergy(points, lamina, x, &gradient));
  state.counters["kl_points"] = static_cast<double>(points.size());
  state.counters["ns_per_kl_point"] = benchmark::Counter(
      static_cast<double>(points.size()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(kirchhoffLoveGradient)
    ->ArgsProduct({{32, 90}, {1, 2}})
    ->ArgNames({"quads", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The former fibre Hessian, for comparison: forward differences of the exact gradient in the sums
// (steps of 1e-7 of their size), symmetrised.
chs::FibreHessian forwardDifferenceFibreHessian(const std::vector<chs::KirchhoffLovePoint>& points,
                                                const chs::FibreRange& fibre,
                                                const chs::HenckyLamina& material,
                                                const chs::StencilSums& s) {
  chs::StencilSums g0, g1;
  chs::fibreEnergy(points, fibre, material, s, &g0);
  chs::FibreHessian H;
  for (int a = 0; a < 5; ++a) {
    const double h = 1e-7 * std::max({s[a].norm(), s[0].norm(), s[1].norm()});
    for (int i = 0; i < 3; ++i) {
      chs::StencilSums t = s;
      t[a][i] += h;
      chs::fibreEnergy(points, fibre, material, t, &g1);
      for (int b = 0; b < 5; ++b) H.block<3, 1>(3 * b, 3 * a + i) = (g1[b] - g0[b]) / h;
    }
  }
  return 0.5 * (H + H.transpose());
}

// projectedFibreHessian's projection, applied to the differences as the former version did.
chs::FibreHessian projected(const chs::FibreHessian& H) {
  const Eigen::LDLT<chs::FibreHessian> ldlt(H);
  const auto& d = ldlt.vectorD();
  if (ldlt.info() == Eigen::Success && d.minCoeff() >= -1e-6 * d.cwiseAbs().maxCoeff()) return H;
  Eigen::SelfAdjointEigenSolver<chs::FibreHessian> eig(H);
  const Eigen::Matrix<double, 15, 1> lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

// The fibres of lagrangianStep's towel (scene 0: 50 x 50 cm cotton, 25 x 25 cells, pinned at two
// adjacent corners) 60 steps after its release, hanging and wrinkled at the pins, with their
// stencil sums; built once.
struct TowelFibres {
  std::vector<chs::KirchhoffLovePoint> points;
  std::vector<chs::FibreRange> fibres;
  std::vector<chs::StencilSums> sums;
  chs::HenckyLamina lamina{1.0, 0.3};
};

const TowelFibres& towelFibres() {
  static const TowelFibres towel = [] {
    const int n = 25;
    chs::DrapeProblem p;
    p.material = *chs::materialPreset("cotton_eischen");
    p.mesh = chs::makeRectangleMesh(0.5, 0.5, n, n);
    for (auto& x : p.mesh.vertices) x.z() = 1.0;
    p.bc.pinned = {n * (n + 1), (n + 1) * (n + 1) - 1};
    chs::HybridShellSettings settings;
    settings.integration = chs::TimeIntegration::kLagrangianImplicit;
    settings.max_time_step = 1.0 / 60.0;
    settings.friction = 0.3;
    chs::HybridShellDynamics d(p, settings);
    for (int i = 0; i < 60; ++i) d.step(d.stableTimeStep());
    TowelFibres t;
    const chs::LimitSurface surface(p.mesh);
    t.points = chs::buildKirchhoffLovePoints(
        surface.numFaces(), [&](int f, double u, double v) { return surface.stencil(f, u, v); },
        p.mesh.vertices, p.material.thickness, settings.kirchhoff_love);
    t.fibres = chs::fibreRanges(t.points);
    for (const chs::FibreRange& f : t.fibres)
      t.sums.push_back(chs::MidSurfaceFrame::sums(t.points[f.first].stencil(), d.positions()));
    t.lamina = chs::HenckyLamina(p.material.young, p.material.poisson);
    return t;
  }();
  return towel;
}

// One fibre's Hessian for the implicit step on towelFibres. method: 0, projectedFibreHessian
// (closed form, projected); 1, the former forward differences with the same projection; 2 and 3,
// the closed form and the differences alone. One thread; ns_per_fibre of wall time; indefinite,
// the share of fibres that the projection's eigen-decomposition handles.
void fibreHessian(benchmark::State& state) {
  const TowelFibres& towel = towelFibres();
  const auto& points = towel.points;
  const auto& fibres = towel.fibres;
  const auto& sums = towel.sums;
  const chs::HenckyLamina& lamina = towel.lamina;
  int indefinite = 0;
  for (std::size_t f = 0; f < fibres.size(); ++f) {
    const chs::FibreHessian H = chs::fibreHessian(points, fibres[f], lamina, sums[f]);
    if (projected(H) != H) ++indefinite;
  }
  const int method = static_cast<int>(state.range(0));
  for (auto _ : state) {
    for (std::size_t f = 0; f < fibres.size(); ++f) {
      const chs::FibreRange& r = fibres[f];
      chs::FibreHessian H;
      switch (method) {
        case 0:
          H = chs::projectedFibreHessian(points, r, lamina, sums[f]);
          break;
        case 1:
          H = projected(forwardDifferenceFibreHessian(points, r, lamina, sums[f]));
          break;
        case 2:
          H = chs::fibreHessian(points, r, lamina, sums[f]);
          break;
        default:
          H = forwardDifferenceFibreHessian(points, r, lamina, sums[f]);
      }
      benchmark::DoNotOptimize(H.data());
    }
  }
  state.counters["fibres"] = static_cast<double>(fibres.size());
  state.counters["indefinite"] = static_cast<double>(indefinite) / fibres.size();
  state.counters["ns_per_fibre"] = benchmark::Counter(
      static_cast<double>(fibres.size()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(fibreHessian)->DenseRange(0, 3)->ArgName("method")->Unit(benchmark::kMillisecond);

// The towel's fibre Hessians (exact, computed once) summed face by face into the stencil
// blocks, as the Newton matrix's assembly does (shell/stencil_hessian.h); one thread.
// ns_per_face of wall time, over the regular, boundary and corner faces alike.
void faceHessianSum(benchmark::State& state) {
  const TowelFibres& towel = towelFibres();
  std::vector<chs::FibreHessian> H;
  for (std::size_t f = 0; f < towel.fibres.size(); ++f)
    H.push_back(chs::fibreHessian(towel.points, towel.fibres[f], towel.lamina, towel.sums[f]));
  std::vector<int> faces;  // first fibre of each run over one stencil
  for (std::size_t f = 0; f < towel.fibres.size(); ++f)
    if (f == 0 || towel.points[towel.fibres[f].first].stencil().points !=
                      towel.points[towel.fibres[f - 1].first].stencil().points)
      faces.push_back(static_cast<int>(f));
  faces.push_back(static_cast<int>(towel.fibres.size()));
  chs::StencilHessian K;
  for (auto _ : state)
    for (std::size_t g = 0; g + 1 < faces.size(); ++g) {
      K.reset(towel.points[towel.fibres[faces[g]].first].stencil().size());
      for (int f = faces[g]; f < faces[g + 1]; ++f)
        K.add(towel.points[towel.fibres[f].first].stencil(), H[f]);
      K.finish();
      benchmark::DoNotOptimize(K.block(0, 0).data());
    }
  const double n = static_cast<double>(faces.size() - 1);
  state.counters["faces"] = n;
  state.counters["ns_per_face"] = benchmark::Counter(
      n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(faceHessianSum)->Unit(benchmark::kMillisecond);

// Two n x n sheets, the upper one a quarter cell above the lower one, over the sphere: one step
// of both, in one world (in_world = 1: field contact between them) or each alone (0).
void twoSheets(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool in_world = state.range(1) != 0;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  chs::HybridShellSettings settings;
  settings.grid_spacing = 1.0 / n;
  chs::DrapeProblem upper = sheetOverSphere(n);
  for (auto& x : upper.mesh.vertices) x.z() += 0.3 * settings.grid_spacing;
  auto a = std::make_shared<chs::HybridShellDynamics>(sheetOverSphere(n), settings);
  auto b = std::make_shared<chs::HybridShellDynamics>(upper, settings);
  chs::WorldSettings ws;
  ws.grid_spacing = settings.grid_spacing;
  chs::World world(ws);
  world.add("lower", a);
  world.add("upper", b);
  world.setColliders(a->colliders(), {}, {});
  const double dt = std::min(a->stableTimeStep(), b->stableTimeStep());
  int contact_nodes = 0, steps = 0;
  auto step = [&] {
    if (in_world) {
      contact_nodes += world.step(dt).contact.contact_nodes;
    } else {
      a->step(dt);
      b->step(dt);
    }
    ++steps;
  };
  for (int i = 0; i < 20; ++i) step();
  contact_nodes = steps = 0;
  for (auto _ : state) step();
  state.counters["quads_per_sheet"] = n * n;
  state.counters["contact_nodes_per_step"] = static_cast<double>(contact_nodes) / steps;
}
BENCHMARK(twoSheets)
    ->ArgsProduct({{32, 64}, {0, 1}})
    ->ArgNames({"quads", "in_world"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The Lagrangian implicit step (time_integration.h) on the scenes of the speed goals, each step
// at the scene's own step (max 1/60 s, shortened by CFL): scene 0, the node's towel (50 x 50 cm
// cotton, 2 cm cells, pinned at two adjacent corners, falling from flat); scene 1,
// cloth_vs_bullet's 1 x 1 m cotton of 32 x 32 cells dropped 10 cm onto a 0.5 m sphere; scene 2,
// one garment of the node's 20-garment row (16 x 16 cm, 8 x 8 cells, as scene 0 otherwise). Each
// iteration is one step, from `warm_steps` steps into the run; counters are per step: stage and
// solver times [ms], Newton iterations and factorisations of the elastic solve, force evaluations
// of the grid's contact solve, the real-time factor dt / wall, and (deep_mm) the limit surface's
// deepest penetration of a collider at the end. history: the elastic solve's
// L-BFGS pairs (0: chord iterations on the kept factor). settings: 0, those of 2026-12-02 for
// side-by-side runs (the elastic and contact solves to 1e-5 m/s); 1, the defaults; 2, the
// defaults with the transfer back of before 2026-12-07 (flip_blend 0: the grid's velocity at
// every point; every fibre carrying contact); 3, the defaults without the obstacles in the
// elastic solve (obstacle_stiffness 0: the grid alone, as before 2026-12-07); 4, the defaults
// with the step bound of before 2026-12-07 (cfl_between_layers_only false: every pair of control
// points counts by its relative speed, a swinging towel steps at 3-4 ms).
void lagrangianStep(benchmark::State& state) {
  const bool small = state.range(0) == 2, towel = state.range(0) == 0 || small;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  chs::DrapeProblem p;
  p.material = *chs::materialPreset("cotton_eischen");
  const int n = small ? 8 : towel ? 25 : 32;
  const double size = small ? 0.16 : towel ? 0.5 : 1.0;
  p.mesh = chs::makeRectangleMesh(size, size, n, n);
  for (auto& x : p.mesh.vertices) x.z() = towel ? 1.0 : 0.6;
  if (towel) {
    p.bc.pinned = {n * (n + 1), (n + 1) * (n + 1) - 1};
  } else {
    p.colliders.push_back(std::make_shared<chs::SphereSurface>(Vec3::Zero(), 0.5));
  }
  chs::HybridShellSettings settings;
  settings.integration = chs::TimeIntegration::kLagrangianImplicit;
  settings.max_time_step = 1.0 / 60.0;
  settings.friction = 0.3;
  settings.elastic_history = static_cast<int>(state.range(2));
  if (state.range(3) == 0) settings.lagrangian_tolerance = 1e-5;
  if (state.range(3) == 2) {
    settings.flip_blend = 0.0;
    settings.contact_between_layers_only = false;
  }
  if (state.range(3) == 3) settings.obstacle_stiffness = 0.0;
  if (state.range(3) == 4) settings.cfl_between_layers_only = false;
  chs::HybridShellDynamics d(p, settings);
  double t = 0.0;
  for (int i = 0; i < state.range(1); ++i) {
    const double dt = d.stableTimeStep();
    d.step(dt);
    t += dt;
  }
  const chs::HybridStageTimes t0 = d.stageTimes();
  double sim = 0.0, assembly = 0.0, factor = 0.0;
  int newton = 0, factorizations = 0, refusals = 0, evaluations = 0, potentials = 0;
  for (auto _ : state) {
    const double dt = d.stableTimeStep();
    d.step(dt);
    sim += dt;
    const chs::ImplicitElasticityResult& e = d.lastElasticSolve();
    newton += e.iterations;
    factorizations += e.factorizations;
    refusals += e.exact_refusals;
    potentials += e.potential_evaluations;
    assembly += e.assembly_seconds;
    factor += e.factorization_seconds;
    evaluations += d.lastImplicitSolve().residual_evaluations;
  }
  const chs::HybridStageTimes t1 = d.stageTimes();
  const int steps = t1.steps - t0.steps;
  state.counters["elastic_ms"] = perStep(t0.elastic_solve, t1.elastic_solve, steps);
  state.counters["assembly_ms"] = 1e3 * assembly / steps;
  state.counters["factor_ms"] = 1e3 * factor / steps;
  state.counters["grid_ms"] = perStep(t0.grid_update, t1.grid_update, steps);
  state.counters["transfers_ms"] = perStep(t0.transfer_to_grid + t0.transfer_to_particles,
                                           t1.transfer_to_grid + t1.transfer_to_particles, steps);
  state.counters["newton"] = static_cast<double>(newton) / steps;
  state.counters["factorizations"] = static_cast<double>(factorizations) / steps;
  state.counters["refusals"] = static_cast<double>(refusals) / steps;
  state.counters["potentials"] = static_cast<double>(potentials) / steps;
  state.counters["grid_evaluations"] = static_cast<double>(evaluations) / steps;
  state.counters["dt_ms"] = 1e3 * sim / steps;
  const double wall = (t1.elastic_solve + t1.transfer_to_grid + t1.grid_update +
                       t1.transfer_to_particles + t1.plasticity) -
                      (t0.elastic_solve + t0.transfer_to_grid + t0.grid_update +
                       t0.transfer_to_particles + t0.plasticity);
  state.counters["real_time_factor"] = sim / wall;
  state.counters["deep_mm"] = 1e3 * d.deepestPenetration();
}
BENCHMARK(lagrangianStep)
    ->ArgsProduct({{0, 1, 2}, {30, 400}, {0, 8}, {0, 1, 2, 3, 4}})
    ->ArgNames({"scene", "warm_steps", "history", "settings"})
    ->Iterations(20)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
