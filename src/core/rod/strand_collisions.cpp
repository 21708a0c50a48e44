#include "cloth_hair_sim/core/rod/strand_collisions.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <Eigen/Dense>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/common/rigid_velocity.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

// Cells per axis of the broad phase's grid, so that a cell is one 64-bit key (see search).
constexpr double kCellsPerAxis = double(1 << 21) - 2.0;

std::uint64_t cellKey(int ix, int iy, int iz) {
  return std::uint64_t(ix) << 42 | std::uint64_t(iy) << 21 | std::uint64_t(iz);
}

// A segment's box with the Verlet list's slack: the larger of `slack` and a tenth of the box's
// size. A box spans the segment's sweep over the step, so a moving segment gets room for its
// next steps' drift too. With the thickness alone (80 um), 1000 swinging hairs on the walking
// head searched anew at 1696 of 1757 calls; with a tenth 1116, and the stage took 0.6 of its
// time (a quarter: 681 searches, no faster, since the list to filter grows; a half: 304,
// slower).
Eigen::AlignedBox3d grownBox(const Eigen::AlignedBox3d& tight, double slack) {
  constexpr double kDriftFraction = 0.1;
  const double grown = std::max(slack, kDriftFraction * tight.sizes().maxCoeff());
  Eigen::AlignedBox3d b = tight;
  b.min().array() -= grown;
  b.max().array() += grown;
  return b;
}

struct Closest {
  double s = 0.0, u = 0.0;
  Vec3 d = Vec3::Zero();  // b(u) - a(s)
};

// Closest points of segments (p0, p1) and (q0, q1) (Ericson, Real-Time Collision Detection
// 5.1.9): the distance is right also for parallel and zero-length segments.
Closest closestPoints(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, u = 0.0;
  if (a <= 0.0 && e > 0.0) {
    u = std::clamp(f / e, 0.0, 1.0);
  } else if (a > 0.0) {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      u = (b * s + f) / e;
      if (u < 0.0) {
        u = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (u > 1.0) {
        u = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {s, u, (q0 + u * d2) - (p0 + s * d1)};
}

double det3(const Vec3& a, const Vec3& b, const Vec3& c) {
  return a.dot(b.cross(c));
}

// The signed volume det(x1 - x0, x2 - x0, x3 - x0) of the four points at time t.
double volumeAt(const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& d, double t) {
  const Vec3 p0 = x[0] + t * d[0];
  return det3(x[1] + t * d[1] - p0, x[2] + t * d[2] - p0, x[3] + t * d[3] - p0);
}

// Roots in (0, 1) of a t^2 + b t + c, numerically stable.
void quadraticRoots(double a, double b, double c, std::vector<double>& out) {
  const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
  if (scale == 0.0) return;
  if (std::abs(a) <= 1e-14 * scale) {
    if (b != 0.0) out.push_back(-c / b);
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    out.push_back(q / a);
    if (q != 0.0) out.push_back(c / q);
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](double t) { return !(t > 0.0 && t < 1.0); }),
            out.end());
}

}  // namespace

