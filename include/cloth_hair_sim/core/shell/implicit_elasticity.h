#pragma once
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth_hair_sim/core/shell/hencky_lamina.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"
#include "cloth_hair_sim/core/shell/kirchhoff_love_point.h"

namespace chs {

class PermutedCholesky;

// How the control points' unknowns are tied: each point moves with an owner (itself, or the
// interior neighbour a clamp slaves it to, subdiv/clamped_edges.h) through a constant map
// dx_p / dx_owner. Fixed for the shell's life (it sets the Hessian's sparsity).
struct ControlPointLinks {
  std::vector<int> owner;
  std::vector<Eigen::Matrix3d> map;  // identity for a point that owns itself
};

// The nearest obstacle to a point: its index (-1: none), the point's signed distance [m] from it,
// its outward unit normal there, its velocity there and its Coulomb coefficient.
struct ObstacleQuery {
  int obstacle = -1;
  double distance = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double friction = 0.0;
};

// Obstacles inside the elastic solve. Without them the elastic stage let a resting cloth fall
// freely for the step and the grid stopped only the part that touched: the rest hung g dt^2 lower
// (2.7 mm at 1/60 s), a strain the next elastic solve had to relax, so every step started far
// from its solution (docs/BENCHMARKS.md, 2026-12-07). Samples: each fibre's mid-surface point
// x_s = sum_k w_k x_k (the surface that rests on the obstacle) and each control point (what the
// grid's obstacle conditions hold out: where the cloth wrinkles, the net dips below its limit
// surface, and those points fell into the obstacle in every elastic stage for the grid to stop).
// Penalty E_s = kappa_s p^2 / 2 on the depth p = offset - d(x_s) > 0 (d: signed distance),
// linear beyond p = offset (a depth the grid left costs a bounded push, not a kick), with
// kappa_s = stiffness m_s / dt^2: m_s is a fibre's share of the shell's mass (point_stiffness and
// its own mass for a control point), so a resting sheet sinks g dt^2 / (stiffness +
// point_stiffness) into the band. Friction: IPC's lagged smoothed Coulomb potential (Li et al.
// 2020, section 5), D_s = mu lambda f0(|u|) with lambda the penalty's normal force at the last
// solve's end (at the step's start for a sample not pressed then), n the normal at the step's
// start, u = (I - n n^T)(x_s - x_s^n - dt v_obstacle) the slip over the step, f0
// quadratic-cubic below eps = friction_velocity dt (a stick that creeps at most that fast),
// linear above. The grid's obstacle conditions act after it, as before. Hessians: kappa_s n n^T
// and IPC's semidefinite friction matrix, spread over the stencil (the surface's curvature term,
// negative semidefinite on convex obstacles, is left out: the matrix stays SPD).
struct ObstaclePenalty {
  // The nearest obstacle to x where each will be at the step's end; only one nearer than
  // `offset` is used, so farther ones may be left out (obstacle -1). Called from several threads
  // at once.
  std::function<ObstacleQuery(const Eigen::Vector3d& x)> nearest;
  const std::vector<Eigen::Vector3d>* start = nullptr;  // control points at the step's start
  double offset = 0.0;                                  // [m]
  double stiffness = 0.0;           // fibres' (dimensionless); 0 switches the obstacles off here
  double point_stiffness = 0.0;     // control points'
  double friction_velocity = 1e-3;  // [m/s]
  // [m] the most a sample that starts inside the band is lifted towards the offset in a step
  // (then a cloth laid on the surface is raised into the band gently, not kicked), counted from
  // the sag its load gave it at the last solve's end (normal force / kappa); at least twice the
  // rest sag, or a resting sheet would creep down.
  double rise = 0.0;
  bool active() const { return nearest && stiffness > 0.0; }
};

// The obstacles' push (normal and friction) on one sample at the returned iterate.
struct ObstaclePush {
  int obstacle = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on the shell [N]; the obstacle takes -force
};

struct ImplicitElasticitySettings {
  // Stop when the mass-weighted RMS of the velocity residual, sqrt(sum |r_i|^2 / m_i / sum m_i)
  // with r = m (v - v~) - dt f, is below this [m/s] (the grid backward Euler's measure).
  double tolerance = 1e-5;
  int max_iterations = 8;
  // Keep the last factorisation, across iterations and steps (chord Newton), while each
  // iteration still cuts the residual to below this fraction; refactorise the Hessian when one
  // does not. A factorisation costs as much as ~20 iterations on a stale one.
  bool reuse_factorization = true;
  double refresh_ratio = 0.5;
  // The same while samples touch obstacles: there the contacts change from iteration to
  // iteration, and a fresh factor cut the residual no faster than the kept one (on the cloth
  // falling onto the sphere, 1.25-2 times per fresh iteration against 1.5-3 per kept one), so
  // the factor is refreshed only when an iteration on it does not lower the residual at all
  // (docs/BENCHMARKS.md, 2026-12-07).
  double contact_refresh_ratio = 1.0;
  // Curvature pairs of L-BFGS kept on top of a kept factorisation (0: plain chord iterations).
  int history = 8;
  ObstaclePenalty obstacles;
};

struct ImplicitElasticityResult {
  int iterations = 0;      // Newton iterations (back-substitutions)
  int factorizations = 0;  // Hessian assemblies and numeric factorisations
  int exact_refusals = 0;  // exact Hessians CHOLMOD refused (each then factorised projected)
  int line_search_cuts = 0;
  int potential_evaluations = 0;  // of Phi with its gradient (the line search's trials)
  double initial_residual = 0.0, residual = 0.0;  // [m/s], as the tolerance
  // Wall time [s] of the fibres' Hessians and their assembly, and of the numeric factorisation.
  double assembly_seconds = 0.0, factorization_seconds = 0.0;
  bool converged = false;
};

// Backward Euler of a Kirchhoff-Love shell in its own Lagrangian unknowns, the control points
// (the elastic stage of Han's split, sections 4.2 and 6.1.1, applied to the shell of chapter 5):
// x^{n+1} minimises the incremental potential
//   Phi(x) = sum_p m_p |x_p - x^_p|^2 / (2 dt^2) + Psi^KL(x),   x^ = x^n + dt v^n + dt^2 g,
// whose stationarity is m (v^{n+1} - v^n) = dt (f(x^{n+1}) + m g). Newton with the fibres'
// Hessians (kirchhoff_love_hessian.h; projected where the sum is indefinite) plus the mass term,
// assembled into a sparse matrix of fixed pattern and factorised by CHOLMOD's supernodal
// Cholesky with the symbolic analysis done once; a backtracking (Armijo) line search on Phi
// makes every iteration lower the energy, so a step never creates energy however stiff the shell
// and long dt.
class ImplicitElasticity {
 public:
  // points: the shell's quadrature points (buildKirchhoffLovePoints, fibres consecutive) over
  // num_points control points. Throws InputError for links of the wrong size or an owner that is
  // not its own owner.
  ImplicitElasticity(const std::vector<KirchhoffLovePoint>& points, int num_points,
                     ControlPointLinks links);
  ~ImplicitElasticity();

