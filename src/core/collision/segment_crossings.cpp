#include "cloth_hair_sim/core/collision/segment_crossings.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

using Real = long double;
using LVec = Eigen::Matrix<Real, 3, 1>;
using Points = std::array<Eigen::Vector3d, 4>;

struct Path {
  std::array<LVec, 4> p0, p1;
  LVec at(int k, Real t) const { return p0[k] + t * (p1[k] - p0[k]); }
  Real volume(Real t) const {
    const LVec a0 = at(0, t);
    return (at(1, t) - a0).dot((at(2, t) - a0).cross(at(3, t) - a0));
  }
};

// (q - p) x (r - p) in the plane of axes (i, j).
Real orient(const LVec& p, const LVec& q, const LVec& r, int i, int j) {
  return (q[i] - p[i]) * (r[j] - p[j]) - (q[j] - p[j]) * (r[i] - p[i]);
}

int sign(Real v, Real tol) {
  return v > tol ? 1 : (v < -tol ? -1 : 0);
}

// Whether the (coplanar) segments a0 a1 and b0 b1 share a point, to `tol` of size `size`.
bool commonPoint(const LVec& a0, const LVec& a1, const LVec& b0, const LVec& b1, Real size) {
  const LVec ea = a1 - a0, eb = b1 - b0;
  const LVec n = ea.cross(eb);
  const Real tol_len = 1e-12L * size;
  if (n.norm() > 1e-9L * ea.norm() * eb.norm()) {
    // Drop the axis the plane's normal is largest along and decide by 2D orientations.
    int drop = 0;
    n.cwiseAbs().maxCoeff(&drop);
    const int i = (drop + 1) % 3, j = (drop + 2) % 3;
    // An orientation is a length times the projected distance; |n_drop| >= |n| / sqrt 3.
    const Real tol = tol_len * size;
    const int o1 = sign(orient(a0, a1, b0, i, j), tol), o2 = sign(orient(a0, a1, b1, i, j), tol);
    const int o3 = sign(orient(b0, b1, a0, i, j), tol), o4 = sign(orient(b0, b1, a1, i, j), tol);
    return o1 * o2 <= 0 && o3 * o4 <= 0;
  }
  // Parallel: on one line and overlapping along it.
  const LVec dir = ea.norm() >= eb.norm() ? ea : eb;
  const Real len = dir.norm();
  if (len <= tol_len) return (a0 - b0).norm() <= tol_len;  // two points
  const LVec u = dir / len;
  auto off = [&](const LVec& p) { return ((p - a0) - (p - a0).dot(u) * u).norm(); };
  if (off(b0) > tol_len || off(b1) > tol_len) return false;
  const Real sa0 = 0, sa1 = ea.dot(u), sb0 = (b0 - a0).dot(u), sb1 = (b1 - a0).dot(u);
  return std::max(std::min(sa0, sa1), std::min(sb0, sb1)) <=
         std::min(std::max(sa0, sa1), std::max(sb0, sb1)) + tol_len;
}

// The segments' distance at the start, each pair of their points moving apart or together by
// at most the largest relative move of two ends (a convex combination of them).
double startDistance(const Points& x0) {
  const Eigen::Vector3d d1 = x0[1] - x0[0], d2 = x0[3] - x0[2], r = x0[0] - x0[2];
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r);
  // Smallest of the four end-to-segment distances and, for a proper interior pair, the lines'.
  auto pointSegment = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q0,
                         const Eigen::Vector3d& q1) {
    const Eigen::Vector3d e = q1 - q0;
    const double ee = e.squaredNorm();
    const double t = ee > 0.0 ? std::clamp((p - q0).dot(e) / ee, 0.0, 1.0) : 0.0;
    return (p - (q0 + t * e)).norm();
  };
  double d = std::min({pointSegment(x0[0], x0[2], x0[3]), pointSegment(x0[1], x0[2], x0[3]),
                       pointSegment(x0[2], x0[0], x0[1]), pointSegment(x0[3], x0[0], x0[1])});
  const double b = d1.dot(d2), denom = a * e - b * b;
  if (denom > 0.0) {
    const double s = (b * f - c * e) / denom, u = (a * f - b * c) / denom;
    if (s > 0.0 && s < 1.0 && u > 0.0 && u < 1.0)
      d = std::min(d, ((x0[0] + s * d1) - (x0[2] + u * d2)).norm());
  }
  return d;
}

}  // namespace

