#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"

#include <chrono>
#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/UmfPackSupport>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"

namespace chs {

namespace {

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

struct Run {
  bool converged = false, cancelled = false;
  std::string status;
  int iterations = 0;
  double residual = 0.0;
  std::vector<ProgressEvent> history;
};

void report(Run& run, const SolidShellModel& model, int it, double residual, bool force_record,
            const SolidShellSettings& s, const ProgressCallback& progress) {
  if (!force_record && it % s.progress_interval != 0) return;
  ProgressEvent e;
  e.load_step = 1;
  e.load_factor = 1.0;
  e.iteration = it;
  e.total_iterations = it;
  e.residual = residual;
  e.active_contacts = model.activeContacts();
  run.history.push_back(e);
  if (progress) progress(e);
}

// Seed 001 eqs. (16)-(18): Newton-Raphson on the full load with the refinement scaled by
// lambda = c L_f / max|dD|. The cap lambda <= 1 is ours: once the refinements are shorter than
// c L_f the iteration is plain Newton.
Run solveStatic(SolidShellModel& model, const SolidShellSettings& s, double free_length,
                const ProgressCallback& progress) {
  Run run;
  Eigen::VectorXd R;
  Eigen::SparseMatrix<double> K;
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  const double load = std::max(model.loadNorm(), 1e-300);
  for (int it = 0;; ++it) {
    model.assemble(R, &K);
    run.residual = R.norm() / load;
    run.iterations = it;
    const bool done = run.residual < s.tolerance;
    report(run, model, it, run.residual, done, s, progress);
    if (!std::isfinite(run.residual)) {
      run.status = "diverged: the out-of-balance force is not finite";
      return run;
    }
    if (done) {
      run.converged = true;
      run.status = "converged: |P - F| / |P| = " + number(run.residual) + " after " +
                   std::to_string(it) + " iterations";
      return run;
    }
    if (it >= s.max_iterations) {
      run.status = "not converged after " + std::to_string(it) +
                   " iterations: |P - F| / |P| = " + number(run.residual);
      return run;
    }
    if (cancelRequested(s.cancel)) {
      run.cancelled = true;
      run.status = "cancelled at iteration " + std::to_string(it);
      return run;
    }
    if (it == 0) lu.analyzePattern(K);
    lu.factorize(K);
    if (lu.info() != Eigen::Success) {
      run.status = "singular tangent at iteration " + std::to_string(it) +
                   ": an unrestrained rigid-body mode or a free director";
      return run;
    }
    const Eigen::VectorXd dD = lu.solve(R);
    const double largest = dD.cwiseAbs().maxCoeff();
    if (!std::isfinite(largest)) {
      run.status = "the Newton refinement is not finite at iteration " + std::to_string(it);
      return run;
    }
    model.increment(std::min(1.0, s.multiplier * free_length / largest) * dD);
  }
}

// Seed 001 eq. (23): central differences with the lumped mass and Rayleigh damping alpha M.
Run solveDynamic(SolidShellModel& model, const SolidShellSettings& s, bool has_colliders,
                 double contact_stiffness, const ProgressCallback& progress) {
  Run run;
  const Eigen::VectorXd M = s.mass_scaling * model.mass();
  Eigen::VectorXd R;
  double dt = s.time_step;
  if (dt <= 0.0) {
    // omega_max^2 <= max_i sum_j |K_ij| / sqrt(M_i M_j) (Gershgorin on M^-1/2 K M^-1/2), with
    // the contact stiffness on every translation that may touch a collider.
    Eigen::SparseMatrix<double> K;
    model.assemble(R, &K);
    Eigen::VectorXd row = Eigen::VectorXd::Zero(model.size());
    for (int c = 0; c < K.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
        row[it.row()] += std::abs(it.value()) / std::sqrt(M[it.row()] * M[it.col()]);
    if (has_colliders)
      for (int i = 0; i < model.size(); ++i)
        if (model.isTranslation(i)) row[i] += contact_stiffness / M[i];
    dt = 0.5 * 2.0 / std::sqrt(row.maxCoeff());
  }
  const double a = 1.0 / (dt * dt), b = 0.5 * s.damping / dt;
  Eigen::VectorXd D = model.freeState(), previous = D;
  const double load = std::max(model.loadNorm(), 1e-300);
  const int steps = static_cast<int>(std::ceil(s.end_time / dt));
  for (int n = 0;; ++n) {
    model.assemble(R, nullptr);
    run.residual = R.norm() / load;
    run.iterations = n;
    const bool done = n > 0 && run.residual < s.tolerance;
    report(run, model, n, run.residual, done, s, progress);
    if (!std::isfinite(run.residual)) {
      run.status = "diverged at t = " + number(n * dt) + " s (time step " + number(dt) + " s)";
      return run;
    }
    if (done) {
      run.converged = true;
      run.status = "converged: |P - F| / |P| = " + number(run.residual) +
                   " at t = " + number(n * dt) + " s after " + std::to_string(n) + " steps of " +
                   number(dt) + " s";
      return run;
    }
    if (n >= steps) {
      run.status = "not settled at t = " + number(n * dt) + " s (" + std::to_string(n) +
                   " steps of " + number(dt) + " s): |P - F| / |P| = " + number(run.residual);
      return run;
    }
    if (cancelRequested(s.cancel)) {
      run.cancelled = true;
      run.status = "cancelled at t = " + number(n * dt) + " s";
      return run;
    }
    const Eigen::VectorXd next = (R.cwiseQuotient(M) + 2.0 * a * D + (b - a) * previous) / (a + b);
    previous = D;
    D = next;
    model.setFreeState(D);
  }
}

}  // namespace

void validateSolidShellSettings(const SolidShellSettings& s) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw InputError(std::string("solid_shell.") + name + " must be positive");
  };
  positive(s.tolerance, "tolerance");
  positive(s.multiplier, "multiplier");
  positive(s.mass_scaling, "mass_scaling");
  positive(s.end_time, "end_time");
  if (!(s.mu > 0.0 && s.mu < 1.0)) throw InputError("solid_shell.mu must lie in (0, 1)");
  if (!(s.free_length >= 0.0)) throw InputError("solid_shell.free_length must not be negative");
  if (!(s.damping >= 0.0)) throw InputError("solid_shell.damping must not be negative (1/s)");
  if (!(s.time_step >= 0.0)) throw InputError("solid_shell.time_step must not be negative");
  if (!(s.contact_stiffness >= 0.0))
    throw InputError("solid_shell.contact_stiffness must not be negative");
  if (s.max_iterations < 1 || s.progress_interval < 1)
    throw InputError("solid_shell.max_iterations and progress_interval must be positive");
}

