// Strand-strand collisions (core/rod/strand_collisions.h, Han (4.13) after Bridson et al. 2002)
// and the missed-crossing audit (core/collision/segment_crossings.h): the continuous test of
// two segments (head-on crossing at the right time, parallel, near miss, touching), the
// impulses' linear momentum, and Han's two bundles falling on each other (Fig. 4.7, scaled
// down) with the crossings over the run counted with and without the impulses.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/collision/segment_crossings.h"
#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/rod/hair_dynamics.h"
#include "cloth_hair_sim/core/rod/strand_collisions.h"
#include "cloth_hair_sim/core/rod/strand_shapes.h"
#include "cloth_hair_sim/core/world/world.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
using Points = std::array<Vec3, 4>;

Points ends(const Points& x, const Points& d) {
  return {x[0] + d[0], x[1] + d[1], x[2] + d[2], x[3] + d[3]};
}

// a along x at z = 0, b along y above it at height h, falling by `drop` over the step; b
// shifted along x by `shift` (past a's end when > 1).
struct Cross {
  Points x, d;
  Cross(double h, double drop, double shift = 0.0) {
    x = {Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(shift, -1, h), Vec3(shift, 1, h)};
    d = {Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, -drop), Vec3(0, 0, -drop)};
  }
};

TEST(SegmentCollision, HeadOnCrossingAtTheRightTime) {
  // Hair scale too: 2.5 mm segments, 1.8 mm apart, 4 mm drop: they meet at t = 0.45.
  for (double scale : {1.0, 1.25e-3}) {
    Cross c(0.9, 2.0);
    for (int k = 0; k < 4; ++k) {
      c.x[k] *= scale;
      c.d[k] *= scale;
    }
    const auto hit = segmentCollision(c.x, c.d, 1e-6 * scale);
    double t_audit = -1.0;
    const bool crossed = segmentsCrossDuringStep(c.x, ends(c.x, c.d), &t_audit);
    ASSERT_TRUE(hit.has_value());
    ASSERT_TRUE(crossed);
    std::printf("head-on (scale %.2e m): impulses' time %.15f, audit's %.15f, exact 0.45\n", scale,
                hit->time, t_audit);
    EXPECT_NEAR(hit->time, 0.45, 1e-6);  // the first time within the margin
    EXPECT_NEAR(t_audit, 0.45, 1e-12);
    EXPECT_NEAR(hit->s, 0.5, 1e-9);
    EXPECT_NEAR(hit->u, 0.5, 1e-9);
    EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);  // from a to b as they started
  }
}

