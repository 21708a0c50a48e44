#include "cloth_hair_sim/core/solid_shell/solid_shell_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/UmfPackSupport>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/solid_shell/adaptive_mesh.h"
#include "cloth_hair_sim/core/solid_shell/solid_shell_model.h"
#include "cloth_hair_sim/core/solver/continuation_problem.h"
#include "cloth_hair_sim/core/solver/energy_newton.h"
#include "cloth_hair_sim/core/solver/stability.h"

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

// The adaptive mesh of seed 001 section 5 and the model on its active elements.
struct Adaptivity {
  AdaptiveQuadMesh mesh;
  BoundaryConditions bc;  // on the background nodes
  int adaptations = 0, peak_active_nodes = 0;
};

std::unique_ptr<SolidShellModel> buildModel(const DrapeProblem& problem,
                                            const SolidShellSettings& s, const Adaptivity* a) {
  const bool centred = s.scheme != SolidShellScheme::kDynamic;
  if (!a)
    return std::make_unique<SolidShellModel>(problem, s.thickness_strain, s.mu, s.contact_stiffness,
                                             centred);
  return std::make_unique<SolidShellModel>(problem, a->mesh.activeMesh(a->bc), s.thickness_strain,
                                           s.mu, s.contact_stiffness, centred);
}

// Eqs. (25)-(26) per leaf, from the largest bending strain of its elements.
std::vector<int> adaptFlags(const AdaptiveQuadMesh& mesh, const SolidShellModel& model,
                            const SolidShellSettings& s) {
  const auto elements = mesh.elements();
  std::vector<double> bend(mesh.leaves().size(), 0.0);
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const double b = model.elements()[e].bendingStrainNorm(model.elementState(static_cast<int>(e)));
    bend[elements[e].leaf] = std::max(bend[elements[e].leaf], b);
  }
  std::vector<int> flags(bend.size(), 0);
  for (std::size_t k = 0; k < bend.size(); ++k) {
    const double L = mesh.sideLength(mesh.leaves()[k]);
    if (bend[k] * L > s.refine_threshold)
      flags[k] = 1;
    else if (bend[k] * 2.0 * L <= s.refine_threshold - s.merge_margin)
      flags[k] = -1;
  }
  return flags;
}

// The switched-on nodes' static equilibrium with every other node held: Newton on their own
// unknowns, from the discrete Kirchhoff state. Ours, not the seed's: the discrete Kirchhoff
// condition is linear and blind to how a coarse element's directors lag its chords, so its nodes
// start with transverse shear (measured: a 4 x 4 wool sheet on a table at its first
// adaptation, shear strains near 0.05 and 100 x the sheet's strain energy, which then threw the
// sheet off the table). Returns the corrections of U_o and U_n (zero where Newton does not lower
// the out-of-balance force).
std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>> settleSwitchedOnNodes(
    const Adaptivity& a, const DrapeProblem& problem, const SolidShellSettings& s,
    const std::vector<bool>& was_active, const std::vector<Eigen::Vector3d>& u,
    const std::vector<Eigen::Vector3d>& un) {
  const std::size_t n = u.size();
  std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>> none{
      std::vector<Eigen::Vector3d>(n, Eigen::Vector3d::Zero()),
      std::vector<Eigen::Vector3d>(n, Eigen::Vector3d::Zero())};
  SolidShellMesh mesh = a.mesh.activeMesh(a.bc);
  for (std::size_t v = 0; v < n; ++v)
    if (was_active[v]) mesh.bc.clamped.push_back(static_cast<int>(v));
  SolidShellModel local(problem, std::move(mesh), s.thickness_strain, s.mu, s.contact_stiffness,
                        s.scheme != SolidShellScheme::kDynamic);
  if (local.size() == 0) return none;
  local.setDisplacements(u, un);
  Eigen::VectorXd R, trial_R;
  Eigen::SparseMatrix<double> K;
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  // Steps are accepted while the out-of-balance force falls.
  local.assemble(R, &K);
  const double start = R.norm();
  for (int it = 0; it < 10 && R.norm() > 1e-6 * start; ++it) {
    lu.compute(K);
    if (lu.info() != Eigen::Success) break;
    Eigen::VectorXd dD = lu.solve(R);
    if (!dD.allFinite()) break;
    const Eigen::VectorXd D = local.freeState();
    // Halve the step until the out-of-balance force falls (an indefinite K near contact).
    bool accepted = false;
    for (int half = 0; half < 8 && !accepted; ++half, dD *= 0.5) {
      local.setFreeState(D + dD);
      local.assemble(trial_R, nullptr);
      accepted = trial_R.norm() < R.norm();
    }
    if (!accepted) {
      local.setFreeState(D);
      break;
    }
    local.assemble(R, &K);
  }
  if (!(R.norm() < start)) return none;
  for (std::size_t v = 0; v < n; ++v) {
    none.first[v] = local.displacements()[v] - u[v];
    none.second[v] = local.directorDisplacements()[v] - un[v];
  }
  return none;
}