DrapeResult solveSolidShell(const DrapeProblem& problem, const SolidShellSettings& settings,
                            const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  problem.validate();
  validateSolidShellSettings(settings);
  if (!problem.seams.empty())
    throw InputError(
        "seams: the solid shell does not sew (use method fem_shell or particle for a garment with "
        "seams)");
  if (settings.scheme == SolidShellScheme::kStatic) problem.checkStaticSupport();
  SolidShellModel model(problem, settings.thickness_strain, settings.mu, settings.contact_stiffness,
                        settings.scheme == SolidShellScheme::kStatic);
  const double k_contact = settings.contact_stiffness > 0.0
                               ? settings.contact_stiffness
                               : 100.0 * (problem.fabric ? std::max(problem.fabric->tensile_warp,
                                                                    problem.fabric->tensile_weft)
                                                         : problem.material.membraneStiffness());
  Run run;
  if (settings.scheme == SolidShellScheme::kStatic) {
    Eigen::AlignedBox3d box;
    for (const auto& x : problem.mesh.vertices) box.extend(x);
    const double lf = settings.free_length > 0.0 ? settings.free_length : box.sizes().maxCoeff();
    run = solveStatic(model, settings, lf, progress);
  } else {
    run = solveDynamic(model, settings, !problem.colliders.empty(), k_contact, progress);
  }
  DrapeResult r;
  r.converged = run.converged;
  r.cancelled = run.cancelled;
  r.status = run.status;
  const int reversed = model.reversedDirectors();
  if (reversed > 0)
    r.status += "; " + std::to_string(reversed) +
                " element corners have their director below the mid-surface (top and bottom "
                "surfaces interpenetrate)";
  r.load_steps = 1;
  r.iterations = run.iterations;
  r.load_factor = 1.0;
  r.residual = run.residual;
  r.history = std::move(run.history);
  r.positions = model.positions();
  for (const auto& n : model.directors()) r.directors.push_back(n.normalized());
  r.reactions = model.reactions();
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace chs
