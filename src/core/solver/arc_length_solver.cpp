#include "cloth_hair_sim/core/solver/arc_length_solver.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/UmfPackSupport>

namespace chs {

namespace {

// The tangent is non-symmetric (Kawabata bending, moment loads, and away from equilibrium the
// director terms) and indefinite past buckling, so it is factorised by UMFPACK's sparse LU. The
// pattern never changes, so its symbolic analysis is done once.
class TangentSolver {
 public:
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

enum class StepOutcome { kConverged, kDiverged, kSingular };

}  // namespace

ContinuationResult solveArcLength(ContinuationProblem& problem, const ArcLengthSettings& s,
                                  const ProgressCallback& progress) {
  ContinuationResult out;
  const int n = problem.size();
  const double load_norm = problem.loadNorm();
  if (!(load_norm > 0.0)) {
    out.converged = true;
    out.lambda = 1.0;
    out.status = "no load: the reference state is the solution";
    return out;
  }
  Eigen::VectorXd R(n), F0(n), uI(n), uII(n), d(n);
  Eigen::SparseMatrix<double> K(n, n);
  TangentSolver lu;

  double lambda = 0.0;          // load factor of the last converged state
  double arc = 0.0;             // gamma_n * Delta s: the arc length of the coming step
  double load_step = s.initial_load_increment;  // load-control increment
  bool final_step = false;      // load control onto lambda = 1
  problem.save();

  auto record = [&](int step, double lam, int it, double res) {
    ProgressEvent e{step, lam, it, res, problem.activeContacts()};
    out.history.push_back(e);
    if (progress) progress(e);
  };

  while (lambda < 1.0) {
    if (out.load_steps >= s.max_load_steps) {
      out.status = "stopped after " + std::to_string(s.max_load_steps) +
                   " load steps at load factor " + std::to_string(lambda);
      break;
    }
    const int step = out.load_steps + 1;
    // Steps 3.1-3.7: predictor along the tangent K^-1 F0.
    problem.linearize(lambda, R, F0, &K);
    if (!lu.factorize(K) || !lu.solve(F0, uI)) {
      out.status = "the tangent stiffness is singular at load factor " + std::to_string(lambda) +
                   ": the garment has a rigid-body mode (no support, or free to slide or spin "
                   "in the plane); clamp, pin or fix components to hold it";
      break;
    }
    if (arc == 0.0) arc = s.initial_load_increment * uI.norm();  // step 3.4: Delta s
    double dlam;
    bool fixed_lambda = final_step || !s.arc_length;
    if (s.arc_length && !final_step) {
      dlam = arc / uI.norm();  // step 3.5
    } else {
      dlam = final_step ? 1.0 - lambda : load_step;
    }
    dlam = std::clamp(dlam, -s.max_load_increment, s.max_load_increment);
    const bool onto_one = lambda + dlam >= 1.0;
    if (onto_one) {
      dlam = 1.0 - lambda;
      fixed_lambda = true;
    }
    d = dlam * uI;  // step 3.6
    problem.increment(d);
    double lam = onto_one ? 1.0 : lambda + dlam, dl = dlam;

    // Step 4: corrector iterations.
    StepOutcome outcome = StepOutcome::kDiverged;
    int it = 0;
    double res = 0.0, first_res = 0.0, last_correction = HUGE_VAL;
    for (; it <= s.max_iterations_per_step; ++it) {
      problem.linearize(lam, R, F0, &K);
      res = R.norm() / load_norm;
      if (it == 0) first_res = res;
      record(step, lam, it, res);
      // Converged, or stalled at the round-off floor: a residual near the tolerance that the
      // last correction (a millionth of a micron of the model) can no longer reduce.
      if (res <= s.tolerance ||
          (res <= 100.0 * s.tolerance && last_correction <= 1e-12 * problem.lengthScale())) {
        outcome = StepOutcome::kConverged;
        break;
      }
      if (!std::isfinite(res) || res > 1e6 * std::max(first_res, 1.0)) break;
      if (it == s.max_iterations_per_step) break;
      if (!lu.factorize(K) || !lu.solve(R, uII)) {
        outcome = StepOutcome::kSingular;
        break;
      }
      double dlam_i = 0.0;
      Eigen::VectorXd delta;
      if (fixed_lambda) {
        delta = uII;
      } else {
        if (!lu.solve(F0, uI)) {
          outcome = StepOutcome::kSingular;
          break;
        }
        const double f = std::sqrt(d.squaredNorm() + dl * dl) - arc;  // eq. (19)
        dlam_i = -(f * (f + arc) + d.dot(uII)) / (dl + d.dot(uI));     // eq. (21)
        delta = dlam_i * uI + uII;                                     // eq. (22)
      }
      if (!delta.allFinite() || delta.lpNorm<Eigen::Infinity>() > 10.0 * problem.lengthScale()) {
        outcome = StepOutcome::kSingular;
        break;
      }
      last_correction = delta.lpNorm<Eigen::Infinity>();
      problem.increment(delta);  // step 4.5
      lam += dlam_i;             // step 4.6
      d += delta;
      dl += dlam_i;
    }
    out.iterations += it;

    if (outcome == StepOutcome::kConverged && !fixed_lambda && lam > 1.0) {
      // The arc overshot lambda = 1: redo the step under load control onto 1.
      problem.restore();
      final_step = true;
      continue;
    }
    if (outcome == StepOutcome::kConverged) {
      problem.save();
      lambda = lam;
      ++out.load_steps;
      out.residual = res;
      // Eq. (20): gamma_n = N_p / N_{n-1}, applied cumulatively to the arc length and bounded to
      // [1/2, 2] so that one easy step cannot throw the next one far past a limit point.
      const double gamma = std::clamp(static_cast<double>(s.target_iterations) /
                                          std::max(it, 1),
                                      0.5, 2.0);
      arc *= gamma;
      load_step = std::min(load_step * gamma, s.max_load_increment);
      continue;
    }
    // Divergence (step 4.1): back to the last converged state with half the arc length.
    problem.restore();
    final_step = false;
    ++out.cutbacks;
    arc *= 0.5;
    load_step *= 0.5;
    if (out.cutbacks > s.max_cutbacks) {
      std::ostringstream msg;
      msg << "no convergence after " << s.max_cutbacks << " arc-length cutbacks at load factor "
          << lambda << " (last residual " << res << ")";
      if (outcome == StepOutcome::kSingular)
        msg << "; the tangent became singular or the increment ran away: the garment may have "
               "a rigid-body mode (free to slide or spin); clamp, pin or fix components";
      out.status = msg.str();
      break;
    }
  }
  out.lambda = lambda;
  out.converged = lambda >= 1.0;
  if (out.converged)
    out.status = "converged: load factor 1 reached in " + std::to_string(out.load_steps) +
                 " load steps, " + std::to_string(out.iterations) + " iterations";
  return out;
}

}  // namespace chs
