#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"

#include <chrono>
#include <cmath>

#include "cloth_hair_sim/core/common/input_error.h"

#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/solver/arc_length_solver.h"
#include "cloth_hair_sim/core/solver/energy_newton.h"

namespace chs {

DrapeResult solveFemShell(const DrapeProblem& problem, const FemShellSettings& settings,
                          const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  problem.validate();
  problem.checkStaticSupport();
  ShellModel model(problem, settings.contact_stiffness, settings.edge_contact);
  if (settings.imperfection > 0.0) {
    if (settings.imperfection_shape == FemShellSettings::Imperfection::kWaves)
      model.perturbWaves(settings.imperfection, settings.imperfection_waves);
    else
      model.perturbRandom(settings.imperfection, settings.imperfection_seed);
  }
  const bool has_energy = std::isfinite(model.energy(0.0));
  FemShellMethod method = settings.solver;
  if (method == FemShellMethod::kAuto)
    method = has_energy && !problem.colliders.empty() ? FemShellMethod::kEnergyNewton
                                                      : FemShellMethod::kArcLength;
  if (method == FemShellMethod::kEnergyNewton && !has_energy)
    throw InputError(
        "fem_shell.solver energy_newton needs a potential energy: Kawabata bending and nodal "
        "moments have none (use arc_length)");

  ContinuationResult c;
  StabilityCheck stability;
  bool stability_computed = false;
  if (method == FemShellMethod::kEnergyNewton) {
    EnergyNewtonSettings e;
    e.tolerance = settings.tolerance;
    e.max_iterations = settings.max_iterations;
    e.max_saddle_escapes = settings.max_saddle_escapes;
    e.cancel = settings.cancel;
    EnergyNewtonResult en = solveEnergyNewton(model, e, progress);
    stability = en.stability;
    stability_computed =
        en.stability.computed || (en.residual <= settings.tolerance && !en.cancelled);
    c = en;
  } else {
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
    c = solveArcLength(model, s, progress);
    if (c.converged) {
      Eigen::VectorXd R, F0;
      Eigen::SparseMatrix<double> K;
      model.linearize(1.0, R, F0, &K);
      stability = checkStability(K);
      stability_computed = true;
    }
  }

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
  DrapeStability& st = r.stability;
  if (!stability_computed) {
    st.verdict = "not assessed: not an equilibrium";
  } else if (!stability.computed) {
    st.verdict = "not assessed: the eigenvalue solver failed";
  } else {
    st.assessed = true;
    st.lowest_eigenvalue = stability.lowest_eigenvalue;
    st.negative_eigenvalues = stability.negative_eigenvalues;
    st.stable = stability.stable;
    st.verdict = stability.stable ? "stable" : "unstable (saddle)";
    if (!has_energy) {
      // Without a potential the symmetric part does not decide stability (a non-conservative
      // problem needs a dynamic criterion): the eigenvalue is reported, the verdict is not used.
      st.verdict += "; not decisive: the problem has no potential energy";
    } else if (!stability.stable && r.converged) {
      r.converged = false;
      r.status += "; but the equilibrium is unstable (a saddle: " +
                  std::to_string(stability.negative_eigenvalues) +
                  " negative eigenvalues of the tangent), not a drape";
    }
  }
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace chs