TEST(SegmentCollision, ParallelNearMissAndTouching) {
  // Parallel segments, b dropping through a: coplanar throughout (the sampled branch).
  Points x{Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(-0.5, 0, 1), Vec3(1.5, 0, 1)};
  Points d{Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, -2), Vec3(0, 0, -2)};
  bool flat = false;
  double t = -1.0;
  EXPECT_TRUE(segmentsCrossDuringStep(x, ends(x, d), &t, &flat));
  EXPECT_TRUE(flat);
  EXPECT_NEAR(t, 0.5, 1e-12);
  EXPECT_TRUE(segmentCollision(x, d, 1e-6).has_value());
  // The same, b beside a by 1e-3: no contact.
  for (int k = 2; k < 4; ++k) x[k].y() = 1e-3;
  EXPECT_FALSE(segmentsCrossDuringStep(x, ends(x, d)));
  EXPECT_FALSE(segmentCollision(x, d, 1e-6).has_value());
  // Near miss: the lines cross at t = 0.5 but 1e-3 past a's end.
  Cross miss(1.0, 2.0, 1.0 + 1e-3);
  EXPECT_FALSE(segmentsCrossDuringStep(miss.x, ends(miss.x, miss.d)));
  EXPECT_FALSE(segmentCollision(miss.x, miss.d, 1e-4).has_value());
  EXPECT_TRUE(segmentCollision(miss.x, miss.d, 2e-3).has_value());  // within a wider margin
  // Touching at the step's end counts; stopping 1e-9 short does not.
  Cross touch(1.0, 1.0);
  EXPECT_TRUE(segmentsCrossDuringStep(touch.x, ends(touch.x, touch.d), &t));
  EXPECT_DOUBLE_EQ(t, 1.0);
  Cross shy(1.0, 1.0 - 1e-9);
  EXPECT_FALSE(segmentsCrossDuringStep(shy.x, ends(shy.x, shy.d)));
  // Moving apart, or side by side without crossing: no contact.
  Cross apart(0.5, -1.0);
  EXPECT_FALSE(segmentsCrossDuringStep(apart.x, ends(apart.x, apart.d)));
  EXPECT_FALSE(segmentCollision(apart.x, apart.d, 1e-3).has_value());
  // A pair starting 1e-5 apart and sliding along each other within the margin: a contact (the
  // impulses push it out), but not a crossing.
  Points slide{Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 1e-5), Vec3(0, 1, 1e-5)};
  Points along{Vec3::Zero(), Vec3::Zero(), Vec3(0.3, 0, 0), Vec3(0.3, 0, 0)};
  EXPECT_TRUE(segmentCollision(slide, along, 1e-4).has_value());
  EXPECT_FALSE(segmentsCrossDuringStep(slide, ends(slide, along)));
  // A turning b sweeping through a near its end: flat in z = 0 across a at t = 0.5.
  Points spin{Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.9, -1, 0.3), Vec3(0.9, 1, -0.1)};
  Points turn{Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, -0.6), Vec3(0, 0, 0.2)};
  EXPECT_TRUE(segmentsCrossDuringStep(spin, ends(spin, turn), &t));
  EXPECT_NEAR(t, 0.5, 1e-12);
  EXPECT_TRUE(segmentCollision(spin, turn, 1e-6).has_value());
}

// Random free strands in a small box thrown at each other: every impulse is an equal and
// opposite pair, so the total momentum stays; after the stage no segment crosses another over
// the step.
TEST(StrandCollisions, MomentumAndNoCrossing) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> x, v;
  std::vector<double> inv_mass;
  std::vector<int> offsets{0};
  const int strands = 40, segments = 10;
  for (int s = 0; s < strands; ++s) {
    const Vec3 root = 0.004 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 vel = 0.5 * Vec3(u(rng), u(rng), u(rng));
    for (int i = 0; i <= segments; ++i) {
      x.push_back(root + 0.001 * i * dir);
      v.push_back(vel + 0.05 * Vec3(u(rng), u(rng), u(rng)));
      inv_mass.push_back(1.0 / (1e-8 * (1.0 + 0.5 * u(rng))));
    }
    offsets.push_back(static_cast<int>(x.size()));
  }
  const double dt = 1.0 / 240.0, thickness = 8e-5;
  auto crossings = [&](const std::vector<Vec3>& vel) {
    std::vector<Vec3> x1(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) x1[i] = x[i] + dt * vel[i];
    return countSegmentCrossings(x, x1, offsets);
  };
  auto momentum = [&](const std::vector<Vec3>& vel, double* scale) {
    Vec3 p = Vec3::Zero();
    *scale = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      p += vel[i] / inv_mass[i];
      *scale += vel[i].norm() / inv_mass[i];
    }
    return p;
  };
  const SegmentCrossings before = crossings(v);
  double scale = 0.0;
  const Vec3 p0 = momentum(v, &scale);
  StrandCollisions collisions;
  std::vector<Vec3> v_new = v;
  const StrandCollisionStats stats = collisions.apply(x, v_new, inv_mass, offsets, thickness, dt);
  double scale1 = 0.0;
  const Vec3 p1 = momentum(v_new, &scale1);
  const SegmentCrossings after = crossings(v_new);
  const double change = (p1 - p0).norm() / scale;
  std::printf(
      "40 random strands: %zu crossings without the stage, %zu after it; %d candidates, %d "
      "proximity impulses, %d collision impulses in %d passes, %d zone passes (%d vertices); "
      "momentum change %.3e of sum m|v|\n",
      before.count, after.count, stats.candidate_pairs, stats.proximity_impulses,
      stats.collision_impulses, stats.collision_passes, stats.zone_passes, stats.zone_vertices,
      change);
  EXPECT_GT(before.count, 0u);
  EXPECT_EQ(after.count, 0u);
  EXPECT_TRUE(stats.resolved);
  EXPECT_LT(change, 1e-12);
  // Clamped (infinite-mass) roots, at rest: they do not move, and nothing crosses.
  std::vector<double> held = inv_mass;
  std::vector<Vec3> v_held = v;
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    for (int i = offsets[k]; i < offsets[k] + 2; ++i) {
      held[i] = 0.0;
      v_held[i].setZero();
    }
  v_new = v_held;
  const StrandCollisionStats held_stats = collisions.apply(x, v_new, held, offsets, thickness, dt);
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    for (int i = offsets[k]; i < offsets[k] + 2; ++i) EXPECT_EQ(v_new[i], Vec3::Zero());
  std::printf("same with clamped roots: %zu crossings without, %zu after (%d zone vertices)\n",
              crossings(v_held).count, crossings(v_new).count, held_stats.zone_vertices);
  EXPECT_EQ(crossings(v_new).count, 0u);
  EXPECT_TRUE(held_stats.resolved);
}