// One adaptation; when the mesh changed, the model is rebuilt on it with the nodal state carried
// over (the nodes switched on get theirs by the discrete Kirchhoff condition, then settle) and the
// free states in `states` (the current one first) re-expressed on its unknowns.
bool adapt(Adaptivity& a, std::unique_ptr<SolidShellModel>& model, const DrapeProblem& problem,
           const SolidShellSettings& s, std::vector<Eigen::VectorXd*> states) {
  const std::vector<bool> was_active = a.mesh.activeNodes();
  if (!a.mesh.adapt(adaptFlags(a.mesh, *model, s))) return false;
  std::vector<std::vector<Eigen::Vector3d>> u(states.size()), un(states.size());
  const std::vector<bool> now_active = a.mesh.activeNodes();
  const auto& X = a.mesh.background().vertices;
  for (std::size_t k = 0; k < states.size(); ++k) {
    model->setFreeState(*states[k]);
    u[k] = model->displacements();
    un[k] = model->directorDisplacements();
  }
  // The current state by the discrete Kirchhoff condition; the others as differences from it
  // interpolated linearly: the new nodes' velocities are their parents' mean. (Applied to each
  // state, the nonlinear condition would give velocities of its jumps over one time step.)
  for (std::size_t k = 1; k < states.size(); ++k)
    for (std::size_t v = 0; v < X.size(); ++v) u[k][v] -= u[0][v], un[k][v] -= un[0][v];
  a.mesh.fillSwitchedOnNodes(was_active, u[0], un[0]);
  for (std::size_t k = 1; k < states.size(); ++k) {
    a.mesh.fillSwitchedOnNodes(was_active, u[k], un[k], false);
    for (std::size_t v = 0; v < X.size(); ++v) u[k][v] += u[0][v], un[k][v] += un[0][v];
  }
  // A node switched on inside a collider (the coarser mesh sagged through a table's edge between
  // its nodes) starts on the collider's surface, not deep in its penalty. Every state moves by
  // the same amount: the node's velocity stays its parents' mean (a velocity from projecting
  // each state on its own would be the penetration over one time step).
  for (std::size_t v = 0; v < X.size(); ++v) {
    if (!now_active[v] || was_active[v]) continue;
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    for (const auto& surface : problem.colliders) {
      const SurfaceProjection p = surface->project(X[v] + u[0][v] + shift);
      if (p.gap < 0.0) shift -= p.gap * p.normal;
    }
    for (auto& state : u) state[v] += shift;
  }
  // The switched-on nodes then settle against their neighbours held still.
  const auto [du, dun] = settleSwitchedOnNodes(a, problem, s, was_active, u[0], un[0]);
  for (std::size_t k = 0; k < states.size(); ++k)
    for (std::size_t v = 0; v < X.size(); ++v) u[k][v] += du[v], un[k][v] += dun[v];
  model = buildModel(problem, s, &a);
  for (std::size_t k = states.size(); k-- > 0;) {
    model->setDisplacements(u[k], un[k]);
    *states[k] = model->freeState();
  }
  ++a.adaptations;
  a.peak_active_nodes = std::max(a.peak_active_nodes, a.mesh.numActiveNodes());
  return true;
}

