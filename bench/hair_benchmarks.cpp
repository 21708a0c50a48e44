// Hair benchmarks (run by hand, never by ctest): a head of hair, N strands of 24 segments (10 cm
// human hair, clamped on the upper half of a 9 cm sphere that is also their collider, leaving it
// along the normal and falling onto it under gravity), stepped as the one body of a World at
// 1/120 s (two steps per 1/60 s frame; the CFL bound of a 1 cm grid allows it here). Each
// iteration is one frame; the counters split it into the body's stages (rod solve = beginStep,
// the implicit Newton per strand; to grid; grid = obstacles' conditions; from grid incl. the
// vertices' Coulomb impulses) and give segment-frames per core-second, Han's figure for his
// hair ball being about 790 (1.92 M segments at 122 s per frame on 20 threads).
//
// Arguments: {strands, TBB threads, continuum}. ms_collisions: the strand-strand impulses (Han
// 4.13, rod/strand_collisions.h), part of "from grid". continuum: 0 off, 1 the strands'
// continuum on the grid (Han 4.3-4.6, HairSettings::continuum, its contact blend; part of
// "grid"), 2 the same with Han's xi = 0.95 everywhere.
//
// hairOnWalkingHead: the same head walking (from standing to 1.2 m/s forward over 0.25 s, a 2 cm
// bob at 2 Hz, a 2 cm sway and a 10 degree yaw at 1 Hz, as a head over a walking gait), the roots
// carried by it and the sphere its collider with its velocity; each 1/60 s frame takes the steps
// the hair's CFL bound asks for (at most 1/120 s). Arguments: {strands, TBB threads}.
//
// fallingBundles: Han's Fig. 4.7 scaled down (as test_rod_strand_collisions): a bundle of n x n
// free 4 cm strands (16 segments, 1 mm apart) falling from 8 mm onto a crossing bundle of n x n
// clamped ones, 72 steps of 1/240 s per iteration; the cost per step of the collision stage and
// the missed crossings (the audit, core/collision/segment_crossings.h, outside the timing).
// Arguments: {n, TBB threads, continuum} (continuum as above).
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "bench_machine.h"
#include "cloth_hair_sim/core/collision/segment_crossings.h"
#include "cloth_hair_sim/core/contact/rigid_surface.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"
#include "cloth_hair_sim/core/world/world.h"

namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kHead = 0.09;  // scalp radius [m]
constexpr int kSegments = 24;

void setContinuum(chs::rod::HairSettings& s, int mode) {
  s.continuum.enabled = mode > 0;
  if (mode == 2) s.pic_blend = 0.95;
}

// Roots on the upper hemisphere, spread by the golden angle.
std::shared_ptr<chs::rod::HairDynamics> headOfHair(int strands, int continuum) {
  chs::rod::HairSettings s;
  s.grid_spacing = 0.01;
  setContinuum(s, continuum);
  s.strand_collisions.enabled = true;  // the collision stage is part of the frame measured
  auto hair = std::make_shared<chs::rod::HairDynamics>(s);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < strands; ++k) {
    const double z = 1.0 - (k + 0.5) / strands, r = std::sqrt(1.0 - z * z);
    const Vec3 n(r * std::cos(golden * k), r * std::sin(golden * k), z);
    hair->addStrand(chs::rod::straightStrand(kHead * n, n, 0.1, kSegments), chs::rod::humanHair());
  }
  return hair;
}

// One step of the world's stages for its one body (no contact between fields), timed per stage,
// with the strand solve's and the strand collisions' counts.
struct StageTimes {
  double solve = 0.0, to_grid = 0.0, grid = 0.0, from_grid = 0.0, collisions = 0.0;
  double candidates = 0.0, collision_passes = 0.0, zone_passes = 0.0, newton = 0.0;
  double full_searches = 0.0, partial_searches = 0.0;
  int steps = 0, max_newton = 0;