bool segmentsCrossDuringStep(const Points& x0, const Points& x1, double* time, bool* coplanar) {
  if (coplanar) *coplanar = false;
  {
    // Cheap rejection: apart at the start by more than any relative move over the step (with
    // a 1 % and 1e-12 allowance for the rounding of these doubles).
    double reach = 0.0, size = 0.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 2; j < 4; ++j) {
        reach = std::max(reach, ((x1[j] - x0[j]) - (x1[i] - x0[i])).norm());
        size = std::max(size, (x0[j] - x0[i]).norm());
      }
    if (startDistance(x0) > 1.01 * reach + 1e-12 * size) return false;
  }
  Path path;
  for (int k = 0; k < 4; ++k) {
    path.p0[k] = x0[k].cast<Real>();
    path.p1[k] = x1[k].cast<Real>();
  }
  Eigen::AlignedBox<Real, 3> box;
  for (int k = 0; k < 4; ++k) {
    box.extend(path.p0[k]);
    box.extend(path.p1[k]);
  }
  const Real size = box.diagonal().norm();
  if (!(size > 0)) {
    if (time) *time = 0.0;
    return true;  // all at one point
  }
  const Real tol_v = 1e-14L * size * size * size;
  auto crossAt = [&](Real t) {
    return commonPoint(path.at(0, t), path.at(1, t), path.at(2, t), path.at(3, t), size);
  };
  auto report = [&](Real t) {
    if (time) *time = static_cast<double>(t);
    return true;
  };
  // The cubic from its values at t = 0, 1/3, 2/3, 1 (Newton's forward differences in s = 3t).
  const Real y0 = path.volume(0), y1 = path.volume(1.0L / 3), y2 = path.volume(2.0L / 3),
             y3 = path.volume(1);
  if (std::max({std::abs(y0), std::abs(y1), std::abs(y2), std::abs(y3)}) <= tol_v) {
    if (coplanar) *coplanar = true;
    for (int k = 0; k <= 256; ++k)
      if (crossAt(k / 256.0L)) return report(k / 256.0L);
    return false;
  }
  const Real d1 = y1 - y0, d2 = y2 - 2 * y1 + y0, d3 = y3 - 3 * y2 + 3 * y1 - y0;
  const Real c3 = d3 / 6, c2 = d2 / 2 - d3 / 2, c1 = d1 - d2 / 2 + d3 / 3;
  // Extrema: 3 c3 s^2 + 2 c2 s + c1 = 0 for s in (0, 3).
  std::vector<Real> breaks{0, 1};
  const Real qa = 3 * c3, qb = 2 * c2, qc = c1;
  const Real qs = std::max({std::abs(qa), std::abs(qb), std::abs(qc)});
  if (qs > 0) {
    if (std::abs(qa) <= 1e-15L * qs) {
      if (qb != 0) breaks.push_back(-qc / qb / 3);
    } else {
      const Real disc = qb * qb - 4 * qa * qc;
      if (disc >= 0) {
        const Real r = std::sqrt(disc);
        breaks.push_back((-qb + r) / (2 * qa) / 3);
        breaks.push_back((-qb - r) / (2 * qa) / 3);
      }
    }
  }
  breaks.erase(
      std::remove_if(breaks.begin(), breaks.end(), [](Real t) { return !(t >= 0 && t <= 1); }),
      breaks.end());
  std::sort(breaks.begin(), breaks.end());
  std::vector<Real> roots;
  for (Real t : breaks)
    if (std::abs(path.volume(t)) <= tol_v) roots.push_back(t);  // touching zero: a double root
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    Real lo = breaks[k], hi = breaks[k + 1];
    Real vlo = path.volume(lo);
    const Real vhi = path.volume(hi);
    if ((vlo > 0) == (vhi > 0) || vlo == 0 || vhi == 0) continue;  // no strict sign change
    for (int it = 0; it < 80; ++it) {
      const Real mid = (lo + hi) / 2, vm = path.volume(mid);
      if ((vm > 0) == (vlo > 0)) {
        lo = mid;
        vlo = vm;
      } else {
        hi = mid;
      }
    }
    roots.push_back((lo + hi) / 2);
  }
  std::sort(roots.begin(), roots.end());
  for (Real t : roots)
    if (crossAt(t)) return report(t);
  return false;
}