// omega_max^2 <= max_i sum_j |K_ij| / sqrt(M_i M_j) (Gershgorin on M^-1/2 K M^-1/2), with the
// contact stiffness on every translation that may touch a collider; half the stable step.
double stableStep(SolidShellModel& model, const Eigen::VectorXd& M, bool has_colliders,
                  double contact_stiffness) {
  Eigen::VectorXd R;
  Eigen::SparseMatrix<double> K;
  model.assemble(R, &K);
  Eigen::VectorXd row = Eigen::VectorXd::Zero(model.size());
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
      row[it.row()] += std::abs(it.value()) / std::sqrt(M[it.row()] * M[it.col()]);
  if (has_colliders)
    for (int i = 0; i < model.size(); ++i)
      if (model.isTranslation(i)) row[i] += contact_stiffness / M[i];
  return 0.5 * 2.0 / std::sqrt(row.maxCoeff());
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

// The solid shell as a problem for the energy minimiser: R = lambda P - F - F_c, K = dF/dD + the
// penalty's stiffness (symmetric: both come from a potential).
class SolidShellEnergyProblem : public ContinuationProblem {
 public:
  explicit SolidShellEnergyProblem(SolidShellModel& model)
      : model_(model), load_(model.loadVector()), saved_(model.freeState()) {
    double edges = 0.0;
    int count = 0;
    const auto x = model.positions();
    for (const auto& el : model.elements())
      for (int i = 0; i < el.corners(); ++i, ++count)
        edges += (x[el.nodes()[i]] - x[el.nodes()[(i + 1) % el.corners()]]).norm();
    mean_edge_ = count > 0 ? edges / count : model.lengthScale();
  }
  int size() const override { return model_.size(); }
  void linearize(double lambda, Eigen::VectorXd& R, Eigen::VectorXd& F0,
                 Eigen::SparseMatrix<double>* K) override {
    model_.assemble(R, K);
    if (lambda != 1.0) R -= (1.0 - lambda) * load_;
    F0 = load_;
  }
  void increment(const Eigen::VectorXd& dq) override { model_.increment(dq); }
  void save() override { saved_ = model_.freeState(); }
  void restore() override { model_.setFreeState(saved_); }
  double loadNorm() const override { return model_.loadNorm(); }
  double lengthScale() const override { return model_.lengthScale(); }
  int activeContacts() const override { return model_.activeContacts(); }
  double energy(double lambda) override { return model_.potentialEnergy(lambda); }
  // As the FEM shell's: no node moves by more than two mean edges, no director by more than
  // half its length, in one Newton step (the far-field step is the huge linear response).
  double stepBound(const Eigen::VectorXd& dq) const override {
    const auto [move, turn] = model_.largestIncrement(dq);
    double f = 1.0;
    if (move > 2.0 * mean_edge_) f = std::min(f, 2.0 * mean_edge_ / move);
    if (turn > 0.5) f = std::min(f, 0.5 / turn);
    return f;
  }

 private:
  SolidShellModel& model_;
  Eigen::VectorXd load_, saved_;
  double mean_edge_ = 1.0;
};

// The energy scheme (ours): Newton on the total potential with a modified Hessian, a line search
// and saddle escapes; the stability of the returned state comes with it.
Run solveEnergy(SolidShellModel& model, const SolidShellSettings& s, StabilityCheck& stability,
                const ProgressCallback& progress) {
  SolidShellEnergyProblem problem(model);
  EnergyNewtonSettings e;
  e.tolerance = s.tolerance;
  e.max_iterations = s.max_iterations;
  e.cancel = s.cancel;
  const EnergyNewtonResult en = solveEnergyNewton(problem, e, progress);
  stability = en.stability;
  Run run;
  run.converged = en.converged;
  run.cancelled = en.cancelled;
  run.status = en.status;
  run.iterations = en.iterations;
  run.residual = en.residual;
  run.history = en.history;
  return run;
}

// Seed 001 eq. (23): central differences with the lumped mass and Rayleigh damping alpha M; with
// adaptivity, the mesh adapts every adapt_interval steps and once more before the run may end.
Run solveDynamic(std::unique_ptr<SolidShellModel>& model, const DrapeProblem& problem,
                 const SolidShellSettings& s, double contact_stiffness, Adaptivity* adaptivity,
                 const ProgressCallback& progress) {
  Run run;
  const bool has_colliders = !problem.colliders.empty();
  Eigen::VectorXd M = s.mass_scaling * model->mass();
  Eigen::VectorXd R;
  double dt =
      s.time_step > 0.0 ? s.time_step : stableStep(*model, M, has_colliders, contact_stiffness);
  double a = 1.0 / (dt * dt), b = 0.5 * s.damping / dt;
  Eigen::VectorXd D = model->freeState(), previous = D;
  const double load = std::max(model->loadNorm(), 1e-300);
  double t = 0.0;
  // After an adaptation: the new mesh's masses and, unless given, its stable step, keeping the
  // velocity (D - previous) / dt.
  auto adapted = [&] {
    M = s.mass_scaling * model->mass();
    if (s.time_step > 0.0) return;
    const double next = stableStep(*model, M, has_colliders, contact_stiffness);
    previous = D - (next / dt) * (D - previous);
    dt = next;
    a = 1.0 / (dt * dt), b = 0.5 * s.damping / dt;
  };
  for (int n = 0;; ++n) {
    if (adaptivity && n > 0 && n % s.adapt_interval == 0 &&
        adapt(*adaptivity, model, problem, s, {&D, &previous}))
      adapted();
    model->assemble(R, nullptr);
    run.residual = R.norm() / load;
    run.iterations = n;
    bool done = n > 0 && run.residual < s.tolerance;
    // Settled: the mesh must be settled too.
    if (done && adaptivity && adapt(*adaptivity, model, problem, s, {&D, &previous})) {
      adapted();
      model->assemble(R, nullptr);
      run.residual = R.norm() / load;
      done = false;
    }
    report(run, *model, n, run.residual, done, s, progress);
    if (!std::isfinite(run.residual)) {
      run.status = "diverged at t = " + number(t) + " s (time step " + number(dt) + " s)";
      return run;
    }
    if (done) {
      run.converged = true;
      run.status = "converged: |P - F| / |P| = " + number(run.residual) + " at t = " + number(t) +
                   " s after " + std::to_string(n) + " steps of " + number(dt) + " s";
      return run;
    }
    if (t >= s.end_time) {
      run.status = "not settled at t = " + number(t) + " s (" + std::to_string(n) + " steps of " +
                   number(dt) + " s): |P - F| / |P| = " + number(run.residual);
      return run;
    }
    if (cancelRequested(s.cancel)) {
      run.cancelled = true;
      run.status = "cancelled at t = " + number(t) + " s";
      return run;
    }
    const Eigen::VectorXd next = (R.cwiseQuotient(M) + 2.0 * a * D + (b - a) * previous) / (a + b);
    previous = D;
    D = next;
    model->setFreeState(D);
    t += dt;
  }
}

}  // namespace

