#include "cloth_hair_sim/core/mpm/approach_speed.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "cloth_hair_sim/core/mpm/collider_candidates.h"

namespace chs::mpm {
namespace {

using Vec3 = Eigen::Vector3d;

// The velocities of one group's particles in one cell, and the particles themselves where their
// pairs may have to count one by one (MotionGroup::one_layer).
struct VelocityBox {
  int group = 0;
  Vec3 lo, hi;
  std::vector<int> members;
};

constexpr int kCellRange = 1 << 20;  // cells per axis each side of the origin

std::int64_t cellKey(const Eigen::Vector3i& c) {
  constexpr std::int64_t kMask = (std::int64_t{1} << 21) - 1;
  return ((c.x() + kCellRange) & kMask) | (((c.y() + kCellRange) & kMask) << 21) |
         (((c.z() + kCellRange) & kMask) << 42);
}

// Far-flung (or non-finite) positions share the outermost cells instead of overflowing.
Eigen::Vector3i cellOf(const Vec3& x, double cell) {
  const Vec3 c = (x / cell).array().floor().max(1.0 - kCellRange).min(kCellRange - 2.0).matrix();
  return c.allFinite() ? Eigen::Vector3i(c.cast<int>()) : Eigen::Vector3i::Zero();
}

double colliderApproach(const MotionGroup& g, const std::vector<GridCollider>& colliders,
                        double support, double longest_step) {
  if (colliders.empty()) return 0.0;
  // A particle asks only the colliders a block of cells lists within the farthest reach below
  // (the fastest particle and the fastest collider point at a particle).
  double fastest = 0.0, fastest_collider = 0.0;
  for (std::size_t p = 0; p < g.x.size(); ++p) {
    fastest = std::max(fastest, g.v[p].norm());
    for (const GridCollider& c : colliders)
      fastest_collider = std::max(fastest_collider, c.velocity.at(g.x[p]).norm());
  }
  const ColliderCandidates near(
      colliders, 0.0, support + longest_step * (fastest + fastest_collider), 4.0 / 3.0 * support);
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, static_cast<int>(g.x.size()), 256), 0.0,
      [&](const tbb::blocked_range<int>& r, double w) {
        for (int p = r.begin(); p != r.end(); ++p)
          for (int k : near.near(g.x[p])) {
            const GridCollider& c = colliders[k];
            const Vec3 vc = c.velocity.at(g.x[p]);
            const double reach = support + longest_step * (g.v[p].norm() + vc.norm());
            if (c.surface->project(g.x[p]).gap < reach) w = std::max(w, (g.v[p] - vc).norm());
          }
        return w;
      },
      [](double a, double b) { return std::max(a, b); });
}

}  // namespace

double approachSpeed(const std::vector<MotionGroup>& groups,
                     const std::vector<GridCollider>& colliders, double support,
                     double longest_step) {
  double w = 0.0, fastest = 0.0;
  bool pairs = groups.size() > 1;
  for (const MotionGroup& g : groups) {
    w = std::max(w, colliderApproach(g, colliders, support, longest_step));
    for (const Vec3& v : g.v) fastest = std::max(fastest, v.norm());
    pairs = pairs || g.self;
  }
  if (!pairs) return w;
  // Two particles that may meet within the longest step are closer than `cell` now, so they lie
  // in the same or neighbouring cells.
  const double cell = support + 2.0 * fastest * longest_step;
  std::unordered_map<std::int64_t, int> index;
  std::vector<Eigen::Vector3i> cells;
  std::vector<std::vector<VelocityBox>> boxes;
  for (int gi = 0; gi < static_cast<int>(groups.size()); ++gi) {
    const MotionGroup& g = groups[gi];
    for (std::size_t p = 0; p < g.x.size(); ++p) {
      const Eigen::Vector3i c = cellOf(g.x[p], cell);
      const auto [it, fresh] = index.emplace(cellKey(c), static_cast<int>(cells.size()));
      if (fresh) {
        cells.push_back(c);
        boxes.emplace_back();
      }
      std::vector<VelocityBox>& here = boxes[it->second];
      auto b = std::find_if(here.begin(), here.end(),
                            [gi](const VelocityBox& vb) { return vb.group == gi; });
      if (b == here.end()) {
        here.push_back({gi, g.v[p], g.v[p], {}});
        b = here.end() - 1;
      } else {
        b->lo = b->lo.cwiseMin(g.v[p]);
        b->hi = b->hi.cwiseMax(g.v[p]);
      }
      if (g.self && g.one_layer) b->members.push_back(static_cast<int>(p));
    }
  }
  // Pairs of one layer-aware group, one by one, those that could raise w and may meet within the
  // longest step: on two layers by their relative speed, on one by their closing in. same_cell:
  // count each pair once.
  const auto layerPairs = [&](const MotionGroup& g, const VelocityBox& a, const VelocityBox& b,
                              bool same_cell, double w) {
    for (std::size_t i = 0; i < a.members.size(); ++i) {
      const int p = a.members[i];
      for (std::size_t j = same_cell ? i + 1 : 0; j < b.members.size(); ++j) {
        const int q = b.members[j];
        const Vec3 du = g.v[p] - g.v[q];
        const double u = du.norm();
        if (u <= w) continue;
        // Closest within the longest step, each moving on at its velocity: one farther apart
        // than the layer test reaches counts only if it closes in.
        const Vec3 r = g.x[p] - g.x[q];
        const double t = std::clamp(-r.dot(du) / (u * u), 0.0, longest_step);
        if ((r + t * du).norm() >= support) continue;
        const double d = r.norm();
        if (!g.one_layer(p, q, d))
          w = u;
        else if (d > 0.0)  // a layer turning or sliding past itself keeps its distances
          w = std::max(w, -r.dot(du) / d);
      }
    }
    return w;
  };
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, static_cast<int>(cells.size()), 16), w,
      [&](const tbb::blocked_range<int>& r, double w_local) {
        for (int ci = r.begin(); ci != r.end(); ++ci)
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const auto it = index.find(cellKey(cells[ci] + Eigen::Vector3i(dx, dy, dz)));
                if (it == index.end()) continue;
                const int cj = it->second;
                for (const VelocityBox& a : boxes[ci])
                  for (const VelocityBox& b : boxes[cj]) {
                    const MotionGroup& g = groups[a.group];
                    if (a.group == b.group && !g.self) continue;
                    const double bound = (a.hi.cwiseMax(b.hi) - a.lo.cwiseMin(b.lo)).norm();
                    if (bound <= w_local) continue;
                    if (a.group != b.group || !g.one_layer)
                      w_local = bound;
                    else if (cj >= ci)  // each pair of cells once
                      w_local = layerPairs(g, a, b, cj == ci, w_local);
                  }
              }
        return w_local;
      },
      [](double a, double b) { return std::max(a, b); });
}

double motionTimeStep(const std::vector<MotionGroup>& groups,
                      const std::vector<GridCollider>& colliders, double support, double travel,
                      double longest_step) {
  const auto step = [&](double reach_step) {
    const double w = approachSpeed(groups, colliders, support, reach_step);
    return w > 0.0 ? std::min(longest_step, travel / w) : longest_step;
  };
  // A step h is safe when everything within reach over h closes by at most `travel` in it. The
  // first bound is safe (what may be met within it is a subset of what may be met within the
  // longest step); a longer one is taken when it passes that test itself.
  const double safe = step(longest_step);
  if (safe >= longest_step) return safe;
  const double longer = step(safe);
  return longer > safe && step(longer) >= longer ? longer : safe;
}

}  // namespace chs::mpm
