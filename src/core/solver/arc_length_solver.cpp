#include "cloth_hair_sim/core/solver/arc_length_solver.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/UmfPackSupport>

#include "cloth_hair_sim/core/common/blas_threads.h"

namespace chs {

namespace {

// The tangent is non-symmetric (Kawabata bending, moment loads, and away from equilibrium the
// director terms) and indefinite past buckling, so it is factorised by UMFPACK's sparse LU. The
// pattern never changes, so its symbolic analysis is done once.
class TangentSolver {
 public:
  TangentSolver() {
    // OpenBLAS's own threads spin against oneTBB's on systems this small; one is faster.
    holdBlasToOneThread();
    lu_.umfpackControl()(UMFPACK_IRSTEP) = 0;  // Newton itself refines the solution
    // The tangent is symmetric up to the small non-symmetric terms: order A + A^T and prefer
    // diagonal pivots, which keeps the fill of a shell stiffness low.
    lu_.umfpackControl()(UMFPACK_STRATEGY) = UMFPACK_STRATEGY_SYMMETRIC;
  }
  bool factorize(const Eigen::SparseMatrix<double>& K) {
    if (!analyzed_) {
      lu_.analyzePattern(K);
      analyzed_ = true;
    }
    lu_.factorize(K);
    K_ = &K;
    return lu_.info() == Eigen::Success;
  }
  // False when the solution is not finite or does not satisfy K x = b: a singular tangent.
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
    x = lu_.solve(b);
    if (!x.allFinite()) return false;
    const double bn = b.norm();
    return bn == 0.0 || ((*K_) * x - b).norm() <= 1e-6 * bn;
  }

 private:
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu_;
  const Eigen::SparseMatrix<double>* K_ = nullptr;
  bool analyzed_ = false;
};

enum class Outcome { kConverged, kDiverged, kSingular, kCancelled };

const char* kRigidBodyHint =
    "the garment may have a rigid-body mode (no support, or free to slide or spin in the "
    "plane); clamp, pin or fix components to hold it";

// One load step of section 2.2.3 from the last saved state: predictor (steps 3.1-3.7) and
// corrector iterations (step 4), either on the arc (19)-(22) or at a fixed load factor.
class StepRunner {
 public:
  StepRunner(ContinuationProblem& p, const ArcLengthSettings& s, ContinuationResult& out,
             const ProgressCallback& progress)
      : p_(p), s_(s), out_(out), progress_(progress), n_(p.size()) {}

  // Tangent direction K^-1 F0 at the saved state; false if K is singular.
  bool predictorDirection(double lambda, Eigen::VectorXd& uI) {
    p_.linearize(lambda, R_, F0_, &K_);
    return lu_.factorize(K_) && lu_.solve(F0_, uI);
  }

  // Runs the step; on return the problem holds the new state (converged or not).
  Outcome run(int step, double lambda, double dlam, const Eigen::VectorXd& uI, bool on_arc,
              double arc, double& lam_out) {
    d_ = dlam * uI;
    p_.increment(d_);
    double lam = lambda + dlam, dl = dlam;
    if (!on_arc && std::abs(lam - 1.0) < 1e-14) lam = 1.0;
    double first = 0.0, correction = HUGE_VAL;
    Outcome outcome = Outcome::kDiverged;
    int it = 0;
    for (;; ++it) {
      if (cancelRequested(s_.cancel)) {
        outcome = Outcome::kCancelled;
        break;
      }
      p_.linearize(lam, R_, F0_, &K_);
      res_ = R_.norm() / p_.loadNorm();
      if (it == 0) first = res_;
      ProgressEvent e{step, lam, it, res_, p_.activeContacts(), out_.iterations + it};
      out_.history.push_back(e);
      if (progress_) progress_(e);
      // Converged, or stalled at the round-off floor: a residual near the tolerance that a
      // correction of a millionth of a millionth of the model size no longer reduces.
      if (res_ <= s_.tolerance ||
          (res_ <= 100.0 * s_.tolerance && correction <= 1e-12 * p_.lengthScale())) {
        outcome = Outcome::kConverged;
        break;
      }
      if (!std::isfinite(res_) || res_ > 1e6 * std::max(first, 1.0)) break;
      if (it == s_.max_iterations_per_step) break;
      if (!lu_.factorize(K_) || !lu_.solve(R_, uII_)) {
        outcome = Outcome::kSingular;
        break;
      }
      double dlam_i = 0.0;
      if (!on_arc) {
        delta_ = uII_;
      } else {
        if (!lu_.solve(F0_, uI_)) {
          outcome = Outcome::kSingular;
          break;
        }
        const double f = std::sqrt(d_.squaredNorm() + dl * dl) - arc;   // eq. (19)
        dlam_i = -(f * (f + arc) + d_.dot(uII_)) / (dl + d_.dot(uI_));  // eq. (21)
        delta_ = dlam_i * uI_ + uII_;                                   // eq. (22)
      }
      correction = delta_.lpNorm<Eigen::Infinity>();
      if (!delta_.allFinite() || correction > 10.0 * p_.lengthScale()) {
        outcome = Outcome::kSingular;
        break;
      }
      p_.increment(delta_);  // step 4.5
      if (!on_arc) backtrack(lam);
      lam += dlam_i;  // step 4.6
      d_ += delta_;
      dl += dlam_i;
    }
    out_.iterations += it;
    iterations_ = it;
    lam_out = lam;
    return outcome;
  }