std::optional<SegmentContact> segmentCollision(const std::array<Vec3, 4>& x,
                                               const std::array<Vec3, 4>& d, double margin) {
  {
    // Apart at the start by more than the margin and any relative move of two ends (which
    // bounds that of any two points of the segments): no contact.
    double reach = 0.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 2; j < 4; ++j) reach = std::max(reach, (d[j] - d[i]).norm());
    if (closestPoints(x[0], x[1], x[2], x[3]).d.norm() > 1.01 * reach + margin) return std::nullopt;
  }
  // V(t) = c0 + c1 t + c2 t^2 + c3 t^3 with e, f, g the edges from x0 and de, df, dg their
  // changes over the step.
  const Vec3 e0 = x[1] - x[0], f0 = x[2] - x[0], g0 = x[3] - x[0];
  const Vec3 de = d[1] - d[0], df = d[2] - d[0], dg = d[3] - d[0];
  const double c1 = det3(de, f0, g0) + det3(e0, df, g0) + det3(e0, f0, dg);
  const double c2 = det3(e0, df, dg) + det3(de, f0, dg) + det3(de, df, g0);
  const double c3 = det3(de, df, dg);
  double reach = 0.0;  // the four points' spread over the step, for the scale of V
  for (int k = 1; k < 4; ++k)
    reach = std::max({reach, (x[k] - x[0]).norm(), (x[k] + d[k] - x[0] - d[0]).norm()});
  const double scale = reach * reach * reach;
  // Candidate times: the step's ends, the cubic's extrema (a tangency is a double root there)
  // and its sign changes between them, refined by bisection on V itself.
  std::vector<double> times;
  const double c0 = det3(e0, f0, g0);
  const double tiny = 1e-12 * scale;
  if (std::abs(c0) <= tiny && std::abs(c1) <= tiny && std::abs(c2) <= tiny &&
      std::abs(c3) <= tiny) {
    // Coplanar throughout: no root to follow; sample the step.
    for (int k = 0; k <= 64; ++k) times.push_back(k / 64.0);
  } else {
    std::vector<double> breaks;
    quadraticRoots(3.0 * c3, 2.0 * c2, c1, breaks);
    breaks.push_back(0.0);
    breaks.push_back(1.0);
    std::sort(breaks.begin(), breaks.end());
    for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
      times.push_back(breaks[k]);
      double lo = breaks[k], hi = breaks[k + 1];
      double vlo = volumeAt(x, d, lo);
      const double vhi = volumeAt(x, d, hi);
      if ((vlo < 0.0) == (vhi < 0.0) && vlo != 0.0 && vhi != 0.0) continue;
      for (int it = 0; it < 60 && hi - lo > 1e-13; ++it) {
        const double mid = 0.5 * (lo + hi), vm = volumeAt(x, d, mid);
        if ((vm < 0.0) == (vlo < 0.0)) {
          lo = mid;
          vlo = vm;
        } else {
          hi = mid;
        }
      }
      times.push_back(lo);
      times.push_back(hi);
    }
    times.push_back(1.0);
    std::sort(times.begin(), times.end());
  }
  // A contact counts when the pair does not end the step clearly on the side of n it started
  // on (n oriented by the start): a crossing flips the side (the contact points' separation
  // along a fixed n is linear in t and vanishes at the root), a pair pushed apart by an impulse
  // ends its gap out and is not found again. Every candidate is tried, so a near approach
  // before a root does not hide the root.
  for (double t : times) {
    std::array<Vec3, 4> y;
    for (int k = 0; k < 4; ++k) y[k] = x[k] + t * d[k];
    const Closest c = closestPoints(y[0], y[1], y[2], y[3]);
    if (c.d.norm() > margin) continue;
    const Vec3 ea = y[1] - y[0], eb = y[3] - y[2];
    auto at = [&](const std::array<Vec3, 4>& z) {
      return Vec3(((1.0 - c.u) * z[2] + c.u * z[3]) - ((1.0 - c.s) * z[0] + c.s * z[1]));
    };
    const Vec3 sep0 = at(x);
    std::array<Vec3, 4> x1;
    for (int k = 0; k < 4; ++k) x1[k] = x[k] + d[k];
    const Vec3 sep1 = at(x1);
    // The normal: along the closest points when apart (an end near the other segment), else
    // across both edges (they meet), else (parallel and meeting) along the start's separation.
    Vec3 n = c.d;
    if (!(c.d.norm() > 1e-3 * margin)) {
      n = ea.cross(eb);
      if (n.norm() <= 1e-6 * ea.norm() * eb.norm()) {
        const double ee = ea.squaredNorm();
        n = ee > 0.0 ? Vec3(sep0 - sep0.dot(ea) / ee * ea) : sep0;
      }
    }
    if (!(n.norm() > 0.0)) n = (ea.squaredNorm() > 0.0 ? ea : Vec3(Vec3::UnitX())).unitOrthogonal();
    n.normalize();
    const double side0 = sep0.dot(n);
    if (side0 < 0.0 || (side0 == 0.0 && sep1.dot(n) < 0.0)) n = -n;
    if (sep1.dot(n) >= margin) continue;
    return SegmentContact{t, c.s, c.u, n, std::abs(side0)};
  }
  return std::nullopt;
}

StrandCollisions::StrandCollisions(const StrandCollisionSettings& s) : settings_(s) {
  if (!std::isfinite(s.thickness)) throw InputError("strand collisions: thickness must be finite");
  if (!(s.friction >= 0.0 && std::isfinite(s.friction)))
    throw InputError("strand collisions: friction must be >= 0 and finite");
  if (!(s.repulsion >= 0.0 && s.repulsion <= 1.0))
    throw InputError("strand collisions: repulsion must lie in [0, 1]");
  if (!(s.collision_margin > 0.0 && s.collision_margin < 0.5))
    throw InputError("strand collisions: collision_margin must lie in (0, 0.5)");
  if (s.max_iterations < 0) throw InputError("strand collisions: max_iterations must be >= 0");
  if (!(s.collision_gap >= 0.0 && s.collision_gap <= 1.0))
    throw InputError("strand collisions: collision_gap must lie in [0, 1]");
}

