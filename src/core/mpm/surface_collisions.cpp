#include "cloth_hair_sim/core/mpm/surface_collisions.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace chs::mpm {

using Vec3 = Eigen::Vector3d;

namespace {
constexpr double kLeastFreeShare = 0.5;  // of a sample's weight on points free to move
}  // namespace

Clearance clearanceOf(const Vec3& x, const std::vector<GridCollider>& colliders,
                      const std::vector<int>* only, double beyond) {
  Clearance c;
  c.gap = c.second_gap = beyond;
  const auto add = [&](int k) {
    const double gap = colliders[k].surface->project(x).gap;
    if (gap < c.gap) {
      c.second_gap = c.gap;
      c.gap = gap;
      c.collider = k;
    } else if (gap < c.second_gap) {
      c.second_gap = gap;
    }
  };
  if (only) {
    for (int k : *only) add(k);
  } else {
    for (std::size_t k = 0; k < colliders.size(); ++k) add(static_cast<int>(k));
  }
  return c;
}

SurfaceCollisions::SurfaceCollisions(const std::vector<SurfaceStencil>& samples) {
  for (const SurfaceStencil& s : samples) {
    int heaviest = -1;
    double largest = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < s.size(); ++k) {
      if (s.w[k] == 0.0) continue;
      terms_.push_back({s.points[k], s.w[k]});
      if (s.w[k] > largest) {
        largest = s.w[k];
        heaviest = s.points[k];
      }
    }
    begin_.push_back(static_cast<int>(terms_.size()));
    heaviest_.push_back(heaviest);
  }
}