  // Under load control a full Newton correction that raises the residual (an active-set switch,
  // a large director rotation) is halved until it lowers it; the exponential map makes -a delta
  // undo a delta exactly. The arc-length corrector keeps full steps to stay on its constraint.
  void backtrack(double lam) {
    double alpha = 1.0;
    for (int k = 0; k < 6; ++k) {
      p_.linearize(lam, R_, F0_, nullptr);
      const double trial = R_.norm() / p_.loadNorm();
      if (!(trial > res_) || res_ <= s_.tolerance) return;
      p_.increment(-0.5 * alpha * delta_);
      alpha *= 0.5;
    }
    delta_ *= alpha;
  }

  // One pseudo-transient Newton iteration at lam, anchored at the current state where the
  // viscous force vanishes: res_ is the true residual there. The state is saved first when it is
  // the best so far. Returns false on a singular tangent or a runaway increment.
  bool ptcIteration(int step, int it, double lam, double& best) {
    p_.anchorHere();
    p_.linearize(lam, R_, F0_, &K_);
    res_ = R_.norm() / p_.loadNorm();
    ProgressEvent e{step, lam, it, res_, p_.activeContacts(), out_.iterations};
    out_.history.push_back(e);
    if (progress_) progress_(e);
    if (res_ < best) {
      best = res_;
      p_.save();
    }
    if (res_ <= s_.tolerance) return true;
    if (!lu_.factorize(K_) || !lu_.solve(R_, delta_) ||
        delta_.lpNorm<Eigen::Infinity>() > 10.0 * p_.lengthScale())
      return false;
    p_.increment(delta_);
    ++out_.iterations;
    return true;
  }

  int iterations() const { return iterations_; }
  double residual() const { return res_; }

 private:
  ContinuationProblem& p_;
  const ArcLengthSettings& s_;
  ContinuationResult& out_;
  const ProgressCallback& progress_;
  const int n_;
  TangentSolver lu_;
  Eigen::SparseMatrix<double> K_;
  Eigen::VectorXd R_, F0_, uI_, uII_, d_, delta_;
  double res_ = 0.0;
  int iterations_ = 0;
};

}  // namespace

