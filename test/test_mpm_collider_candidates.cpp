// The colliders a point may be near (mpm/collider_candidates.h): a point's nearest collider
// within reach, found among its cell's candidates, is the one a search of every collider finds,
// for still, sliding and turning colliders, and from several threads at once; the grid's
// obstacle conditions, which ask the lists of blocks of nodes, act as a search of all of them,
// and so does a strand's obstacle contact, which asks a vertex's list.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "cloth_hair_sim/core/collision/penetration_depth.h"
#include "cloth_hair_sim/core/contact/capsule_surface.h"
#include "cloth_hair_sim/core/contact/posed_surface.h"
#include "cloth_hair_sim/core/mpm/collider_candidates.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"
#include "cloth_hair_sim/core/rod/obstacle_contact.h"

namespace chs::mpm {
namespace {

using Vec3 = Eigen::Vector3d;

struct Nearest {
  int collider = -1;
  double gap = 0.0;
};

// The nearest collider within reach of x at the step's end among `which` (-1: none).
Nearest nearestOf(const std::vector<GridCollider>& colliders, const std::vector<int>& which,
                  const Vec3& x, double dt, double reach) {
  Nearest n;
  for (int k : which) {
    const GridCollider& c = colliders[k];
    const double gap = c.surface->project(x - dt * c.velocity.at(x)).gap;
    if (gap < reach && (n.collider < 0 || gap < n.gap)) n = {k, gap};
  }
  return n;
}

// A limb-like scene: 18 capsules (two of them posed boxes) over a 1 m cube, some sliding and
// turning as the mannequin's limbs do.
std::vector<GridCollider> limbs() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  std::vector<GridCollider> colliders;
  for (int k = 0; k < 16; ++k) {
    GridCollider c;
    const Vec3 a(u(rng), u(rng), u(rng)), b = a + 0.3 * Vec3(s(rng), s(rng), s(rng));
    c.surface = std::make_shared<CapsuleSurface>(a, b, 0.02 + 0.05 * u(rng));
    if (k % 3 == 0) c.velocity.linear = Vec3(s(rng), s(rng), s(rng));
    if (k % 4 == 0) {
      c.velocity.angular = 6.0 * Vec3(s(rng), s(rng), s(rng));
      c.velocity.origin = a;
    }
    colliders.push_back(c);
  }
  for (int k = 0; k < 2; ++k) {
    GridCollider c;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.rotate(Eigen::AngleAxisd(0.7 + k, Vec3(1, 2, 3).normalized()));
    pose.translation() = Vec3(u(rng), u(rng), u(rng));
    c.surface = std::make_shared<PosedSurface>(
        std::make_shared<BoxSurface>(Vec3::Zero(), Vec3(0.1, 0.2, 0.05)), pose);
    c.velocity.angular = Vec3(0.0, 0.0, 3.0);
    c.velocity.origin = pose.translation();
    colliders.push_back(c);
  }
  return colliders;
}

TEST(MpmColliderCandidates, NearestWithinReachAsAFullSearch) {
  const std::vector<GridCollider> colliders = limbs();
  std::vector<int> every;
  for (std::size_t k = 0; k < colliders.size(); ++k) every.push_back(static_cast<int>(k));
  const double dt = 1.0 / 60.0;
  // Points near the surfaces (where it matters) and anywhere in the cube.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 1.2), small(-0.004, 0.004);
  std::vector<Vec3> points;
  for (int i = 0; i < 20000; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  for (std::size_t k = 0; k < colliders.size(); ++k)
    for (int i = 0; i < 2000; ++i) {
      const Vec3 x(u(rng), u(rng), u(rng));
      const GridCollider& c = colliders[k];
      const SurfaceProjection p = c.surface->project(x);
      // On the surface where it will be at the step's end, give or take 4 mm.
      const Vec3 on = x - p.gap * p.normal;
      points.push_back(on + dt * c.velocity.at(on) + Vec3(small(rng), small(rng), small(rng)));
    }
  for (double reach : {1e-3, 5e-3}) {
    for (double cell : {0.01, 0.04, 0.1}) {
      const ColliderCandidates candidates(colliders, dt, reach, cell);
      std::vector<Nearest> fast(points.size());
      std::vector<std::size_t> listed(points.size());
      tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
        const std::vector<int>& near = candidates.near(points[i]);
        listed[i] = near.size();
        fast[i] = nearestOf(colliders, near, points[i], dt, reach);
      });
      int within = 0, wrong = 0;
      double tested = 0.0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Nearest full = nearestOf(colliders, every, points[i], dt, reach);
        within += full.collider >= 0;
        wrong += full.collider != fast[i].collider || full.gap != fast[i].gap;
        tested += static_cast<double>(listed[i]);
      }
      std::printf(
          "[figure] collider candidates, reach %.0f mm, cells %.0f mm: %d of %zu points within "
          "reach of a collider, %d answers differ from the full search; %.2f of %zu colliders "
          "projected per query\n",
          1e3 * reach, 1e3 * cell, within, points.size(), wrong, tested / points.size(),
          colliders.size());
      EXPECT_GT(within, 10000);
      EXPECT_EQ(wrong, 0);
      EXPECT_LT(tested / points.size(), 0.5 * colliders.size());
    }
  }
}