  // x: in, the start (owners' held axes at their prescribed values, slaved points placed by
  // `place`); out, the last iterate. free: per point, 1 where an owner's axis is an unknown, 0
  // where it is held (pins, fixed components); slaved points' entries are ignored. place: puts
  // every slaved point where its owner's position puts it.
  ImplicitElasticityResult solve(std::vector<Eigen::Vector3d>& x,
                                 const std::vector<Eigen::Vector3d>& x_hat,
                                 const std::vector<double>& mass, double dt,
                                 const std::vector<Eigen::Vector3d>& free,
                                 const HenckyLamina& material,
                                 const std::function<void(std::vector<Eigen::Vector3d>&)>& place,
                                 const ImplicitElasticitySettings& settings = {});

  // dPsi^KL/dx_p at the returned iterate, per point (not folded): the elastic force is -this.
  const std::vector<Eigen::Vector3d>& elasticGradient() const { return gradient_; }
  // The obstacle penalty's gradient per point (zero without obstacles: the force is -this), and
  // its pushes on the samples in contact (fibres' mid-surface points, control points), at the
  // returned iterate.
  const std::vector<Eigen::Vector3d>& obstacleGradient() const { return obstacle_gradient_; }
  const std::vector<ObstaclePush>& obstaclePushes() const { return pushes_; }
  // Forget the factorisation, the Newton mode and the contacts' normal forces (the material,
  // the plastic state or the positions changed; a saved state restarts from here).
  void invalidate() {
    factored_ = false;
    newton_ = false;
    pair_s_.clear();
    pair_y_.clear();
    normal_force_.clear();
  }

