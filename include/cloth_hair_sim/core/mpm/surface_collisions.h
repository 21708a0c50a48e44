#pragma once
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/mpm/grid_collider.h"
#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs::mpm {

// A point's clearance from the colliders: its least signed distance, to which collider, and the
// least distance to any other (+inf with fewer than two colliders).
struct Clearance {
  double gap = 0.0, second_gap = 0.0;
  int collider = -1;
};

struct SurfaceCollisionResult {
  int samples_inside = 0;  // found inside at the first pass
  int iterations = 0;      // Jacobi passes
  double deepest = 0.0;    // [m] depth of the deepest sample left inside (0: none)
};

// Keeps a subdivision shell's limit surface, not only its control net, out of the colliders.
// The grid's conditions and the control points' collision impulses hold the control points out,
// but the Catmull-Clark limit surface lies inside its control net wherever the cloth wraps a
// convex obstacle: a net of spacing h laid on a cylinder of radius R puts the limit points at
// R (1 - cos(h / R)) / 3 inside it (the cubic B-spline's (1, 4, 1) / 6 average), 6 mm for a 4 cm
// net on a 3.8 cm forearm, and Han's grid, a cell or more wide, cannot resolve a limb that thin.
// So, after the transfer back, samples of the limit surface (the displayed tessellation, the
// surface a user sees and the penetration is measured on) that lie inside a collider are pushed
// out along its normal by moving the control points of their stencils: for one sample the least
// move sum |dx_k|^2 that carries the sample by d, dx_k = w_k d / sum_j w_j^2, at most d / max w
// (weighted by the points' masses instead, a light boundary point of small weight would take
// d / w_k); where stencils overlap the requests are averaged with weights w_k, and the
// passes repeat (Jacobi) until no sample is deeper than `tolerance`. The tangential part of the
// sample's motion relative to the collider over the step is cut as Coulomb friction allows (a
// position-based friction: at most mu times the normal push). The part of a move that undoes
// the step's own approach and slide changes the points' velocities too (dv = dx / dt), so a
// resting sample ends at rest on the surface; depth a sample had at the step's start is removed
// by position alone, without a kick. Samples whose stencil weight lies mostly on prescribed
// points (pins) are left to them. No library keeps a subdivision surface's samples out of
// signed-distance obstacles through its control points, hence this code.
class SurfaceCollisions {
 public:
  explicit SurfaceCollisions(const std::vector<SurfaceStencil>& samples);

  int size() const { return static_cast<int>(heaviest_.size()); }
  // Whether the last apply moved control point k.
  bool moved(int k) const {
    return k < static_cast<int>(shift_.size()) && shift_[k] != Eigen::Vector3d::Zero();
  }

  // x, v: control positions and velocities at the end of the step, moved in place; x_start:
  // positions at its start; mass: per point; movable: per point, false for points whose motion
  // is prescribed (pins, clamps, held axes). clearance: per point, of the colliders at x (a
  // sample lies outside a collider when a stencil point's clearance beats its distance to the
  // sample: a signed distance changes no faster than the point moves). impulses: per collider,
  // the momentum each gives the points is added.
  SurfaceCollisionResult apply(std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& v,
                               const std::vector<Eigen::Vector3d>& x_start,
                               const std::vector<double>& mass, const std::vector<char>& movable,
                               const std::vector<Clearance>& clearance,
                               const std::vector<GridCollider>& colliders, double dt,
                               std::vector<ColliderImpulse>& impulses, double tolerance = 1e-6,
                               int max_iterations = 10);

 private:
  struct Term {
    int point;
    double w;
  };
  std::vector<int> begin_{0};
  std::vector<Term> terms_;
  std::vector<int> heaviest_;           // per sample, the point of its largest weight
  std::vector<Eigen::Vector3d> shift_;  // per point, the last apply's move
};

// The clearance of point x from the colliders: from all of them, or from those `only` lists
// when every other one is known to be farther than `beyond` (ColliderCandidates); a gap of
// `beyond` (collider -1) then is a lower bound, which apply() may take as a clearance.
Clearance clearanceOf(const Eigen::Vector3d& x, const std::vector<GridCollider>& colliders,
                      const std::vector<int>* only = nullptr,
                      double beyond = std::numeric_limits<double>::infinity());

}  // namespace chs::mpm