// Broad phase: each segment's box over its step (x and x + dt v at both ends), grown by
// grow / 2. The pairs come from a cell search over the boxes grown further by a slack (a Verlet
// list, as molecular dynamics keeps its neighbour lists): while every segment's box stays inside
// its slack-grown box of the last search, the pairs whose boxes meet are among that search's,
// and filtering its list gives exactly what a new search would. The proximity and collision
// passes of a step, which change the velocities by a fraction of the thickness per step, then
// share one search; hair at rest keeps it over steps.
void StrandCollisions::candidates(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                  double grow, double dt, double slack, bool changed_only,
                                  StrandCollisionStats& stats) {
  const int n = static_cast<int>(segments_.size());
  // A segment's box changes only with its vertices' velocities: after a pass, only those the
  // pass changed (dirty_) are made again.
  std::vector<Eigen::AlignedBox3d>& boxes = boxes_;
  const bool all = !changed_only || static_cast<int>(boxes.size()) != n || grow != boxes_grow_;
  boxes.resize(n);
  boxes_grow_ = grow;
  remade_.resize(n);
  tbb::parallel_for(0, n, [&](int k) {
    const int i = segments_[k];
    remade_[k] = all || dirty_[i] || dirty_[i + 1];
    if (!remade_[k]) return;
    Eigen::AlignedBox3d& b = boxes[k];
    b.setEmpty();
    for (int j = i; j <= i + 1; ++j) {
      b.extend(x[j]);
      b.extend(x[j] + dt * v[j]);
    }
    b.min().array() -= 0.5 * grow;
    b.max().array() += 0.5 * grow;
  });
  // A few boxes that left theirs (the segments a pass's impulses turned, a strand swung past
  // its slack) are searched again alone; when more than kSearchAgainLimit have since the last
  // full search, all are. 1000 swinging hairs on the walking head: of 1116 calls that found a
  // box outside, 842 found fewer than 100 of the 24 000.
  constexpr int kSearchAgainLimit = 512;
  std::vector<int> left;
  const bool same = searched_segments_ == segments_;
  for (int k = 0; k < n && same; ++k)
    if (remade_[k] && !searched_boxes_[k].contains(boxes[k])) left.push_back(k);
  if (!same || !left.empty()) {
    const bool few =
        same && static_cast<int>(searched_again_.size() + left.size()) <= kSearchAgainLimit;
    if (few && searchAgain(boxes, left, slack)) {
      ++stats.partial_searches;
    } else {
      search(boxes, slack);
      ++stats.full_searches;
    }
  }
  // The kept list filtered in its order (the impulse passes' order, and so their result, is the
  // same as a serial filter's): the tests in parallel, then the copy.
  const std::size_t m = searched_pairs_.size();
  keep_.resize(m);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, m, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const Pair& p = searched_pairs_[i];
          // The flags first: a byte per vertex stays in cache, the boxes of a pair do not.
          keep_[i] =
              (!changed_only || (dirty_[p.a] | dirty_[p.a + 1] | dirty_[p.b] | dirty_[p.b + 1])) &&
              boxes[segment_index_[p.a]].intersects(boxes[segment_index_[p.b]]);
        }
      });
  pairs_.clear();
  for (std::size_t i = 0; i < m; ++i)
    if (keep_[i]) pairs_.push_back(searched_pairs_[i]);
}