SegmentCrossings countSegmentCrossings(const std::vector<Eigen::Vector3d>& x0,
                                       const std::vector<Eigen::Vector3d>& x1,
                                       const std::vector<int>& offsets,
                                       std::size_t max_reported_pairs) {
  const int nv = static_cast<int>(x0.size());
  if (static_cast<int>(x1.size()) != nv)
    throw InputError("segment crossings: " + std::to_string(nv) + " start and " +
                     std::to_string(x1.size()) + " end positions");
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != nv ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    throw InputError("segment crossings: strand offsets must rise from 0 to the vertex count " +
                     std::to_string(nv));
  for (int i = 0; i < nv; ++i)
    if (!x0[i].allFinite() || !x1[i].allFinite())
      throw InputError("segment crossings: vertex " + std::to_string(i) + " is not finite");
  std::vector<int> seg;
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    for (int i = offsets[k]; i + 1 < offsets[k + 1]; ++i) seg.push_back(i);
  const int n = static_cast<int>(seg.size());
  SegmentCrossings out;
  if (n < 2) return out;
  std::vector<Eigen::AlignedBox3d> box(n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), mean2 = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const int i = seg[k];
    for (int j = i; j <= i + 1; ++j) {
      box[k].extend(x0[j]);
      box[k].extend(x1[j]);
    }
    // Grown by a hair of its size: the test itself tolerates 1e-12 of it.
    const double grow = 1e-9 * box[k].diagonal().norm() + 1e-300;
    box[k].min().array() -= grow;
    box[k].max().array() += grow;
    const Eigen::Vector3d c = box[k].center();
    mean += c / n;
    mean2 += c.cwiseProduct(c) / n;
  }
  int axis = 0;
  (mean2 - mean.cwiseProduct(mean)).maxCoeff(&axis);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return box[a].min()[axis] < box[b].min()[axis]; });
  struct Local {
    std::size_t candidates = 0, coplanar = 0;
    std::vector<std::array<int, 2>> pairs;
  };
  tbb::enumerable_thread_specific<Local> local;
  tbb::parallel_for(0, n, [&](int r) {
    Local& l = local.local();
    const int p = order[r];
    for (int q2 = r + 1; q2 < n && box[order[q2]].min()[axis] <= box[p].max()[axis]; ++q2) {
      const int q = order[q2];
      const int a = std::min(seg[p], seg[q]), b = std::max(seg[p], seg[q]);
      if (b - a <= 1 || !box[p].intersects(box[q])) continue;
      ++l.candidates;
      const Points s0{x0[a], x0[a + 1], x0[b], x0[b + 1]};
      const Points s1{x1[a], x1[a + 1], x1[b], x1[b + 1]};
      bool flat = false;
      if (segmentsCrossDuringStep(s0, s1, nullptr, &flat)) l.pairs.push_back({a, b});
      if (flat) ++l.coplanar;
    }
  });
  for (const Local& l : local) {
    out.candidate_pairs += l.candidates;
    out.coplanar_pairs += l.coplanar;
    out.count += l.pairs.size();
    out.pairs.insert(out.pairs.end(), l.pairs.begin(), l.pairs.end());
  }
  std::sort(out.pairs.begin(), out.pairs.end());
  if (out.pairs.size() > max_reported_pairs) out.pairs.resize(max_reported_pairs);
  return out;
}

}  // namespace chs
