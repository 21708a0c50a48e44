#include "cloth_hair_sim/core/fem_shell/fem_shell_solver.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/drape/seam_groups.h"

#include "cloth_hair_sim/core/fem_shell/coarse_start.h"
#include "cloth_hair_sim/core/fem_shell/shell_model.h"
#include "cloth_hair_sim/core/solver/arc_length_solver.h"
#include "cloth_hair_sim/core/solver/energy_newton.h"

namespace chs {

namespace {

// The coarsest mesh a nested start goes down to, in quads (8 x 8 on a rectangle): coarser, a
// drape's folds no longer fit.
constexpr int kMinCoarseQuads = 64;

void perturb(ShellModel& model, const FemShellSettings& settings) {
  if (settings.imperfection <= 0.0) return;
  if (settings.imperfection_shape == FemShellSettings::Imperfection::kWaves)
    model.perturbWaves(settings.imperfection, settings.imperfection_waves);
  else
    model.perturbRandom(settings.imperfection, settings.imperfection_seed);
}

// One static solve of a model, from its current nodes, with the stability of what it finds.
DrapeResult solveModel(const DrapeProblem& problem, ShellModel& model,
                       const FemShellSettings& settings, const ProgressCallback& progress) {
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
  return r;
}

// Sewing (the FEM counterpart of seed 000 section 3.2.1's): each sewn group (SeamGroups) is
// tied, its members sharing their translational unknowns (ShellModel's join_seams), and the
// offsets between them are load-stepped to zero: before step s of N they are scaled about the
// group's mean by (N - s) / (N - s + 1), and the garment is solved to equilibrium with gravity,
// loads and contact with those offsets held. A zero-length constraint applied in N increments
// that leaves the seam line free to move (round a body, say); at step N the seams are closed
// exactly and that equilibrium is the drape.
DrapeResult solveSewn(const DrapeProblem& problem, const FemShellSettings& settings,
                      const ProgressCallback& progress) {
  const SeamGroups seams(problem.mesh.numVertices(), problem.seams);
  ShellModel model(problem, settings.contact_stiffness, settings.edge_contact, true);
  perturb(model, settings);
  std::vector<ShellNode> nodes = model.nodes();
  auto positions = [&] {
    std::vector<Eigen::Vector3d> x;
    for (const auto& n : nodes) x.push_back(n.position);
    return x;
  };
  const double gap0 = seams.maxGap(positions());
  // Held translations (before the ties spread them over the groups): two members held apart
  // along the same axis can never meet.
  std::vector<bool> held(3 * nodes.size(), false);
  for (int v : problem.bc.clamped)
    for (int k = 0; k < 3; ++k) held[3 * v + k] = true;
  for (int v : problem.bc.pinned)
    for (int k = 0; k < 3; ++k) held[3 * v + k] = true;
  for (const auto& f : problem.bc.fixed_components) held[3 * f.vertex + f.axis] = true;
  for (const auto& g : seams.groups())
    for (int k = 0; k < 3; ++k)
      for (int a : g)
        for (int b : g)
          if (a < b && held[3 * a + k] && held[3 * b + k] &&
              std::abs(nodes[a].position[k] - nodes[b].position[k]) > 1e-9 * model.lengthScale())
            throw InputError("seams: vertices " + std::to_string(a) + " and " + std::to_string(b) +
                             " are sewn together but held apart along " + std::string(1, "xyz"[k]) +
                             " by the boundary conditions");
  DrapeResult all;
  const int steps = settings.seam_steps;
  for (int step = 1; step <= steps; ++step) {
    const double t = static_cast<double>(step) / steps;
    const double shrink = static_cast<double>(steps - step) / (steps - step + 1);
    for (const auto& g : seams.groups()) {
      // The members meet at their mean, or, along an axis a member is held on, where it is.
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int v : g) centre += nodes[v].position;
      centre /= static_cast<double>(g.size());
      for (int k = 0; k < 3; ++k)
        for (int v : g)
          if (held[3 * v + k]) centre[k] = nodes[v].position[k];
      for (int v : g) nodes[v].position = centre + shrink * (nodes[v].position - centre);
    }
    model.setNodes(nodes);
    ProgressCallback p;
    if (progress)
      p = [&](const ProgressEvent& e) {
        ProgressEvent f = e;
        f.load_step = step;
        f.load_factor = t;
        f.total_iterations += all.iterations;
        progress(f);
      };
    DrapeResult r = solveModel(problem, model, settings, p);
    for (ProgressEvent e : r.history) {
      e.load_step = step;
      e.load_factor = t;
      e.total_iterations += all.iterations;
      all.history.push_back(e);
    }
    all.iterations += r.iterations;
    r.history = all.history;
    r.iterations = all.iterations;
    r.load_steps = step;
    r.load_factor = t;
    std::ostringstream status;
    // On the way an equilibrium is enough: before the seams close, a garment that does not yet
    // touch what will hold it has neutral modes (a zero eigenvalue the check calls a saddle).
    const bool equilibrium =
        r.converged || (!r.cancelled && r.residual <= 100.0 * settings.tolerance);
    if (step < steps && !equilibrium) {
      status << "sewing step " << step << " of " << steps << " (seam gap " << (1.0 - t) * gap0
             << " m) failed: " << r.status;
      r.status = status.str();
      return r;
    }
    if (step == steps) {
      status << "seams (largest gap " << gap0 << " m) closed in " << steps
             << " steps and tied; drape: " << r.status;
      r.status = status.str();
      return r;
    }
    nodes = model.nodes();
  }
  return all;  // not reached: seam_steps >= 1
}

}  // namespace