// All pairs of segments (not sharing a vertex) whose boxes, grown by the slack, meet: each box
// in every cell of a uniform grid it touches, a pair kept by the cell holding the low corner of
// the two boxes' overlap.
void StrandCollisions::search(const std::vector<Eigen::AlignedBox3d>& tight, double slack) {
  const int n = static_cast<int>(segments_.size());
  std::vector<Eigen::AlignedBox3d>& boxes = searched_boxes_;
  boxes = tight;
  double mean = 0.0, largest = 0.0;
  Eigen::AlignedBox3d all;
  for (Eigen::AlignedBox3d& b : boxes) {
    b = grownBox(b, slack);
    const double e = b.sizes().maxCoeff();
    mean += e / n;
    largest = std::max(largest, e);
    all.extend(b);
  }
  searched_segments_ = segments_;
  segment_index_.assign(segments_.empty() ? 0 : segments_.back() + 1, -1);
  for (int k = 0; k < n; ++k) segment_index_[segments_[k]] = k;
  // Cells of twice the mean box's size: a box lies in 3-4 cells instead of the 8 of cells of
  // its own size, fewer entries to sort for more pairs to test per cell (1000 strands of hair:
  // the stage took 28 ms per frame on one thread with cells of the mean size, 18 with twice,
  // 18 with three times; on two threads 9 with twice, 12 with three times). They are numbered
  // from the corner of all boxes with 21 bits per axis (coarser where the boxes span more than
  // 2^21 cells), so that a cell is one 64-bit key: the sort below compares integers, not tuples
  // (a third of the broad phase's time).
  cell_size_ =
      std::max({2.0 * mean, largest / 16.0, all.sizes().maxCoeff() / kCellsPerAxis, 1e-300});
  grid_corner_ = all.min();
  std::vector<CellEntry>& entries = grid_;
  entries.clear();
  entries.reserve(2 * static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const Eigen::Array3i lo = cellOf(boxes[k].min()), hi = cellOf(boxes[k].max());
    for (int ix = lo.x(); ix <= hi.x(); ++ix)
      for (int iy = lo.y(); iy <= hi.y(); ++iy)
        for (int iz = lo.z(); iz <= hi.z(); ++iz) entries.push_back({cellKey(ix, iy, iz), k});
  }
  tbb::parallel_sort(entries.begin(), entries.end(), [](const CellEntry& a, const CellEntry& b) {
    return a.cell < b.cell || (a.cell == b.cell && a.k < b.k);
  });
  searched_again_.clear();
  is_searched_again_.assign(n, 0);
  std::vector<std::size_t> runs;  // starts of runs of one cell
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (e == 0 || entries[e].cell != entries[e - 1].cell) runs.push_back(e);
  runs.push_back(entries.size());
  tbb::enumerable_thread_specific<std::vector<Pair>> found;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size() - 1),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<Pair>& out = found.local();
                      std::vector<Eigen::AlignedBox3d> local;
                      for (std::size_t r = range.begin(); r != range.end(); ++r) {
                        const std::uint64_t here = entries[runs[r]].cell;
                        // The cell's boxes side by side: its pairs' tests then read them from
                        // the cache instead of from all over the list.
                        const std::size_t first = runs[r], count = runs[r + 1] - first;
                        local.resize(count);
                        for (std::size_t e = 0; e < count; ++e)
                          local[e] = boxes[entries[first + e].k];
                        for (std::size_t p = 0; p < count; ++p)
                          for (std::size_t q = p + 1; q < count; ++q) {
                            if (!local[p].intersects(local[q])) continue;
                            const int kp = entries[first + p].k, kq = entries[first + q].k;
                            const int a = segments_[kp], b = segments_[kq];
                            if (std::abs(a - b) <= 1) continue;  // share a vertex
                            const Eigen::Array3i corner =
                                cellOf(local[p].min().cwiseMax(local[q].min()));
                            if (cellKey(corner.x(), corner.y(), corner.z()) != here) continue;
                            out.push_back({std::min(a, b), std::max(a, b)});
                          }
                      }
                    });
  // In (a, b) order: a counting sort on a (a segment's first vertex), then each run of one a by
  // b (a few pairs each); the comparison sort of the whole list took a third of the search.
  std::vector<int> start(static_cast<std::size_t>(segments_.back()) + 2, 0);
  for (const std::vector<Pair>& f : found)
    for (const Pair& p : f) ++start[p.a + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  searched_pairs_.resize(start.back());
  std::vector<int> next(start.begin(), start.end() - 1);
  for (const std::vector<Pair>& f : found)
    for (const Pair& p : f) searched_pairs_[next[p.a]++] = p;
  tbb::parallel_for(0, static_cast<int>(start.size()) - 1, [&](int a) {
    std::sort(searched_pairs_.begin() + start[a], searched_pairs_.begin() + start[a + 1],
              [](const Pair& p, const Pair& q) { return p.b < q.b; });
  });
}

Eigen::Array3i StrandCollisions::cellOf(const Vec3& p) const {
  const Eigen::Array3d c =
      ((p - grid_corner_) / cell_size_).array().floor().max(0.0).min(kCellsPerAxis);
  return c.cast<int>();
}

