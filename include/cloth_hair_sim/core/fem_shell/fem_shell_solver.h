#pragma once
#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs {

// Settings of the static FEM shell solve: Newton-Raphson with the adaptive arc-length method of
// seed 000 section 2.2.1 and node-on-surface penalty contact (section 2.2.2).
struct FemShellSettings {
  double tolerance = 1e-8;               // relative residual |R| / |F_ref| at convergence
  int max_iterations_per_step = 30;      // divergence: halve the arc length, restart the step
  int target_iterations = 6;             // N_p of eq. (20)
  double initial_load_increment = 0.05;  // Delta lambda_0 of step 2 in section 2.2.3
  double max_load_increment = 1.0;
  int max_load_steps = 400;
  int max_cutbacks = 20;
  double contact_stiffness = 0.0;  // k_c; 0 picks one from the membrane stiffness
  bool arc_length = true;          // false: plain load control with the same cutbacks
  // Viscous stabilisation of buckling drapes (ArcLengthSettings::stabilization); 0 = off.
  double stabilization = 0.0;
  int max_settling_steps = 200;
  // Amplitude (length) of a seeded random initial displacement along the directors that breaks
  // the symmetry of a perfectly flat sheet; 0 = none.
  double imperfection = 0.0;
  unsigned imperfection_seed = 1;
  // Polled each iteration: once set, the solve returns the last converged load step (while
  // settling, the state of least residual) with DrapeResult::cancelled.
  const CancelFlag* cancel = nullptr;
};

// Solves the static drape; never throws on non-convergence: the result then holds the last
// converged load step, converged = false and a status that says why. Throws InputError for input
// that makes no sense.
DrapeResult solveFemShell(const DrapeProblem& problem, const FemShellSettings& settings,
                          const ProgressCallback& progress = {});

}  // namespace chs
