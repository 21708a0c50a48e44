#pragma once
#include <string>
#include <vector>

#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"
#include "cloth_hair_sim/core/solver/continuation_problem.h"

namespace chs {

struct ArcLengthSettings {
  double tolerance = 1e-8;
  int max_iterations_per_step = 30;
  int target_iterations = 6;
  double initial_load_increment = 0.05;
  double max_load_increment = 1.0;
  int max_load_steps = 400;
  int max_cutbacks = 20;
  bool arc_length = true;
  // Buckling drapes (folds at a table's corners) branch off the symmetric path at bifurcation
  // points that path following steps over. With stabilization > 0 each load step is a strongly
  // damped pseudo-time step: a viscous force -c m (x - x_n) (c = stabilization |g| / l_e per unit
  // mass) lets the cloth leave unstable branches, as Abaqus' *STATIC, STABILIZE does. Load
  // control is used; at lambda = 1 pseudo-transient continuation (one Newton iteration per
  // pseudo-time step, damping relaxed as the residual falls) runs until the residual without
  // any viscous force is below tolerance: only a true equilibrium counts as converged.
  double stabilization = 0.0;
  int max_settling_steps = 200;
  const CancelFlag* cancel = nullptr;  // polled each iteration (FemShellSettings::cancel)
};

struct ContinuationResult {
  bool converged = false;
  bool cancelled = false;
  std::string status;
  double lambda = 0.0;  // load factor of the returned (last converged) state
  int load_steps = 0;
  int iterations = 0;
  int cutbacks = 0;
  double residual = 0.0;
  std::vector<ProgressEvent> history;
};

// Newton-Raphson with the adaptive arc-length method of seed 000 section 2.2.3: Schweizerhof-
// Wriggers constraint (19) scaled by the acceleration factor (20), increments (21)-(26), and on
// divergence the arc length is halved and the load step restarted from the last converged state.
// The last step switches to load control so that lambda lands on 1 exactly. The problem is left
// at the last converged state when the solve fails.
ContinuationResult solveArcLength(ContinuationProblem& problem, const ArcLengthSettings& settings,
                                  const ProgressCallback& progress = {});

}  // namespace chs