// Han's Fig. 4.7, scaled down: a bundle of free strands along y falls from 8 mm onto a bundle
// of strands along x clamped at one end, both 4 x 4 strands 1 mm apart, 4 cm of human hair in
// 16 segments, 0.3 s at 1/240 s. The crossings (segments passing through each other over a
// step) are counted with the audit, with the impulses and without.
struct BundleRun {
  std::size_t crossings = 0;
  double upper_height = 0.0;  // mean height of the falling bundle at the end [m]
  double lower_height = 0.0;  // of the clamped bundle under it
  double seconds = 0.0, seconds_collisions = 0.0;  // the steps', of which the collisions
  int max_zone_vertices = 0, zone_steps = 0, passes = 0;
  bool resolved = true;
};

// bulk: the strands' continuum on the grid (Han 4.3-4.6), with xi 0.95 across strands in
// contact (its default) or, with han, xi = 0.95 everywhere.
BundleRun fallingBundles(bool collide, bool jacobi = false, bool bulk = false, bool han = false) {
  WorldSettings ws;
  ws.grid_spacing = 0.01;
  World world(ws);
  HairSettings hs;
  hs.grid_spacing = 0.01;
  hs.strand_collisions.enabled = collide;
  hs.strand_collisions.jacobi = jacobi;
  hs.continuum.enabled = bulk;
  if (han) hs.pic_blend = 0.95;

  auto hair = std::make_shared<HairDynamics>(hs);
  world.add("hair", hair);
  const int n = 4, segments = 16;
  const double gap = 1e-3, length = 0.04;
  std::vector<int> upper;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double p = (a - 0.5 * (n - 1)) * gap, q = (b - 0.5 * (n - 1)) * gap;
      hair->addStrand(straightStrand(Vec3(-0.5 * length, p, q), Vec3::UnitX(), length, segments),
                      humanHair(), true);
      upper.push_back(hair->addStrand(
          straightStrand(Vec3(0.25 * length + p, -0.5 * length, 0.008 + q + 0.5 * gap),
                         Vec3::UnitY(), length, segments),
          humanHair(), false));
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
  BundleRun run;
  const double dt = 1.0 / 240.0;
  std::vector<Vec3> x0 = positions();
  for (int step = 0; step < 72; ++step) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(dt);
    run.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.seconds_collisions += hair->lastStrandCollisions().seconds;
    const std::vector<Vec3> x1 = positions();
    run.crossings += countSegmentCrossings(x0, x1, offsets).count;
    run.zone_steps += hair->lastStrandCollisions().zone_passes > 0;
    run.passes += hair->lastStrandCollisions().collision_passes;
    run.max_zone_vertices =
        std::max(run.max_zone_vertices, hair->lastStrandCollisions().zone_vertices);
    run.resolved = run.resolved && hair->lastStrandCollisions().resolved;
    x0 = x1;
    EXPECT_TRUE(hair->finite());
  }
  // Heights: the falling bundle's mean, and the clamped bundle's mean under it (within 5 mm
  // in x of the falling bundle's centre).
  Vec3 upper_c = Vec3::Zero();
  int nu = 0;
  for (int s = 1; s < hair->numStrands(); s += 2)
    for (const Vec3& p : hair->strand(s).positions()) {
      upper_c += p;
      ++nu;
    }
  upper_c /= nu;
  double lower_z = 0.0;
  int nl = 0;
  for (int s = 0; s < hair->numStrands(); s += 2)
    for (const Vec3& p : hair->strand(s).positions())
      if (std::abs(p.x() - upper_c.x()) < 0.005) {
        lower_z += p.z();
        ++nl;
      }
  run.upper_height = upper_c.z();
  run.lower_height = nl ? lower_z / nl : 0.0;
  return run;
}