DrapeResult solveFemShell(const DrapeProblem& problem, const FemShellSettings& settings,
                          const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  problem.validate();
  problem.checkStaticSupport();
  if (settings.seam_steps < 1) throw InputError("fem_shell.seam_steps must be at least 1");
  DrapeResult r;
  if (problem.seams.empty()) {
    ShellModel model(problem, settings.contact_stiffness, settings.edge_contact);
    std::optional<GridCoarsening> grid;
    std::string no_grid;
    if (settings.coarse_levels > 0) grid = GridCoarsening::of(problem, kMinCoarseQuads, &no_grid);
    DrapeResult coarse;
    if (grid) {
      FemShellSettings below = settings;
      --below.coarse_levels;
      ProgressCallback coarse_progress;
      if (progress)
        coarse_progress = [&progress](const ProgressEvent& e) {
          ProgressEvent c = e;
          ++c.coarser_grids;
          progress(c);
        };
      coarse = solveFemShell(grid->coarse(), below, coarse_progress);
      for (ProgressEvent& e : coarse.history) ++e.coarser_grids;
      if (coarse.cancelled) {
        r.cancelled = true;
        r.status =
            "cancelled while draping the coarser grid to start from; the flat sheet returned";
        for (const auto& n : model.nodes()) {
          r.positions.push_back(n.position);
          r.directors.push_back(n.frame.director());
        }
        r.iterations = r.coarse_iterations = coarse.iterations;
        r.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return r;
      }
      if (coarse.converged)
        model.setNodes(grid->prolong(coarse.positions, coarse.directors, model.nodes(), problem));
    }
    if (!coarse.converged) perturb(model, settings);
    r = solveModel(problem, model, settings, progress);
    if (settings.coarse_levels > 0 && !grid) r.status += "; no nested start: " + no_grid;
    if (grid) {
      std::ostringstream from;
      if (coarse.converged)
        from << "; started from the drape of the coarser mesh of " << grid->coarse().mesh.numQuads()
             << " quads (" << coarse.iterations << " iterations there"
             << (coarse.status.find("started from") != std::string::npos ? ", itself nested" : "")
             << ")";
      else
        from << "; the drape of the coarser mesh of " << grid->coarse().mesh.numQuads()
             << " quads, to start from, failed (" << coarse.status
             << "): solved from the flat sheet";
      r.status += from.str();
      r.iterations += coarse.iterations;
      r.coarse_iterations = coarse.iterations;
      r.history.insert(r.history.begin(), coarse.history.begin(), coarse.history.end());
    }
  } else {
    r = solveSewn(problem, settings, progress);
  }
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace chs