  void step(chs::rod::HairDynamics& hair, double dt) {
    auto t = chs::bench::Clock::now();
    hair.beginStep(dt);
    solve += chs::bench::secondsSince(t);
    t = chs::bench::Clock::now();
    hair.transferToGrid();
    to_grid += chs::bench::secondsSince(t);
    t = chs::bench::Clock::now();
    hair.updateGrid(dt);
    grid += chs::bench::secondsSince(t);
    t = chs::bench::Clock::now();
    hair.transferFromGrid(dt);
    hair.endStep(dt);
    from_grid += chs::bench::secondsSince(t);
    const chs::rod::StrandCollisionStats& c = hair.lastStrandCollisions();
    collisions += c.seconds;
    candidates += c.candidate_pairs;
    collision_passes += c.collision_passes;
    zone_passes += c.zone_passes;
    full_searches += c.full_searches;
    partial_searches += c.partial_searches;
    max_newton = std::max(max_newton, hair.lastNewtonIterations());
    newton += static_cast<double>(hair.lastTotalNewtonIterations()) / hair.numStrands();
    ++steps;
  }
  double wall() const { return solve + to_grid + grid + from_grid; }
  // Per frame: wall time and its stages, segment-frames per core-second; per step: Newton
  // iterations per strand, the broad phase's pairs and its full and partial searches, the
  // collision passes with impulses, the zone passes.
  void report(benchmark::State& state, int frames, int strands, int threads) const {
    state.counters["ms_frame"] = 1e3 * wall() / frames;
    state.counters["ms_rod_solve"] = 1e3 * solve / frames;
    state.counters["ms_to_grid"] = 1e3 * to_grid / frames;
    state.counters["ms_grid"] = 1e3 * grid / frames;
    state.counters["ms_from_grid"] = 1e3 * from_grid / frames;
    state.counters["ms_collisions"] = 1e3 * collisions / frames;
    state.counters["seg_frames_per_core_s"] =
        static_cast<double>(strands) * kSegments * frames / (wall() * threads);
    state.counters["max_newton"] = max_newton;
    state.counters["newton_per_strand_step"] = newton / steps;
    state.counters["candidates"] = candidates / steps;
    state.counters["collision_passes"] = collision_passes / steps;
    state.counters["zone_passes"] = zone_passes / steps;
    state.counters["full_searches"] = full_searches / steps;
    state.counters["partial_searches"] = partial_searches / steps;
  }
};

void hairFrame(benchmark::State& state) {
  const int strands = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  chs::WorldSettings ws;
  ws.grid_spacing = 0.01;
  chs::World world(ws);
  auto hair = headOfHair(strands, static_cast<int>(state.range(2)));
  world.add("hair", hair);
  world.setColliders({std::make_shared<chs::SphereSurface>(Vec3::Zero(), kHead)});
  const double dt = 1.0 / 120.0;
  for (int i = 0; i < 30; ++i) world.step(dt);  // the hair falls onto the head
  StageTimes times;
  int frames = 0;
  for (auto _ : state) {
    for (int sub = 0; sub < 2; ++sub) times.step(*hair, dt);
    ++frames;
  }
  times.report(state, frames, strands, threads);
}
BENCHMARK(hairFrame)
    ->Args({100, 1, 0})
    ->Args({100, 2, 0})
    ->Args({100, 1, 1})
    ->Args({100, 1, 2})
    ->Args({1000, 1, 0})
    ->Args({1000, 2, 0})
    ->Iterations(10)  // the same frames in every run, so that builds compare
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The walking head's pose at time t and its velocity there (linear, angular about its centre).
struct HeadMotion {
  Eigen::Isometry3d pose;
  chs::SurfaceVelocity velocity;
};
HeadMotion walkingHead(double t) {
  constexpr double kSpeed = 1.2, kRamp = 0.25, kBob = 0.02, kSway = 0.02;
  constexpr double kYaw = 10.0 * M_PI / 180.0, w = 2.0 * M_PI;  // 1 Hz: the stride; bob at 2 Hz
  HeadMotion m;
  // From standing, the forward speed rises linearly over kRamp seconds.
  const double forward = t < kRamp ? 0.5 * kSpeed * t * t / kRamp : kSpeed * (t - 0.5 * kRamp);
  const Vec3 centre(forward, kSway * std::sin(w * t), kBob * std::sin(2.0 * w * t));
  m.pose = Eigen::Translation3d(centre) * Eigen::AngleAxisd(kYaw * std::sin(w * t), Vec3::UnitZ());
  m.velocity.origin = centre;
  m.velocity.linear = Vec3(kSpeed * std::min(1.0, t / kRamp), kSway * w * std::cos(w * t),
                           kBob * 2.0 * w * std::cos(2.0 * w * t));
  m.velocity.angular = Vec3(0.0, 0.0, kYaw * w * std::cos(w * t));
  return m;
}