TEST(StrandCollisions, FallingBundlesNoMissedCrossings) {
  const BundleRun without = fallingBundles(false);
  const BundleRun with = fallingBundles(true);
  const BundleRun jacobi = fallingBundles(true, true);
  const BundleRun bulk = fallingBundles(false, false, true);
  const BundleRun both = fallingBundles(true, false, true);
  const BundleRun han = fallingBundles(false, false, true, true);
  const BundleRun han_both = fallingBundles(true, false, true, true);
  std::printf(
      "falling bundles (2 x 16 strands of 16 segments, 72 steps of 1/240 s): missed crossings "
      "%zu without the impulses, %zu with (Han: 543 K for McAdams et al., 120 for his); falling "
      "bundle's mean height %.2f mm without, %.2f mm with (clamped bundle under it %.2f / %.2f "
      "mm); "
      "%d collision passes, impact zones in %d steps, up to %d vertices; steps %.2f s / %.2f s of "
      "wall time, collision stage %.2f "
      "s\n",
      without.crossings, with.crossings, 1e3 * without.upper_height, 1e3 * with.upper_height,
      1e3 * without.lower_height, 1e3 * with.lower_height, with.passes, with.zone_steps,
      with.max_zone_vertices, without.seconds, with.seconds, with.seconds_collisions);
  std::printf(
      "same with Jacobi passes (Bridson's averaging): %zu crossings, %d collision passes, impact "
      "zones in %d steps, collision stage %.2f s\n",
      jacobi.crossings, jacobi.passes, jacobi.zone_steps, jacobi.seconds_collisions);
  std::printf(
      "with the strands' continuum (Han 4.3-4.6, xi = 0.95 in contact): %zu crossings without the "
      "impulses, %zu with; falling bundle's mean height %.2f / %.2f mm (clamped one %.2f / %.2f "
      "mm); steps %.2f / %.2f s; with the impulses %d collision passes, impact zones in %d "
      "steps, collision stage %.2f s\n",
      bulk.crossings, both.crossings, 1e3 * bulk.upper_height, 1e3 * both.upper_height,
      1e3 * bulk.lower_height, 1e3 * both.lower_height, bulk.seconds, both.seconds, both.passes,
      both.zone_steps, both.seconds_collisions);
  std::printf(
      "same with xi = 0.95 everywhere (Han): %zu crossings without the impulses, %zu with; "
      "falling bundle's mean height %.2f / %.2f mm (clamped one %.2f / %.2f mm); steps %.2f / "
      "%.2f s; with the impulses %d collision passes, impact zones in %d steps, collision stage "
      "%.2f s\n",
      han.crossings, han_both.crossings, 1e3 * han.upper_height, 1e3 * han_both.upper_height,
      1e3 * han.lower_height, 1e3 * han_both.lower_height, han.seconds, han_both.seconds,
      han_both.passes, han_both.zone_steps, han_both.seconds_collisions);
  EXPECT_EQ(jacobi.crossings, 0u);
  // Bundles 3 mm thick on a 1 cm grid: the continuum with its contact blend does not resolve
  // them (the falling bundle passes); with Han's blend everywhere it catches it by itself and
  // leaves the impulses almost nothing to do. With the impulses none cross either way.
  EXPECT_LT(han.crossings, without.crossings / 3);
  EXPECT_GT(han.upper_height, han.lower_height - 0.01);
  EXPECT_EQ(both.crossings, 0u);
  EXPECT_EQ(han_both.crossings, 0u);
  EXPECT_TRUE(both.resolved);
  EXPECT_TRUE(han_both.resolved);
  EXPECT_GT(without.crossings, 100u);
  EXPECT_EQ(with.crossings, 0u);
  EXPECT_TRUE(with.resolved);
  // Without the impulses the falling bundle passes through the clamped one and falls on; with
  // them it is caught on it (draped over it, its mean within a centimetre of the other's).
  EXPECT_LT(without.upper_height, without.lower_height - 0.1);
  EXPECT_GT(with.upper_height, with.lower_height - 0.01);
}