 private:
  // Obstacle sample i (fibres' mid-surface points, then control points): where it is at x, and
  // its penalty stiffness kappa_i.
  Eigen::Vector3d samplePoint(int i, const std::vector<Eigen::Vector3d>& x) const;
  double sampleStiffness(int i, const std::vector<double>& mass, double total_mass,
                         double dt) const;
  // What settings.obstacles takes from the step's start (lagged_).
  void lagContacts(const std::vector<double>& mass, double dt);
  // The obstacles' potential at x: its energy, obstacle_gradient_ and pushes_ (samples in
  // contact), with each sample's Hessian in contact_hessian_.
  double obstaclePenalty(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& mass,
                         double dt);
  double incrementalPotential(const std::vector<Eigen::Vector3d>& x,
                              const std::vector<Eigen::Vector3d>& x_hat,
                              const std::vector<double>& mass, double dt,
                              const HenckyLamina& material, bool with_gradient);
  // The Newton matrix at x, factorised (factored_ false where it is not positive definite): the
  // fibres' exact Hessians, or with `projected` their positive semidefinite forms.
  void assemble(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& mass, double dt,
                const std::vector<Eigen::Vector3d>& free, const HenckyLamina& material,
                bool projected, ImplicitElasticityResult& result);
  // assemble(): the exact Hessian, which the mass term mostly keeps positive definite and with
  // which Newton converges quadratically; the projected one where CHOLMOD refuses it. On the
  // projected one Newton's tail is linear: on the towel at 1/60 s the residual halved per
  // iteration from 7e-4 m/s, where the exact one went from 3e-3 to 9e-6 m/s in one.
  void refresh(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& mass, double dt,
               const std::vector<Eigen::Vector3d>& free, const HenckyLamina& material,
               ImplicitElasticityResult& result);

  const std::vector<KirchhoffLovePoint>& points_;
  int n_;
  ControlPointLinks links_;
  std::vector<FibreRange> fibres_;
  // Block (3 x 3) pattern over owners: row r's blocks are block_col_[block_start_[r] ..].
  std::vector<int> block_start_, block_col_;
  // Per fibre: the block index of each (k, l) pair of its stencil, k-major, from slot_start_[f].
  std::vector<int> slot_start_, slot_;
  // Runs of consecutive fibres over the same stencil points (a face's): fibres groups_[g] to
  // groups_[g + 1] - 1.
  std::vector<int> groups_;
  // 9 per block (r, c <= r): its entries' places in matrix_.valuePtr(), the lower triangle in
  // CHOLMOD's order (-1: a diagonal block's entry left to its mirror).
  std::vector<int> value_index_;
  Eigen::SparseMatrix<double> matrix_;
  std::unique_ptr<PermutedCholesky> factor_;
  struct Workspace;
  std::unique_ptr<Workspace> workspace_;
  bool factored_ = false;
  double factored_dt_ = 0.0;
  bool exact_refused_ = false;  // in this solve: factorise the projected Hessian directly
  // Refactorise at every iteration (Newton) instead of keeping the factor (chord), from an
  // iteration that found the kept factor useless to a solve that converges at once (solve()).
  bool newton_ = false;
  std::vector<Eigen::Vector3d> factored_free_;
  // L-BFGS pairs since the factorisation, oldest first: increments of the unknowns and the
  // elastic gradient's change over them (held components zero).
  std::vector<Eigen::VectorXd> pair_s_, pair_y_;
  std::vector<Eigen::Vector3d> gradient_, folded_;
  // Per fibre: its share of the shell's volume (of the mass). Per sample (fibres, then control
  // points): the push on it (obstacle -1: none) with its Hessian and its normal part, the normal
  // part at the last solve's end, and what the solve takes from the step's start: the penalty's
  // offset for the sample, and its friction.
  std::vector<double> fibre_share_;
  struct LaggedContact {
    double offset = 0.0;
    int obstacle = -1;
    double mu_lambda = 0.0;                // 0: no friction
    Eigen::Vector3d normal, start, slide;  // slide: the obstacle's motion over the step
  };
  std::vector<LaggedContact> lagged_;
  std::vector<double> normal_, normal_force_;
  const ObstaclePenalty* obstacles_ = nullptr;  // during solve()
  std::vector<ObstaclePush> contacts_, pushes_;
  std::vector<Eigen::Matrix3d> contact_hessian_;
  std::vector<Eigen::Vector3d> obstacle_gradient_;
};

}  // namespace chs
