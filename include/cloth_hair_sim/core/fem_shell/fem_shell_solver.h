#pragma once
#include "cloth_hair_sim/core/common/cancel_flag.h"
#include "cloth_hair_sim/core/drape/drape_problem.h"

namespace chs {

// How the static equilibrium is found. kEnergyNewton: minimisation of the potential energy with
// a modified-Hessian Newton method, leaving saddles along their lowest mode
// (core/solver/energy_newton.h); kArcLength: seed 000's path following (with the optional
// pseudo-transient stabilisation). kAuto: energy minimisation for drapes (a collider, a
// potential energy), arc length otherwise (beams under loads, Kawabata bending, moments).
enum class FemShellMethod { kAuto, kEnergyNewton, kArcLength };

// Settings of the static FEM shell solve: Newton-Raphson with the adaptive arc-length method of
// seed 000 section 2.2.1 or energy minimisation, and penalty contact (section 2.2.2) at the
// nodes and where element edges cross a collider's edge.
struct FemShellSettings {
  FemShellMethod solver = FemShellMethod::kAuto;
  int max_iterations = 2000;         // energy minimisation: Newton iterations in all
  int max_saddle_escapes = 20;       // energy minimisation: saddles left along their lowest mode
  bool edge_contact = true;          // contact of element edges between nodes (ShellModel)
  double tolerance = 1e-8;           // relative residual |R| / |F_ref| at convergence
  int max_iterations_per_step = 30;  // divergence: halve the arc length, restart the step
  int target_iterations = 6;         // N_p of eq. (20)
  double initial_load_increment = 0.05;  // Delta lambda_0 of step 2 in section 2.2.3
  double max_load_increment = 1.0;
  int max_load_steps = 400;
  int max_cutbacks = 20;
  double contact_stiffness = 0.0;  // k_c; 0 picks one from the membrane stiffness
  bool arc_length = true;          // false: plain load control with the same cutbacks
  // Viscous stabilisation of buckling drapes (ArcLengthSettings::stabilization); 0 = off.
  double stabilization = 0.0;
  int max_settling_steps = 200;
  // Initial imperfection that breaks the symmetry of a perfectly flat sheet, displacing the
  // free nodes along their directors by up to `imperfection` (a length; 0 = none). Shape
  // kRandom: uniform in [0, a] per node from imperfection_seed (std::mt19937); kWaves:
  // a (1 + cos(n theta)) / 2 (r / r_max)^2 with n = imperfection_waves, theta and r about the
  // mesh centroid: n folds' worth of ripple growing towards the rim.
  double imperfection = 0.0;
  unsigned imperfection_seed = 1;
  enum class Imperfection { kRandom, kWaves } imperfection_shape = Imperfection::kRandom;
  int imperfection_waves = 4;
  // Sewing (DrapeProblem::seams): the tied partners' offsets go to zero in this many steps, each
  // an equilibrium; the last is the drape (solveFemShell).
  int seam_steps = 10;
  // Nested start (fem_shell/coarse_start.h): a 2 x 2 refined quad mesh starts from the drape on
  // every second grid line, itself started so, down this many levels while the coarse mesh
  // resolves the folds (0: from the flat sheet). Faster on fine grids; it may find another of
  // the drape's stable equilibria than the flat sheet's path does.
  int coarse_levels = 0;
  // Polled each iteration: once set, the solve returns the last converged load step (while
  // settling, the state of least residual) with DrapeResult::cancelled.
  const CancelFlag* cancel = nullptr;
};

// Solves the static drape and checks the stability of the equilibrium it finds (result.stability):
// with seams, after sewing them (tied, their offsets stepped to zero; see solveSewn).
// a saddle of a problem with a potential energy is not reported as converged. Never throws on
// non-convergence: the result then holds the last
// converged load step, converged = false and a status that says why. Throws InputError for input
// that makes no sense.
DrapeResult solveFemShell(const DrapeProblem& problem, const FemShellSettings& settings,
                          const ProgressCallback& progress = {});

}  // namespace chs