// Two free strands twisted round each other (a double helix, two turns over 3 cm, centrelines
// 120 um apart, no gravity) and pulled apart sideways by opposite uniform forces (5 m/s^2):
// without the impulses they pass through each other, with them they must untwist. 60 steps of
// 1/240 s.
std::size_t twistedPair(bool collide, double* separation) {
  HairSettings hs;
  hs.grid_spacing = 0.01;
  hs.gravity.setZero();
  hs.strand_collisions.enabled = collide;
  WorldSettings ws;
  ws.grid_spacing = 0.01;
  World world(ws);
  auto hair = std::make_shared<HairDynamics>(hs);
  world.add("hair", hair);
  const double r = 6e-5, length = 0.03;
  const int segments = 30;
  for (int k = 0; k < 2; ++k) {
    std::vector<Vec3> x;
    for (int i = 0; i <= segments; ++i) {
      const double z = length * i / segments, phi = 4.0 * M_PI * z / length + k * M_PI;
      x.push_back(Vec3(r * std::cos(phi), r * std::sin(phi), z));
    }
    const int s = hair->addStrand(x, humanHair(), false);
    hair->setNaturalShape(s, std::vector<Eigen::Vector2d>(segments + 1, Eigen::Vector2d::Zero()),
                          std::vector<double>(segments + 1, 0.0));
    for (int i = 0; i <= segments; ++i)
      hair->setVertexForce(s, i, Vec3(k ? -5.0 : 5.0, 0, 0) * hair->strand(s).vertexMass(i));
  }
  const std::vector<int> offsets{0, segments + 1, 2 * segments + 2};
  auto positions = [&] {
    std::vector<Vec3> x = hair->strand(0).positions();
    x.insert(x.end(), hair->strand(1).positions().begin(), hair->strand(1).positions().end());
    return x;
  };
  std::size_t crossings = 0;
  std::vector<Vec3> x0 = positions();
  for (int step = 0; step < 60; ++step) {
    world.step(1.0 / 240.0);
    const std::vector<Vec3> x1 = positions();
    crossings += countSegmentCrossings(x0, x1, offsets).count;
    x0 = x1;
  }
  Vec3 c[2] = {Vec3::Zero(), Vec3::Zero()};
  for (int k = 0; k < 2; ++k)
    for (const Vec3& p : hair->strand(k).positions()) c[k] += p / (segments + 1);
  *separation = (c[0] - c[1]).x();
  return crossings;
}

TEST(StrandCollisions, TwistedPairPulledApart) {
  double apart_without = 0.0, apart_with = 0.0;
  const std::size_t without = twistedPair(false, &apart_without);
  const std::size_t with = twistedPair(true, &apart_with);
  std::printf(
      "twisted pair pulled apart: missed crossings %zu without the impulses, %zu with; centres "
      "%.2f / %.2f mm apart in x at the end\n",
      without, with, 1e3 * apart_without, 1e3 * apart_with);
  EXPECT_GT(without, 0u);
  EXPECT_EQ(with, 0u);
}