SurfaceCollisionResult SurfaceCollisions::apply(
    std::vector<Vec3>& x, std::vector<Vec3>& v, const std::vector<Vec3>& x_start,
    const std::vector<double>& mass, const std::vector<char>& movable,
    const std::vector<Clearance>& clearance, const std::vector<GridCollider>& colliders, double dt,
    std::vector<ColliderImpulse>& impulses, double tolerance, int max_iterations) {
  SurfaceCollisionResult result;
  const int n = static_cast<int>(x.size());
  shift_.assign(n, Vec3::Zero());
  if (colliders.empty() || size() == 0) return result;
  const auto position = [&](int s, const std::vector<Vec3>& at) {
    Vec3 p = Vec3::Zero();
    for (int t = begin_[s]; t < begin_[s + 1]; ++t) p += terms_[t].w * at[terms_[t].point];
    return p;
  };

  // Broad phase: a sample whose heaviest point is clear of every collider by more than its
  // distance to the sample is outside them all; one clear of all but its nearest by that much
  // can only be inside that one (-1: check all).
  std::vector<int> check(size(), -2);  // -2: skipped
  tbb::parallel_for(0, size(), [&](int s) {
    const int i = heaviest_[s];
    if (i < 0) return;
    const double d = (position(s, x) - x[i]).norm();
    const Clearance& c = clearance[i];
    if (c.gap > d) return;
    check[s] = c.second_gap > d ? c.collider : -1;
  });
  std::vector<int> candidates;
  for (int s = 0; s < size(); ++s)
    if (check[s] != -2) candidates.push_back(s);
  const int nc = static_cast<int>(candidates.size());
  if (nc == 0) return result;
  std::vector<Vec3> start(nc);
  tbb::parallel_for(0, nc, [&](int c) { start[c] = position(candidates[c], x_start); });

  // Per candidate: its depth, its push, the part of the push that undoes the step's approach and
  // slide (that part changes the velocity), and the collider it is in.
  std::vector<double> depth(nc, 0.0);
  std::vector<Vec3> sample_request(nc), sample_velocity_request(nc);
  std::vector<int> request_collider(nc, -1);
  // Per point: the pass's requests summed with their weights, the moves' velocity parts, and the
  // collider of its strongest request, which takes the point's momentum change.
  std::vector<Vec3> request(n, Vec3::Zero()), velocity_request(n, Vec3::Zero()),
      velocity_shift(n, Vec3::Zero());
  std::vector<double> request_weight(n, 0.0), request_strength(n, 0.0);
  std::vector<int> point_collider(n, -1);
  for (int pass = 0;; ++pass) {
    // Each candidate's push: out of its deepest collider, less the friction on its slide.
    tbb::parallel_for(0, nc, [&](int c) {
      const int s = candidates[c];
      const Vec3 xs = position(s, x);
      depth[c] = 0.0;
      request_collider[c] = -1;
      SurfaceProjection deepest;
      const int only = check[s];
      for (int k = (only >= 0 ? only : 0);
           k < (only >= 0 ? only + 1 : static_cast<int>(colliders.size())); ++k) {
        const SurfaceProjection pr = colliders[k].surface->project(xs);
        if (-pr.gap > depth[c]) {
          depth[c] = -pr.gap;
          deepest = pr;
          request_collider[c] = k;
        }
      }
      if (request_collider[c] < 0) return;
      const GridCollider& gc = colliders[request_collider[c]];
      const Vec3& nrm = deepest.normal;
      // The sample's motion over the step relative to the collider's surface: the depth it
      // moved in during the step is undone with its velocity, any depth it started with by
      // position alone (a velocity of depth / dt would throw it out).
      const Vec3 slide = (xs - start[c]) - dt * gc.velocity.at(xs);
      const double approach = std::max(0.0, -slide.dot(nrm));
      const Vec3 tangential = slide - slide.dot(nrm) * nrm;
      const double t_norm = tangential.norm();
      double cut = gc.boundary == ColliderBoundary::kSticky ? t_norm : gc.friction * depth[c];
      cut = std::min(cut, t_norm);
      Vec3& dv = sample_velocity_request[c];
      dv = std::min(depth[c], approach) * nrm;
      if (t_norm > 0.0) dv -= (cut / t_norm) * tangential;
      sample_request[c] = dv + std::max(0.0, depth[c] - approach) * nrm;
    });
    double deepest = 0.0;
    int inside = 0;
    for (int c = 0; c < nc; ++c) {
      deepest = std::max(deepest, depth[c]);
      inside += depth[c] > 0.0;
    }
    if (pass == 0) result.samples_inside = inside;
    result.deepest = deepest;
    if (deepest <= tolerance || pass == max_iterations) break;
    ++result.iterations;

    // The least move of each sample's movable points, averaged where they overlap.
    for (int c = 0; c < nc; ++c) {
      if (depth[c] <= 0.0) continue;
      const int s = candidates[c];
      double measure = 0.0, share = 0.0;
      for (int t = begin_[s]; t < begin_[s + 1]; ++t)
        if (movable[terms_[t].point]) {
          measure += terms_[t].w * terms_[t].w;
          share += terms_[t].w;
        }
      // A sample placed mostly by prescribed points (a pinned patch) goes where they take it:
      // its few free points would have to move many times its depth.
      if (share < kLeastFreeShare) continue;
      for (int t = begin_[s]; t < begin_[s + 1]; ++t) {
        const int k = terms_[t].point;
        if (!movable[k]) continue;
        const double w = std::abs(terms_[t].w);
        const double a = w * terms_[t].w / measure;
        request[k] += a * sample_request[c];
        velocity_request[k] += a * sample_velocity_request[c];
        request_weight[k] += w;
        const double strength = w * sample_request[c].norm();
        if (strength > request_strength[k]) {
          request_strength[k] = strength;
          point_collider[k] = request_collider[c];
        }
      }
    }
    for (int k = 0; k < n; ++k) {
      if (request_weight[k] <= 0.0) continue;
      const Vec3 dx = request[k] / request_weight[k];
      x[k] += dx;
      shift_[k] += dx;
      velocity_shift[k] += velocity_request[k] / request_weight[k];
      request[k].setZero();
      velocity_request[k].setZero();
      request_weight[k] = 0.0;
    }
  }

  // The moves that undid the step's approach and slide become velocity (as position-based
  // dynamics takes v = (x - x_start) / dt), and their momentum the colliders'.
  impulses.resize(colliders.size());
  for (int k = 0; k < n; ++k) {
    if (point_collider[k] < 0) continue;
    const Vec3 dv = velocity_shift[k] / dt;
    v[k] += dv;
    impulses[point_collider[k]].add(x[k], mass[k] * dv);
  }
  return result;
}

}  // namespace chs::mpm