// Each box that left is grown anew and tested against the grid's entries in the cells it
// touches (a pair kept, as in search, by the cell of the overlap's low corner; the clamp to the
// grid's range maps space onto cells monotonically, so a box outside it still meets its pairs),
// and directly against the boxes searched again before and now (few: their grid entries are
// stale). The pairs of the boxes that stayed are kept, so the list holds every pair whose
// grown boxes meet, as after a full search.
bool StrandCollisions::searchAgain(const std::vector<Eigen::AlignedBox3d>& tight,
                                   const std::vector<int>& left, double slack) {
  // A box grown far beyond the boxes the grid was sized for (a strand thrown or moved by a
  // jump of its frame) would walk through many of its cells: searched anew instead, on a grid
  // sized for it.
  constexpr double kMostCells = 64.0;
  for (int k : left) {
    const Eigen::AlignedBox3d b = grownBox(tight[k], slack);
    if ((b.sizes() / cell_size_).array().ceil().max(1.0).prod() > kMostCells) return false;
  }
  std::vector<Eigen::AlignedBox3d>& boxes = searched_boxes_;
  std::vector<char> is_left(segments_.size(), 0);
  for (int k : left) {
    boxes[k] = grownBox(tight[k], slack);
    is_left[k] = 1;
  }
  searched_pairs_.erase(std::remove_if(searched_pairs_.begin(), searched_pairs_.end(),
                                       [&](const Pair& p) {
                                         return is_left[segment_index_[p.a]] ||
                                                is_left[segment_index_[p.b]];
                                       }),
                        searched_pairs_.end());
  const auto apart = [&](int kp, int kq) {
    return std::abs(segments_[kp] - segments_[kq]) <= 1 || !boxes[kp].intersects(boxes[kq]);
  };
  const auto pair = [&](int kp, int kq) {
    return Pair{std::min(segments_[kp], segments_[kq]), std::max(segments_[kp], segments_[kq])};
  };
  tbb::enumerable_thread_specific<std::vector<Pair>> found;
  tbb::parallel_for(0, static_cast<int>(left.size()), [&](int i) {
    std::vector<Pair>& out = found.local();
    const int kp = left[i];
    const Eigen::Array3i lo = cellOf(boxes[kp].min()), hi = cellOf(boxes[kp].max());
    for (int ix = lo.x(); ix <= hi.x(); ++ix)
      for (int iy = lo.y(); iy <= hi.y(); ++iy)
        for (int iz = lo.z(); iz <= hi.z(); ++iz) {
          const std::uint64_t here = cellKey(ix, iy, iz);
          auto e = std::lower_bound(grid_.begin(), grid_.end(), here,
                                    [](const CellEntry& a, std::uint64_t c) { return a.cell < c; });
          for (; e != grid_.end() && e->cell == here; ++e) {
            const int kq = e->k;
            if (is_left[kq] || is_searched_again_[kq] || apart(kp, kq)) continue;
            const Eigen::Array3i corner = cellOf(boxes[kp].min().cwiseMax(boxes[kq].min()));
            if (cellKey(corner.x(), corner.y(), corner.z()) == here) out.push_back(pair(kp, kq));
          }
        }
    for (int kq : searched_again_)
      if (!is_left[kq] && !apart(kp, kq)) out.push_back(pair(kp, kq));
    for (std::size_t j = i + 1; j < left.size(); ++j)
      if (!apart(kp, left[j])) out.push_back(pair(kp, left[j]));
  });
  std::vector<Pair> added;
  for (const std::vector<Pair>& f : found) added.insert(added.end(), f.begin(), f.end());
  const auto before = [](const Pair& p, const Pair& q) {
    return p.a < q.a || (p.a == q.a && p.b < q.b);
  };
  std::sort(added.begin(), added.end(), before);
  const std::size_t kept = searched_pairs_.size();
  searched_pairs_.insert(searched_pairs_.end(), added.begin(), added.end());
  std::inplace_merge(searched_pairs_.begin(), searched_pairs_.begin() + kept, searched_pairs_.end(),
                     before);
  for (int k : left)
    if (!is_searched_again_[k]) {
      is_searched_again_[k] = 1;
      searched_again_.push_back(k);
    }
  return true;
}