// The broad phase keeps its pairs over calls and searches again only the segments whose boxes
// left their grown ones (or all, when many have): the impulses must be exactly those of a stage
// that searches everything afresh at every step. 40 strands turning about z, a few kicked at
// every step (searched again alone), all of them at every 20th and one thrown hard once
// (searched anew). The strands rise from a 5 x 8 lattice of roots 1.5 mm apart, each tilted at
// random up to 45 degrees, so that neighbours cross over each other's roots.
TEST(StrandCollisions, KeptPairsMatchAFreshSearch) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int strands = 40, segments = 10;
  std::vector<Vec3> x, v;
  std::vector<double> inv_mass(strands * (segments + 1), 1e8);
  std::vector<int> offsets{0};
  for (int row = 0; row < 5; ++row)
    for (int col = 0; col < 8; ++col) {
      const Vec3 root(1.5e-3 * (col - 3.5), 1.5e-3 * (row - 2.0), 0.0);
      const Vec3 rise = Vec3(u(rng), u(rng), 1.0).normalized();
      for (int i = 0; i <= segments; ++i) x.push_back(root + 1e-3 * i * rise);
      offsets.push_back(static_cast<int>(x.size()));
    }
  const double dt = 1.0 / 240.0, thickness = 8e-5, omega = 4.0 * M_PI;
  for (const Vec3& p : x) v.push_back(omega * Vec3(-p.y(), p.x(), 0.0));
  StrandCollisions kept;
  int full = 0, partial = 0, differing = 0, candidates = 0;
  for (int step = 0; step < 60; ++step) {
    std::uniform_int_distribution<int> pick(0, strands - 1);
    for (int kick = 0; kick < (step % 20 == 0 ? strands : 3); ++kick) {
      const int s = step % 20 == 0 ? kick : pick(rng);
      const Vec3 dv = 0.2 * Vec3(u(rng), u(rng), u(rng));
      for (int i = offsets[s]; i < offsets[s + 1]; ++i) v[i] += dv;
    }
    // Once, one strand thrown at 20 m/s: its box spans far more cells than the kept grid's.
    if (step == 30)
      for (int i = offsets[7]; i < offsets[8]; ++i) v[i] += Vec3(20.0, 0.0, 0.0);
    std::vector<Vec3> v_kept = v, v_fresh = v;
    const StrandCollisionStats a = kept.apply(x, v_kept, inv_mass, offsets, thickness, dt);
    const StrandCollisionStats b =
        StrandCollisions().apply(x, v_fresh, inv_mass, offsets, thickness, dt);
    full += a.full_searches;
    partial += a.partial_searches;
    candidates += a.candidate_pairs;
    EXPECT_EQ(a.candidate_pairs, b.candidate_pairs) << "step " << step;
    EXPECT_EQ(a.collision_impulses, b.collision_impulses) << "step " << step;
    for (std::size_t i = 0; i < v.size(); ++i) differing += v_kept[i] != v_fresh[i];
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += dt * v_kept[i];
    v = v_kept;
  }
  std::printf(
      "kept broad phase over 60 steps: %d full and %d partial searches, %d candidate pairs; %d "
      "velocities differ from a fresh search's\n",
      full, partial, candidates, differing);
  EXPECT_GE(full, 3);
  EXPECT_GE(partial, 30);
  EXPECT_GT(candidates, 0);
  EXPECT_EQ(differing, 0);
}

TEST(StrandCollisions, BadInput) {
  StrandCollisionSettings s;
  s.friction = -1.0;
  EXPECT_THROW(StrandCollisions{s}, InputError);
  s = {};
  s.collision_margin = 0.0;
  EXPECT_THROW(StrandCollisions{s}, InputError);
  HairSettings hs;
  hs.strand_collisions.max_iterations = -1;
  EXPECT_THROW(HairDynamics{hs}, InputError);
  StrandCollisions c;
  std::vector<Vec3> x(4, Vec3::Zero()), v(3, Vec3::Zero());
  std::vector<double> w(4, 1.0);
  EXPECT_THROW(c.apply(x, v, w, {0, 4}, 1e-4, 0.01), InputError);
  v.resize(4);
  EXPECT_THROW(c.apply(x, v, w, {0, 3}, 1e-4, 0.01), InputError);
  EXPECT_THROW(c.apply(x, v, w, {0, 4}, 0.0, 0.01), InputError);
  EXPECT_THROW(countSegmentCrossings(x, v, {0, 5}), InputError);
  x[1].x() = NAN;
  EXPECT_THROW(countSegmentCrossings(x, v, {0, 4}), InputError);
}

}  // namespace
}  // namespace chs::rod