// The deepest penetration asked of the lists with reach 0 (what the node's status and simulate's
// report measure, HybridShellDynamics::deepestPenetration) is the one asking every collider, point
// by point, for points on the colliders' surfaces give or take 4 mm (half of them inside).
TEST(MpmColliderCandidates, DeepestPenetrationAsWithEveryCollider) {
  const std::vector<GridCollider> colliders = limbs();
  RigidSurfaces surfaces;
  for (const GridCollider& c : colliders) surfaces.push_back(c.surface);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.2, 1.2), small(-0.004, 0.004);
  std::vector<Vec3> points;
  for (const GridCollider& c : colliders)
    for (int i = 0; i < 1000; ++i) {
      const Vec3 x(u(rng), u(rng), u(rng));
      const SurfaceProjection p = c.surface->project(x);
      points.push_back(x - p.gap * p.normal + Vec3(small(rng), small(rng), small(rng)));
    }
  const ColliderCandidates inside(colliders, 0.0, 0.0, 0.04);
  const auto listed = [&inside](const Vec3& x) -> const std::vector<int>& {
    return inside.near(x);
  };
  int deep = 0, wrong = 0;
  double tested = 0.0;
  for (const Vec3& x : points) {
    const DeepestPenetration full = deepestPenetration({x}, surfaces);
    const DeepestPenetration fast = deepestPenetration({x}, surfaces, listed);
    deep += full.collider >= 0;
    wrong += full.collider != fast.collider || full.depth != fast.depth;
    tested += static_cast<double>(inside.near(x).size());
  }
  const DeepestPenetration all = deepestPenetration(points, surfaces);
  const DeepestPenetration fast = deepestPenetration(points, surfaces, listed);
  std::printf(
      "[figure] deepest penetration from the lists: %d of %zu points inside a collider, %d "
      "answers differ from asking all; deepest %.3f mm both (%s); %.2f of %zu colliders asked per "
      "point\n",
      deep, points.size(), wrong, 1e3 * fast.depth, all.depth == fast.depth ? "equal" : "DIFFER",
      tested / points.size(), colliders.size());
  EXPECT_GT(deep, 5000);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(all.depth, fast.depth);
  EXPECT_LT(tested / points.size(), 0.5 * colliders.size());
}

