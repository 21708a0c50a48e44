#pragma once
#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/solver/arc_length_solver.h"
#include "cloth_hair_sim/core/solver/stability.h"

namespace chs {

struct EnergyNewtonSettings {
  double tolerance = 1e-8;  // relative residual |R| / |F_ref|
  int max_iterations = 2000;
  // An equilibrium whose tangent is not positive definite (a saddle: a symmetric sheet that
  // has not chosen its folds) is left along its lowest mode, at most this often.
  int max_saddle_escapes = 20;
  const CancelFlag* cancel = nullptr;
};

struct EnergyNewtonResult : ContinuationResult {
  StabilityCheck stability;  // of the returned state (computed when it is an equilibrium)
  int saddle_escapes = 0;
};

// Minimises the total potential energy at load factor 1 by Newton's method with a modified
// Hessian and a backtracking line search (Nocedal and Wright, Numerical Optimization, 2nd ed.,
// section 3.4): the step solves (K_s + mu diag K_s) d = R, K_s the symmetrised tangent, with mu
// raised until the sparse Cholesky factorisation succeeds, so d is a descent direction and each
// accepted step lowers the energy (Armijo). Where the Hessian is positive definite mu falls to 0
// and the iteration is Newton's, quadratically convergent. An equilibrium that is a saddle
// (checkStability) is left along its lowest eigenvector, the energy decreasing to second order
// there, and the minimisation continues: only a stable equilibrium is returned as converged.
EnergyNewtonResult solveEnergyNewton(ContinuationProblem& problem,
                                     const EnergyNewtonSettings& settings,
                                     const ProgressCallback& progress = {});

}  // namespace chs