void StrandCollisions::applyImpulses(const std::vector<Impulse>& impulses, std::vector<Vec3>& v,
                                     const std::vector<double>& inverse_mass) {
  const bool jacobi = settings_.jacobi;
  if (jacobi) {
    std::fill(count_.begin(), count_.end(), 0);
    for (const Impulse& im : impulses)
      for (int k = 0; k < 4; ++k)
        if (im.weight[k] != 0.0 && inverse_mass[im.vertex[k]] > 0.0) ++count_[im.vertex[k]];
  }
  std::vector<std::pair<int, Vec3>> dv;  // Jacobi's changes, applied after all are computed
  for (const Impulse& im : impulses) {
    double k_eff = 0.0;
    int c = 1;
    Vec3 vrel = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      k_eff += im.weight[k] * im.weight[k] * inverse_mass[im.vertex[k]];
      if (jacobi) c = std::max(c, count_[im.vertex[k]]);
      vrel += im.weight[k] * v[im.vertex[k]];
    }
    const double vn = vrel.dot(im.normal);
    const double change = std::max(im.target - vn, im.min_change);
    if (!(k_eff > 0.0) || !(change > 0.0)) continue;
    // Coulomb: the slip reduced by at most mu times the normal change.
    const Vec3 vt = vrel - vn * im.normal;
    const double slip = vt.norm();
    Vec3 dvrel = change * im.normal;
    if (slip > 0.0) dvrel -= std::min(slip, settings_.friction * change) / slip * vt;
    // P on b's side (its weights positive) changes the relative velocity by P k_eff.
    const Vec3 P = dvrel / (k_eff * c);
    for (int k = 0; k < 4; ++k) {
      const int i = im.vertex[k];
      const Vec3 d = (inverse_mass[i] * im.weight[k]) * P;
      if (jacobi)
        dv.emplace_back(i, d);
      else
        v[i] += d;
    }
  }
  for (const auto& [i, change] : dv) v[i] += change;
}

std::vector<StrandCollisions::Impulse> StrandCollisions::collisionImpulses(
    const std::vector<Vec3>& x, const std::vector<Vec3>& v, const std::vector<double>& inverse_mass,
    double thickness, double dt) const {
  const double margin = settings_.collision_margin * thickness;
  tbb::enumerable_thread_specific<std::vector<Impulse>> found;
  tbb::parallel_for(std::size_t(0), pairs_.size(), [&](std::size_t k) {
    const Pair& pr = pairs_[k];
    const std::array<int, 4> id{pr.a, pr.a + 1, pr.b, pr.b + 1};
    std::array<Vec3, 4> x4, d4;
    bool moving = false;
    for (int j = 0; j < 4; ++j) {
      x4[j] = x[id[j]];
      d4[j] = dt * v[id[j]];
      moving = moving || inverse_mass[id[j]] > 0.0;
    }
    // Unchanged since a pass found it apart: still apart.
    if (!moving || !(dirty_[id[0]] || dirty_[id[1]] || dirty_[id[2]] || dirty_[id[3]])) return;
    const std::optional<SegmentContact> hit = segmentCollision(x4, d4, margin);
    if (!hit) return;
    const double s = hit->s, u = hit->u;
    Impulse im;
    im.vertex = id;
    im.weight = {-(1.0 - s), -s, 1.0 - u, u};
    // Inelastic: b's contact point ends the step 2 margins in front of a's along n.
    im.normal = hit->normal;
    const double gap = std::max(2.0 * margin, settings_.collision_gap * thickness);
    im.target = (gap - hit->start_gap) / dt;
    im.min_change = 2.0 * margin / dt;
    found.local().push_back(im);
  });
  std::vector<Impulse> out;
  for (const std::vector<Impulse>& f : found) out.insert(out.end(), f.begin(), f.end());
  std::sort(out.begin(), out.end(), [](const Impulse& p, const Impulse& q) {
    return std::tie(p.vertex[0], p.vertex[2]) < std::tie(q.vertex[0], q.vertex[2]);
  });
  return out;
}

