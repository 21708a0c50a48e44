#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"

#include <chrono>

#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/solver/arc_length_solver.h"

namespace chs {

DrapeResult solveFemShell(const DrapeProblem& problem, const FemShellSettings& settings,
                          const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  problem.validate();
  problem.checkStaticSupport();
  ShellModel model(problem, settings.contact_stiffness);

  ArcLengthSettings s;
  s.tolerance = settings.tolerance;
  s.max_iterations_per_step = settings.max_iterations_per_step;
  s.target_iterations = settings.target_iterations;
  s.initial_load_increment = settings.initial_load_increment;
  s.max_load_increment = settings.max_load_increment;
  s.max_load_steps = settings.max_load_steps;
  s.max_cutbacks = settings.max_cutbacks;
  s.arc_length = settings.arc_length;
  s.stabilization = settings.stabilization;
  s.max_settling_steps = settings.max_settling_steps;
  s.cancel = settings.cancel;
  if (settings.imperfection > 0.0) model.perturb(settings.imperfection, settings.imperfection_seed);
  const ContinuationResult c = solveArcLength(model, s, progress);

  DrapeResult r;
  r.converged = c.converged;
  r.cancelled = c.cancelled;
  r.status = c.status;
  if (!c.converged && !c.cancelled) {
    const std::string free_modes = model.unrestrainedRigidModes();
    if (!free_modes.empty())
      r.status += "; the garment has unrestrained rigid-body modes (" + free_modes +
                  "): clamp, pin or fix components, or add a collider, to hold it";
  }
  r.load_steps = c.load_steps;
  r.iterations = c.iterations;
  r.load_factor = c.lambda;
  r.residual = c.residual;
  r.history = c.history;
  for (const auto& n : model.nodes()) {
    r.positions.push_back(n.position);
    r.directors.push_back(n.frame.director());
  }
  r.reactions = model.reactions();
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace chs