SolidShellScheme parseSolidShellScheme(const std::string& name) {
  if (name == "static") return SolidShellScheme::kStatic;
  if (name == "dynamic") return SolidShellScheme::kDynamic;
  if (name == "energy") return SolidShellScheme::kEnergy;
  throw InputError("solid_shell.scheme must be static, dynamic or energy, got '" + name + "'");
}

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
  if (s.adaptive_levels < 0 || s.adaptive_levels > kMaxAdaptiveLevels)
    throw InputError("solid_shell.adaptive_levels must lie in [0, " +
                     std::to_string(kMaxAdaptiveLevels) +
                     "] (0: no adaptivity; each level quadruples the background mesh), got " +
                     std::to_string(s.adaptive_levels));
  if (s.adaptive_levels > 0) {
    positive(s.refine_threshold, "refine_threshold");
    if (!(s.merge_margin > 0.0 && s.merge_margin < s.refine_threshold))
      throw InputError("solid_shell.merge_margin must lie in (0, refine_threshold)");
    if (s.adapt_interval < 1 || s.adapt_iterations < 1)
      throw InputError("solid_shell.adapt_interval and adapt_iterations must be positive");
  }
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
  if (settings.scheme != SolidShellScheme::kDynamic) problem.checkStaticSupport();
  std::optional<Adaptivity> adaptivity;
  if (settings.adaptive_levels > 0) {
    const SolidShellMesh level0 = solidShellMesh(problem);
    adaptivity.emplace(
        Adaptivity{AdaptiveQuadMesh(problem.mesh, level0.Xn, settings.adaptive_levels), {}, 0, 0});
    adaptivity->bc = adaptivity->mesh.boundaryConditions(problem.bc);
    adaptivity->peak_active_nodes = adaptivity->mesh.numActiveNodes();
  }
  Adaptivity* adaptive = adaptivity ? &*adaptivity : nullptr;
  std::unique_ptr<SolidShellModel> model = buildModel(problem, settings, adaptive);
  const double k_contact = settings.contact_stiffness > 0.0
                               ? settings.contact_stiffness
                               : 100.0 * (problem.fabric ? std::max(problem.fabric->tensile_warp,
                                                                    problem.fabric->tensile_weft)
                                                         : problem.material.membraneStiffness());
  Run run;
  std::optional<StabilityCheck> stability;
  if (settings.scheme != SolidShellScheme::kDynamic) {
    Eigen::AlignedBox3d box;
    for (const auto& x : problem.mesh.vertices) box.extend(x);
    const double lf = settings.free_length > 0.0 ? settings.free_length : box.sizes().maxCoeff();
    const auto solve_with = [&](const SolidShellSettings& ss) {
      if (ss.scheme == SolidShellScheme::kStatic) return solveStatic(*model, ss, lf, progress);
      stability.emplace();
      return solveEnergy(*model, ss, *stability, progress);
    };
    const auto solve = [&] { return solve_with(settings); };
    int used = 0;
    if (adaptive && settings.scheme == SolidShellScheme::kEnergy) {
      // The descent adapts as it goes, every adapt_iterations Newton iterations: solved to the end
      // on the coarse mesh first, the sheet folds over more sharply than the mesh can follow and
      // stays so (120 reversed directors on the pedestal, 385 on the sphere).
      SolidShellSettings chunk = settings;
      chunk.max_iterations = std::min(settings.adapt_iterations, settings.max_iterations);
      for (;;) {
        run = solve_with(chunk);
        used += run.iterations;
        if (run.converged || run.cancelled || used >= settings.max_iterations) break;
        Eigen::VectorXd D = model->freeState();
        if (!adapt(*adaptive, model, problem, settings, {&D})) break;
      }
    }
    if (!run.cancelled) {
      run = solve();
      run.iterations += used;
    }
    // Adaptive: each converged drape adapts the mesh and is solved again, until the mesh stays.
    for (int round = 0; adaptive && run.converged && round < 4 * settings.adaptive_levels;
         ++round) {
      Eigen::VectorXd D = model->freeState();
      if (!adapt(*adaptive, model, problem, settings, {&D})) break;
      const int before = run.iterations;
      run = solve();
      run.iterations += before;
    }
    // The seed's scheme finds an equilibrium, not necessarily a minimum: assess it as well.
    if (settings.scheme == SolidShellScheme::kStatic && run.converged) {
      Eigen::VectorXd R;
      Eigen::SparseMatrix<double> K;
      model->assemble(R, &K);
      stability = checkStability(K);
    }
  } else {
    run = solveDynamic(model, problem, settings, k_contact, adaptive, progress);
  }
  DrapeResult r;
  r.converged = run.converged;
  r.cancelled = run.cancelled;
  r.status = run.status;
  if (adaptive)
    r.status += "; adaptive mesh: " + std::to_string(adaptive->adaptations) + " adaptations, " +
                std::to_string(adaptive->mesh.leaves().size()) + " leaves, " +
                std::to_string(adaptive->mesh.numActiveNodes()) + " active nodes (" +
                std::to_string(adaptive->peak_active_nodes) + " at most) of " +
                std::to_string(adaptive->mesh.numNodes());
  const int reversed = model->reversedDirectors();
  if (reversed > 0)
    r.status += "; " + std::to_string(reversed) +
                " element corners have their director below the mid-surface (top and bottom "
                "surfaces interpenetrate)";
  r.load_steps = 1;
  r.iterations = run.iterations;
  r.load_factor = 1.0;
  r.residual = run.residual;
  r.history = std::move(run.history);
  r.positions = model->positions();
  std::vector<Eigen::Vector3d> directors = model->directors();
  if (adaptive) {
    // On the background mesh: the inactive nodes where the active elements put them.
    adaptive->mesh.interpolateInactive(r.positions);
    adaptive->mesh.interpolateInactive(directors);
    r.refined_mesh = adaptive->mesh.background();
    for (const auto& e : adaptive->mesh.elements()) r.active_elements.push_back(e.nodes);
    r.peak_active_nodes = adaptive->peak_active_nodes;
  }
  for (const auto& n : directors) r.directors.push_back(n.normalized());
  r.reactions = model->reactions();
  if (stability && stability->computed) {
    r.stability.assessed = true;
    r.stability.lowest_eigenvalue = stability->lowest_eigenvalue;
    r.stability.negative_eigenvalues = stability->negative_eigenvalues;
    r.stability.stable = stability->stable;
    r.stability.verdict = stability->stable ? "stable" : "unstable (saddle)";
    if (!stability->stable && r.converged) {
      r.converged = false;
      r.status += "; but the equilibrium is unstable (a saddle: " +
                  std::to_string(stability->negative_eigenvalues) +
                  " negative eigenvalues of the tangent), not a drape";
    }
  } else if (stability) {
    r.stability.verdict = "not assessed: not an equilibrium, or the eigenvalue solver failed";
  }
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace chs
