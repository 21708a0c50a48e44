#pragma once
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/grid_collider.h"

namespace chs::mpm {

// Which of a body's colliders a point may lie within `reach` of, at the step's end, by cells of a
// hash grid: the few a query must project instead of every one. The Lagrangian step's elastic
// solve asks for the nearest collider of each of its obstacle samples at every evaluation of its
// potential; on the demo's mannequin (18 colliders) those projections took a third of the node's
// time, though a sample is within reach of one collider or none.
//
// A collider is queried where it will be at the step's end: a point x is where x - dt v(x) is now
// (as the elastic solve sees it). That map's gap g(x) is Lipschitz with L = 1 + dt |omega| (a
// signed distance changes no faster than the point moves; the rotation adds dt |omega|). So a
// collider whose gap at a cell's centre is at least reach + L r (r: the cell's half-diagonal,
// with a margin of a hundredth for sampled distance fields) is farther than reach from every
// point of the cell, and leaves the cell's list. A cell's list is made on its first query and
// kept for the step, by each thread for itself (a shared map's locks cost more than the few
// cells two threads both make). With two colliders or fewer, or a reach that is not finite,
// every query gets them all (a list would cost what it saves).
class ColliderCandidates {
 public:
  ColliderCandidates(const std::vector<GridCollider>& colliders, double dt, double reach,
                     double cell);

  // The indices of the colliders that may lie within reach of x, ascending.
  const std::vector<int>& near(const Eigen::Vector3d& x) const;
  // How far every collider a list leaves out lies at least: reach, or infinity when every query
  // gets them all.
  double beyond() const { return listing_ ? reach_ : std::numeric_limits<double>::infinity(); }

 private:
  using CellMap = std::unordered_map<std::int64_t, std::vector<int>>;
  const std::vector<GridCollider>& colliders_;
  double dt_, reach_, cell_;
  std::vector<double> lipschitz_;  // per collider
  std::vector<int> all_;           // every collider: for a point whose cell cannot be keyed
  bool listing_ = false;
  mutable tbb::enumerable_thread_specific<CellMap> cells_;
};

}  // namespace chs::mpm