// The grid's conditions (applyGridColliders, which asks the lists of blocks of 4^3 nodes) give
// every node the velocity and every collider the impulse that applying all 18 in turn gives.
TEST(MpmColliderCandidates, GridConditionsAsWithEveryCollider) {
  const std::vector<GridCollider> colliders = limbs();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.1, 1.1), s(-1.0, 1.0);
  const double dx = 0.01;
  SparseGrid grid(dx);
  for (int i = 0; i < 40000; ++i) {
    const Vec3 x(u(rng), u(rng), u(rng));
    const int n = grid.activate((x / dx).array().floor().cast<int>().matrix());
    grid.mass[n] = std::max(0.0, s(rng));  // half of them massless: skipped
    grid.velocity[n] = Vec3(s(rng), s(rng), s(rng));
    grid.momentum[n] = grid.mass[n] * grid.velocity[n];
  }
  SparseGrid reference = grid;
  std::vector<ColliderImpulse> expected(colliders.size()), got;
  int inside = 0;
  for (int i = 0; i < reference.size(); ++i) {
    if (reference.mass[i] <= 0.0) continue;
    const Vec3 x = reference.position(i);
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      const GridCollider& c = colliders[k];
      const SurfaceProjection p = c.surface->project(x);
      if (p.gap > 0.0) continue;
      ++inside;
      const Vec3 vc = c.velocity.at(x), before = reference.momentum[i];
      reference.velocity[i] = vc + collideRelativeVelocity(reference.velocity[i] - vc, p.normal,
                                                           c.boundary, c.friction);
      reference.momentum[i] = reference.mass[i] * reference.velocity[i];
      expected[k].add(x, reference.momentum[i] - before);
    }
  }
  applyGridColliders(grid, colliders, &got);
  int differ = 0;
  for (int i = 0; i < grid.size(); ++i)
    differ +=
        grid.velocity[i] != reference.velocity[i] || grid.momentum[i] != reference.momentum[i];
  for (std::size_t k = 0; k < colliders.size(); ++k)
    differ += got[k].linear != expected[k].linear || got[k].angular != expected[k].angular;
  std::printf(
      "[figure] grid conditions with the lists: %d of %d nodes inside a collider, %d "
      "velocities or impulses differ from applying every collider\n",
      inside, grid.size(), differ);
  EXPECT_GT(inside, 300);
  EXPECT_EQ(differ, 0);
}

// A strand's lagged obstacle contacts (rod/obstacle_contact.h) from the lists are those of all
// 18 obstacles, in the same order, with the same gaps and forces.
TEST(MpmColliderCandidates, StrandContactsAsWithEveryObstacle) {
  const std::vector<GridCollider> colliders = limbs();
  std::vector<rod::StrandObstacle> obstacles;
  for (const GridCollider& c : colliders) obstacles.push_back({c.surface, c.velocity, 0.3});
  // Vertices on and near the surfaces, and anywhere in the cube.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 1.1), small(-0.003, 0.003);
  std::vector<Vec3> x;
  for (int i = 0; i < 3000; ++i) x.emplace_back(u(rng), u(rng), u(rng));
  for (const GridCollider& c : colliders)
    for (int i = 0; i < 300; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      const SurfaceProjection q = c.surface->project(p);
      x.push_back(p - q.gap * q.normal + Vec3(small(rng), small(rng), small(rng)));
    }
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4 * static_cast<int>(x.size()) - 1);
  for (std::size_t i = 0; i < x.size(); ++i) q.segment<3>(4 * i) = x[i];
  // beyond covers the reach, the contact distance and the obstacles' motion over the step (the
  // limbs' fastest surface points move 0.03 m in it), so every vertex asks its list.
  const double dt = 1.0 / 600.0, reach = 0.004, beyond = 0.04;
  rod::ObstacleContactSettings settings;
  rod::ObstacleContact all(obstacles, settings, 4e-5, dt, x),
      listed(obstacles, settings, 4e-5, dt, x);
  const ColliderCandidates near(colliders, 0.0, beyond, 0.04);
  listed.setNearObstacles([&](const Vec3& p) -> const std::vector<int>& { return near.near(p); },
                          beyond);
  all.updateLag(q, reach, {});
  listed.updateLag(q, reach, {});
  // The lists are what the vertices ask: empty ones find no contact.
  rod::ObstacleContact none(obstacles, settings, 4e-5, dt, x);
  const std::vector<int> nothing;
  none.setNearObstacles([&](const Vec3&) -> const std::vector<int>& { return nothing; }, beyond);
  none.updateLag(q, reach, {});
  EXPECT_TRUE(none.empty());
  const auto& a = all.contacts();
  const auto& b = listed.contacts();
  int differ = a.size() == b.size() ? 0 : 1;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k)
    differ += a[k].vertex != b[k].vertex || a[k].obstacle != b[k].obstacle ||
              a[k].gap != b[k].gap || a[k].normal_force != b[k].normal_force;
  std::printf(
      "[figure] strand obstacle contacts with the lists: %zu contacts of %zu vertices, %d "
      "differ from asking all 18 obstacles\n",
      a.size(), x.size(), differ);
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace chs::mpm
