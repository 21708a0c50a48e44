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

// How the control points' unknowns are tied: each point moves with an owner (itself, or the
// interior neighbour a clamp slaves it to, subdiv/clamped_edges.h) through a constant map
// dx_p / dx_owner. Fixed for the shell's life (it sets the Hessian's sparsity).
struct ControlPointLinks {
  std::vector<int> owner;
  std::vector<Eigen::Matrix3d> map;  // identity for a point that owns itself
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
  // Curvature pairs of L-BFGS kept on top of a kept factorisation (0: plain chord iterations).
  int history = 8;
};

struct ImplicitElasticityResult {
  int iterations = 0;      // Newton iterations (back-substitutions)
  int factorizations = 0;  // Hessian assemblies and numeric factorisations
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
// projected Hessians (kirchhoff_love_hessian.h) plus the mass term, assembled into a sparse SPD
// matrix of fixed pattern and factorised by CHOLMOD's supernodal Cholesky with the symbolic
// analysis done once; a backtracking (Armijo) line search on Phi makes every iteration lower the
// energy, so a step never creates energy however stiff the shell and long dt.
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
  // Forget the factorisation (the material or plastic state changed).
  void invalidate() {
    factored_ = false;
    pair_s_.clear();
    pair_y_.clear();
  }

 private:
  double incrementalPotential(const std::vector<Eigen::Vector3d>& x,
                              const std::vector<Eigen::Vector3d>& x_hat,
                              const std::vector<double>& mass, double dt,
                              const HenckyLamina& material, bool with_gradient);
  void assemble(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& mass, double dt,
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
  std::vector<int> diagonal_block_;  // of each point's owner row
  std::vector<int> value_index_;     // 9 per block: its entries' places in matrix_.valuePtr()
  Eigen::SparseMatrix<double> matrix_;
  struct Factor;
  std::unique_ptr<Factor> factor_;
  bool factored_ = false;
  double factored_dt_ = 0.0;
  std::vector<Eigen::Vector3d> factored_free_;
  // L-BFGS pairs since the factorisation, oldest first: increments of the unknowns and the
  // elastic gradient's change over them (held components zero).
  std::vector<Eigen::VectorXd> pair_s_, pair_y_;
  std::vector<Eigen::Vector3d> gradient_, folded_;
};

}  // namespace chs