StrandCollisionStats StrandCollisions::apply(const std::vector<Vec3>& x, std::vector<Vec3>& v,
                                             const std::vector<double>& inverse_mass,
                                             const std::vector<int>& offsets, double thickness,
                                             double dt) {
  const auto start = std::chrono::steady_clock::now();
  StrandCollisionStats stats = resolve(x, v, inverse_mass, offsets, thickness, dt);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

StrandCollisionStats StrandCollisions::resolve(const std::vector<Vec3>& x, std::vector<Vec3>& v,
                                               const std::vector<double>& inverse_mass,
                                               const std::vector<int>& offsets, double thickness,
                                               double dt) {
  const int nv = static_cast<int>(x.size());
  if (static_cast<int>(v.size()) != nv || static_cast<int>(inverse_mass.size()) != nv)
    throw InputError("strand collisions: " + std::to_string(nv) + " positions, " +
                     std::to_string(v.size()) + " velocities and " +
                     std::to_string(inverse_mass.size()) + " inverse masses");
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != nv ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    throw InputError("strand collisions: strand offsets must rise from 0 to the vertex count " +
                     std::to_string(nv));
  if (!(thickness > 0.0 && std::isfinite(thickness)))
    throw InputError("strand collisions: thickness must be positive and finite");
  if (!(dt > 0.0 && std::isfinite(dt)))
    throw InputError("strand collisions: time step must be positive and finite");
  for (double w : inverse_mass)
    if (!(w >= 0.0 && std::isfinite(w)))
      throw InputError("strand collisions: inverse masses must be >= 0 and finite");
  StrandCollisionStats stats;
  segments_.clear();
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    for (int i = offsets[k]; i + 1 < offsets[k + 1]; ++i) segments_.push_back(i);
  stats.segments = static_cast<int>(segments_.size());
  strand_of_.resize(nv);
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    std::fill(strand_of_.begin() + offsets[k], strand_of_.begin() + offsets[k + 1],
              static_cast<int>(k));
  if (segments_.empty()) return stats;
  count_.assign(nv, 0);

  // Proximity (Bridson 7.1): pairs closer than the thickness at x^n.
  candidates(x, v, thickness, dt, thickness, false, stats);
  stats.candidate_pairs = static_cast<int>(pairs_.size());
  const double repulsion = settings_.repulsion;
  // The pairs closer than the thickness and their normals depend on x alone: found once, in the
  // order the impulses take, and each pass asks only whether their relative velocity falls short.
  std::vector<Impulse> close;
  {
    tbb::enumerable_thread_specific<std::vector<Impulse>> found;
    tbb::parallel_for(std::size_t(0), pairs_.size(), [&](std::size_t k) {
      const Pair& pr = pairs_[k];
      const std::array<int, 4> id{pr.a, pr.a + 1, pr.b, pr.b + 1};
      if (inverse_mass[id[0]] + inverse_mass[id[1]] + inverse_mass[id[2]] + inverse_mass[id[3]] <=
          0.0)
        return;
      const Closest c = closestPoints(x[id[0]], x[id[1]], x[id[2]], x[id[3]]);
      const double dist = c.d.norm();
      if (dist >= thickness) return;
      Impulse im;
      im.vertex = id;
      im.weight = {-(1.0 - c.s), -c.s, 1.0 - c.u, c.u};
      Vec3 n = c.d / dist;
      if (!(dist > 1e-9 * thickness)) {  // touching: across the edges
        n = (x[id[1]] - x[id[0]]).cross(x[id[3]] - x[id[2]]);
        if (!(n.norm() > 0.0)) return;  // collinear and touching: left to the collision passes
        n.normalize();
      }
      im.normal = n;
      im.target = repulsion * (thickness - dist) / dt;
      found.local().push_back(im);
    });
    for (const std::vector<Impulse>& f : found) close.insert(close.end(), f.begin(), f.end());
    std::sort(close.begin(), close.end(), [](const Impulse& p, const Impulse& q) {
      return std::tie(p.vertex[0], p.vertex[2]) < std::tie(q.vertex[0], q.vertex[2]);
    });
  }
  std::vector<char> short_of_target(close.size());
  for (int pass = 0; pass < settings_.max_iterations; ++pass) {
    tbb::parallel_for(std::size_t(0), close.size(), [&](std::size_t k) {
      const Impulse& im = close[k];
      Vec3 vrel = Vec3::Zero();
      for (int j = 0; j < 4; ++j) vrel += im.weight[j] * v[im.vertex[j]];
      // (A pass's own rounding leaves pairs a hair below their target: not another pass.)
      short_of_target[k] = vrel.dot(im.normal) < im.target - 1e-9 * std::abs(im.target);
    });
    std::vector<Impulse> impulses;
    for (std::size_t k = 0; k < close.size(); ++k)
      if (short_of_target[k]) impulses.push_back(close[k]);
    if (impulses.empty()) break;
    stats.proximity_impulses += static_cast<int>(impulses.size());
    applyImpulses(impulses, v, inverse_mass);
  }

  // Collisions over the step's paths in passes; the broad phase follows the new velocities,
  // and a pass tests only pairs with a vertex the previous one changed.
  const double margin = settings_.collision_margin * thickness;
  dirty_.assign(nv, 1);
  auto mark = [&](const std::vector<Impulse>& impulses) {
    std::fill(dirty_.begin(), dirty_.end(), 0);
    for (const Impulse& im : impulses)
      for (int i : im.vertex) dirty_[i] = 1;
  };
  for (int pass = 0; pass < settings_.max_iterations; ++pass) {
    candidates(x, v, margin, dt, thickness, true, stats);
    std::vector<Impulse> impulses = collisionImpulses(x, v, inverse_mass, thickness, dt);
    if (impulses.empty()) return stats;
    ++stats.collision_passes;
    stats.collision_impulses += static_cast<int>(impulses.size());
    applyImpulses(impulses, v, inverse_mass);
    mark(impulses);
  }

  // Fail-safe: rigid impact zones, merged until no pair collides.
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (;;) {
    candidates(x, v, margin, dt, thickness, true, stats);
    // A pair inside one zone moves affinely and does not cross (it may stay within the margin).
    // One left inside a zone with clamps moving apart is not resolved.
    bool outside = false, stuck = false;
    const std::vector<Impulse> hits = collisionImpulses(x, v, inverse_mass, thickness, dt);
    std::fill(dirty_.begin(), dirty_.end(), 0);
    for (const Impulse& im : hits)  // their zones' velocities change below; still colliding
      for (int i : im.vertex) dirty_[i] = 1;
    for (const Impulse& im : hits) {
      int r = root(im.vertex[0]);
      bool one = true, translating = true;
      for (int k = 1; k < 4; ++k) {
        const int a = root(im.vertex[k]);
        translating = translating && v[im.vertex[k]] == v[im.vertex[0]];
        if (a != r) {
          parent[std::max(a, r)] = std::min(a, r);
          r = std::min(a, r);
          one = false;
        }
      }
      outside = outside || !one;
      if (settings_.whole_strand_zones && !one)
        // The strands of the pair join whole: a zone's rigid motion would otherwise stretch
        // the segments leaving it, which the next implicit step turns into violent velocities.
        for (int k = 0; k < 4; ++k) {
          const int st = strand_of_[im.vertex[k]];
          for (int i = offsets[st]; i < offsets[st + 1]; ++i) {
            const int a = root(i), b = root(r);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
          }
        }
      // Inside a zone with clamps, only a common translation is sure not to cross.
      bool held = false;
      for (int k = 0; k < 4; ++k) held = held || inverse_mass[im.vertex[k]] == 0.0;
      stuck = stuck || (one && held && !translating);
    }
    if (!outside) {
      stats.resolved = !stuck;
      break;
    }
    ++stats.zone_passes;
    std::vector<std::pair<int, int>> members;  // (zone, vertex) for zones of 2 or more
    for (int i = 0; i < nv; ++i) members.emplace_back(root(i), i);
    std::sort(members.begin(), members.end());
    stats.zone_vertices = 0;
    for (std::size_t b = 0; b < members.size();) {
      std::size_t e = b;
      while (e < members.size() && members[e].first == members[b].first) ++e;
      if (e - b > 1) {
        stats.zone_vertices += static_cast<int>(e - b);
        for (std::size_t k = b; k < e; ++k) dirty_[members[k].second] = 1;
        Vec3 held_v = Vec3::Zero();
        int held = 0;
        for (std::size_t k = b; k < e; ++k) {
          const int i = members[k].second;
          if (inverse_mass[i] == 0.0) {
            held_v += v[i];
            ++held;
          }
        }
        if (held > 0) {
          held_v /= held;
          for (std::size_t k = b; k < e; ++k)
            if (inverse_mass[members[k].second] > 0.0) v[members[k].second] = held_v;
        } else {
          const RigidVelocity rigid =
              fitRigidVelocity(static_cast<int>(e - b), [&](int k, double& m, Vec3& xk, Vec3& vk) {
                const int i = members[b + k].second;
                m = 1.0 / inverse_mass[i];
                xk = x[i];
                vk = v[i];
              });
          for (std::size_t k = b; k < e; ++k) {
            const int i = members[k].second;
            v[i] = rigid.at(x[i]);
          }
        }
      }
      b = e;
    }
  }
  return stats;
}

}  // namespace chs::rod