void hairOnWalkingHead(benchmark::State& state) {
  const int strands = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  chs::WorldSettings ws;
  ws.grid_spacing = 0.01;
  chs::World world(ws);
  auto hair = headOfHair(strands, 0);
  world.add("hair", hair);
  world.setColliders({std::make_shared<chs::SphereSurface>(Vec3::Zero(), kHead)});
  for (int i = 0; i < 30; ++i) world.step(1.0 / 120.0);  // the hair falls onto the still head
  const double frame = 1.0 / 60.0;
  double t = 0.0;
  StageTimes times;
  int frames = 0;
  for (auto _ : state) {
    for (double left = frame; left > 1e-12;) {
      const double dt = std::min({left, 1.0 / 120.0, hair->stableTimeStep()});
      // The roots' clamps move to the head's pose at the step's end; the collider is the sphere
      // where the head is now, moving with its velocity.
      const HeadMotion now = walkingHead(t), next = walkingHead(t + dt);
      for (int s = 0; s < hair->numStrands(); ++s) hair->setRootFrame(s, next.pose);
      world.setColliders({std::make_shared<chs::SphereSurface>(now.pose.translation(), kHead)},
                         {now.velocity});
      times.step(*hair, dt);
      t += dt;
      left -= dt;
    }
    ++frames;
  }
  times.report(state, frames, strands, threads);
  state.counters["steps_frame"] = static_cast<double>(times.steps) / frames;
  state.counters["real_time_factor"] = frames * frame / times.wall();
}
BENCHMARK(hairOnWalkingHead)
    ->Args({100, 2})
    ->Args({1000, 2})
    ->Args({2000, 2})  // issue 12's real-time goal: 2000 guides of 24 segments on 2 cores
    ->Iterations(30)   // half a second of walking
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void fallingBundles(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  const int segments = 16, steps = 72;
  const double gap = 1e-3, length = 0.04, dt = 1.0 / 240.0;
  double t_step = 0.0, t_collide = 0.0;
  std::size_t crossings = 0;
  int zone_steps = 0, runs = 0;
  for (auto _ : state) {
    chs::WorldSettings ws;
    ws.grid_spacing = 0.01;
    chs::World world(ws);
    chs::rod::HairSettings hs;
    hs.grid_spacing = 0.01;
    hs.strand_collisions.enabled = true;
    setContinuum(hs, static_cast<int>(state.range(2)));
    auto hair = std::make_shared<chs::rod::HairDynamics>(hs);
    world.add("hair", hair);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double p = (a - 0.5 * (n - 1)) * gap, q = (b - 0.5 * (n - 1)) * gap;
        hair->addStrand(
            chs::rod::straightStrand(Vec3(-0.5 * length, p, q), Vec3::UnitX(), length, segments),
            chs::rod::humanHair(), true);
        hair->addStrand(
            chs::rod::straightStrand(Vec3(0.25 * length + p, -0.5 * length, 0.008 + q + 0.5 * gap),
                                     Vec3::UnitY(), length, segments),
            chs::rod::humanHair(), false);
      }
    std::vector<int> offsets{0};
    for (int s = 0; s < hair->numStrands(); ++s)
      offsets.push_back(offsets.back() + hair->strand(s).numVertices());
    auto positions = [&] {
      std::vector<Vec3> x;
      for (int s = 0; s < hair->numStrands(); ++s)
        x.insert(x.end(), hair->strand(s).positions().begin(), hair->strand(s).positions().end());
      return x;
    };
    std::vector<Vec3> x0 = positions();
    for (int step = 0; step < steps; ++step) {
      const auto t = chs::bench::Clock::now();
      world.step(dt);
      t_step += chs::bench::secondsSince(t);
      t_collide += hair->lastStrandCollisions().seconds;
      zone_steps += hair->lastStrandCollisions().zone_passes > 0;
      state.PauseTiming();
      const std::vector<Vec3> x1 = positions();
      crossings += chs::countSegmentCrossings(x0, x1, offsets).count;
      x0 = x1;
      state.ResumeTiming();
    }
    ++runs;
  }
  state.counters["ms_step"] = 1e3 * t_step / (runs * steps);
  state.counters["ms_collisions_step"] = 1e3 * t_collide / (runs * steps);
  state.counters["collision_share"] = t_collide / t_step;
  state.counters["zone_steps"] = static_cast<double>(zone_steps) / runs;
  state.counters["missed_crossings"] = static_cast<double>(crossings) / runs;
}
BENCHMARK(fallingBundles)
    ->Args({4, 1, 0})
    ->Args({4, 2, 0})
    ->Args({6, 2, 0})
    ->Args({4, 1, 1})
    ->Args({4, 1, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  chs::bench::printMachine(2);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