ContinuationResult solveArcLength(ContinuationProblem& problem, const ArcLengthSettings& s,
                                  const ProgressCallback& progress) {
  ContinuationResult out;
  if (!(problem.loadNorm() > 0.0)) {
    out.converged = true;
    out.lambda = 1.0;
    out.status = "no load: the reference state is the solution";
    return out;
  }
  const bool stabilized = s.stabilization > 0.0;
  const bool arc_length = s.arc_length && !stabilized;
  double stab_scale = 1.0;  // a stabilised step that fails retries with stronger damping
  problem.setStabilization(s.stabilization);
  StepRunner runner(problem, s, out, progress);
  Eigen::VectorXd uI;

  double lambda = 0.0;  // load factor of the last converged state
  double arc = 0.0;     // gamma_n * Delta s: arc length of the coming step
  double load_step = s.initial_load_increment;
  bool onto_one = false;  // load control onto lambda = 1 after the arc overshot it
  int settling = 0;
  bool failed = false;
  problem.save();

  while (!failed && lambda < 1.0) {
    if (out.load_steps >= s.max_load_steps) {
      std::ostringstream msg;
      msg << "stopped after " << s.max_load_steps << " load steps at load factor " << lambda;
      out.status = msg.str();
      failed = true;
      break;
    }
    const int step = out.load_steps + 1;
    if (cancelRequested(s.cancel)) {
      out.cancelled = failed = true;
      break;
    }
    if (!runner.predictorDirection(lambda, uI)) {
      out.status = "the tangent stiffness is singular at load factor " + std::to_string(lambda) +
                   ": " + kRigidBodyHint;
      failed = true;
      break;
    }
    if (arc == 0.0) arc = s.initial_load_increment * uI.norm();  // step 3.4: Delta s
    bool on_arc = arc_length && !onto_one;
    double dlam = on_arc ? arc / uI.norm() : (onto_one ? 1.0 - lambda : load_step);  // step 3.5
    dlam = std::min(dlam, s.max_load_increment);
    if (lambda + dlam >= 1.0) {
      dlam = 1.0 - lambda;
      on_arc = false;
    }
    double lam = lambda;
    const Outcome outcome = runner.run(step, lambda, dlam, uI, on_arc, arc, lam);
    if (outcome == Outcome::kCancelled) {
      problem.restore();
      out.cancelled = failed = true;
      break;
    }

    if (outcome == Outcome::kConverged && on_arc && lam > 1.0) {
      // The arc overshot lambda = 1: redo the step under load control onto 1.
      problem.restore();
      onto_one = true;
      continue;
    }
    if (outcome == Outcome::kConverged) {
      problem.save();
      lambda = on_arc ? lam : lambda + dlam;
      if (!on_arc && std::abs(lambda - 1.0) < 1e-12) lambda = 1.0;
      ++out.load_steps;
      out.residual = runner.residual();
      // Eq. (20): gamma_n = N_p / N_{n-1}, applied cumulatively to the arc length and bounded to
      // [1/2, 2] so that one easy step cannot throw the next one far past a limit point.
      const double gamma = std::clamp(
          static_cast<double>(s.target_iterations) / std::max(runner.iterations(), 1), 0.5, 2.0);
      arc *= gamma;
      load_step = std::min(load_step * gamma, s.max_load_increment);
      if (stabilized && stab_scale > 1.0) {
        stab_scale = std::max(1.0, stab_scale / gamma);
        problem.setStabilization(s.stabilization * stab_scale);
      }
      continue;
    }
    // Divergence (step 4.1): back to the last converged state with half the arc length.
    problem.restore();
    onto_one = false;
    ++out.cutbacks;
    arc *= 0.5;
    load_step *= 0.5;
    if (stabilized) {
      stab_scale *= 4.0;
      problem.setStabilization(s.stabilization * stab_scale);
    }
    if (out.cutbacks > s.max_cutbacks) {
      std::ostringstream msg;
      msg << "no convergence after " << s.max_cutbacks << " arc-length cutbacks at load factor "
          << lambda << " (last residual " << runner.residual() << ")";
      if (outcome == Outcome::kSingular)
        msg << "; the tangent became singular or the increment ran away: " << kRigidBodyHint;
      out.status = msg.str();
      failed = true;
    }
  }
  out.lambda = lambda;
  if (out.cancelled) {
    std::ostringstream msg;
    msg << "cancelled at load factor " << lambda << " after " << out.load_steps
        << " load steps; returning the last converged load step";
    out.status = msg.str();
  }
  if (failed) return out;

  if (stabilized) {
    // Pseudo-transient continuation at lambda = 1 (Kelley and Keyes 1998): one Newton iteration
    // per pseudo-time step, damped by the viscous term anchored at the current state, with
    // switched evolution relaxation c_{k+1} = c_k r_k / r_{k-1}: the damping fades as the
    // residual falls, so the last iterations are plain Newton and converge quadratically.
    // A step that fails or lets the residual grow a thousandfold past the best one restarts from
    // the best state with ten times the damping.
    const int step = out.load_steps + 1;
    double previous = 0.0, best = HUGE_VAL;
    bool settled = false;
    for (; settling < s.max_settling_steps; ++settling) {
      if (cancelRequested(s.cancel)) {
        out.cancelled = true;
        break;
      }
      problem.setStabilization(s.stabilization * stab_scale);
      const bool ok = runner.ptcIteration(step, settling, 1.0, best);
      const double r = runner.residual();
      if (r <= s.tolerance) {
        settled = true;
        break;
      }
      if (!ok || r > 1e3 * std::max(best, s.tolerance)) {
        problem.restore();
        stab_scale *= 10.0;
        previous = 0.0;
        if (stab_scale > 1e8) break;  // even a near-frozen step fails: stalled
        continue;
      }
      if (previous > 0.0) stab_scale *= std::clamp(r / previous, 0.1, 4.0);
      previous = r;
    }
    problem.setStabilization(0.0);
    if (out.cancelled) {
      problem.restore();
      std::ostringstream msg;
      msg << "cancelled while settling at load factor 1 after " << settling
          << " pseudo-time steps (least residual " << best
          << "); returning the state of least residual";
      out.status = msg.str();
      return out;
    }
    if (!settled) {
      problem.restore();  // the state of least residual
      out.status = "the stabilised drape did not settle to equilibrium in " +
                   std::to_string(settling) + " pseudo-time steps (least residual " +
                   std::to_string(best) +
                   (stab_scale > 1e8 ? ", stalled: no damped step helps" : "") +
                   "); returning the state of least residual";
      return out;
    }
    problem.save();
    out.residual = runner.residual();
  }
  out.converged = true;
  std::ostringstream msg;
  msg << "converged: load factor 1 reached in " << out.load_steps << " load steps, "
      << out.iterations << " iterations";
  if (stabilized) msg << " (" << settling << " settling steps)";
  out.status = msg.str();
  return out;
}

}  // namespace chs
