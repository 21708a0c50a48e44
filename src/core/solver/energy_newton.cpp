#include "cloth_hair_sim/core/solver/energy_newton.h"

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "cloth_hair_sim/core/solver/permuted_cholesky.h"

namespace chs {

namespace {

constexpr double kArmijo = 1e-4;
constexpr double kMinStep = 1e-8;
constexpr double kMinShift = 1e-8, kMaxShift = 1e6;
constexpr double kNearSaddle = 1e-3;  // relative residual
constexpr int kProbeInterval = 10;

// Modified Hessian H = K_s + mu |diag(K_s)| (Levenberg-Marquardt's scaling, so mu is
// dimensionless), factorised by CHOLMOD's supernodal Cholesky in the fill-reducing order with the
// fewest flops (the 48 x 48 pedestal: NESDIS, 237 MFlop per factorisation where CHOLMOD's own
// choice, AMD, needs 283); the pattern is analysed once.
class ModifiedHessian {
 public:
  // Factorises with the smallest mu (from the last one, lowered) for which H is positive
  // definite; false if even mu = kMaxShift fails.
  bool factorize(const Eigen::SparseMatrix<double>& K) {
    // A problem with a potential has a symmetric tangent (ShellElement's, the penalty's): its
    // upper triangle is K_s, copied into the lower triangle of P H P^T that CHOLMOD factorises.
    if (!cholesky_) {
      const Eigen::SparseMatrix<double> pattern = K.selfadjointView<Eigen::Upper>();
      cholesky_ = std::make_unique<PermutedCholesky>(fewestFlopsOrder(pattern));
      H_ = cholesky_->permutedLower(K, slot_);
      for (int c = 0; c < K.outerSize(); ++c)
        for (int i = K.outerIndexPtr()[c]; i < K.outerIndexPtr()[c + 1]; ++i)
          if (K.innerIndexPtr()[i] == c) diagonal_.push_back(slot_[i]);
    }
    double* h = H_.valuePtr();
    const double* k = K.valuePtr();
    for (Eigen::Index i = 0; i < K.nonZeros(); ++i)
      if (slot_[i] >= 0) h[slot_[i]] = k[i];
    diag_.resize(static_cast<Eigen::Index>(diagonal_.size()));
    for (std::size_t i = 0; i < diagonal_.size(); ++i) diag_[i] = h[diagonal_[i]];
    mu_ = mu_ < 10.0 * kMinShift ? 0.0 : 0.1 * mu_;
    for (;;) {
      for (std::size_t i = 0; i < diagonal_.size(); ++i)
        h[diagonal_[i]] = diag_[i] + mu_ * std::abs(diag_[i]);
      if (cholesky_->factorize(H_)) return true;
      if (mu_ >= kMaxShift) return false;
      mu_ = mu_ == 0.0 ? kMinShift : 10.0 * mu_;
    }
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return cholesky_->solve(b); }
  double shift() const { return mu_; }

 private:
  std::unique_ptr<PermutedCholesky> cholesky_;
  Eigen::SparseMatrix<double> H_;  // the lower triangle of P H P^T
  std::vector<int> slot_;          // of each of K's values in H_ (-1: below the diagonal)
  std::vector<int> diagonal_;      // H_'s diagonal entries, in K's order
  Eigen::VectorXd diag_;           // K_s's diagonal, unshifted
  double mu_ = 0.0;
};

}  // namespace

EnergyNewtonResult solveEnergyNewton(ContinuationProblem& p, const EnergyNewtonSettings& s,
                                     const ProgressCallback& progress) {
  EnergyNewtonResult out;
  out.load_steps = 1;
  out.lambda = 1.0;
  const double lambda = 1.0, load = p.loadNorm();
  Eigen::VectorXd R, F0, d, Rt;
  Eigen::SparseMatrix<double> K;
  p.save();
  p.linearize(lambda, R, F0, &K);
  double E = p.energy(lambda);
  if (!std::isfinite(E)) {
    out.status =
        "the problem has no potential energy (Kawabata bending or nodal moments): use "
        "the arc-length solver";
    return out;
  }
  if (!(load > 0.0)) {
    out.converged = true;
    out.status = "no load: the reference state is the solution";
    return out;
  }
  ModifiedHessian hessian;
  int it = 0;
  bool floor = false;  // stalled at the round-off floor, within 100 times the tolerance
  int next_probe = 0;  // the first iteration that may look for a saddle nearby
  for (;; ++it) {
    out.residual = R.norm() / load;
    ProgressEvent e{1, lambda, it, out.residual, p.activeContacts(), it};
    out.history.push_back(e);
    if (progress) progress(e);
    if (cancelRequested(s.cancel)) {
      out.cancelled = true;
      out.status = "cancelled after " + std::to_string(it) +
                   " Newton iterations; returning the last accepted iterate";
      break;
    }
    const bool equilibrium = out.residual <= s.tolerance || floor;
    // Near a saddle already: the last Hessian needed a shift and the residual is small. The
    // shifted Newton step leaves a saddle along its negative mode by a factor of about two per
    // iteration (the tablecloth: 25 iterations from a residual of 6e-6 to 0.1): leave it along
    // the mode at once instead. Probed at most every kProbeInterval iterations.
    const bool near_saddle = !equilibrium && hessian.shift() > 0.0 && out.residual <= kNearSaddle &&
                             it >= next_probe && out.saddle_escapes < s.max_saddle_escapes;
    if (equilibrium || near_saddle) {
      floor = false;
      out.stability = checkStability(K);
      const bool saddle = out.stability.computed && !out.stability.stable;
      if (equilibrium && !saddle) {
        out.converged = out.stability.computed;
        break;
      }
      if (equilibrium && out.saddle_escapes == s.max_saddle_escapes) break;
      next_probe = it + kProbeInterval;
      if (!saddle) out.stability = StabilityCheck();  // only an equilibrium's is reported
    }
    if (equilibrium || (near_saddle && out.stability.computed && !out.stability.stable)) {
      // Leave the saddle along its lowest mode: E(q + b v) - E(q) = b^2 lambda_min v.Dv / 2 < 0
      // for small b. The sign is fixed (largest component positive) so the run is reproducible;
      // the step starts at the model's trust bound and is halved while that lowers the energy
      // further: the lowest of the trials is taken (the first that merely lowers it can be a
      // tiny step, from which Newton creeps away again at the negative mode's slow rate).
      Eigen::VectorXd v = out.stability.mode;
      Eigen::Index k;
      v.cwiseAbs().maxCoeff(&k);
      if (v[k] < 0.0) v = -v;
      const double b = p.stepBound(1e6 * v / v.norm()) * 1e6 / v.norm();
      double best_t = 0.0, best_E = E - 1e-14 * std::abs(E);
      for (int sign : {1, -1}) {
        for (double t = b; t > 1e-6 * b; t *= 0.5) {
          p.increment(sign * t * v);
          const double Et = p.energy(lambda);
          p.restore();
          if (Et < best_E) {
            best_E = Et;
            best_t = sign * t;
          } else if (best_t * sign > 0.0) {
            break;  // past the best along this direction
          }
        }
        if (best_t != 0.0) break;
      }
      const bool left = best_t != 0.0;
      if (left) p.increment(best_t * v);
      ++out.saddle_escapes;
      out.stability = StabilityCheck();
      if (left) {
        p.save();
        p.linearize(lambda, R, F0, &K);
        E = p.energy(lambda);
        continue;
      }
      if (equilibrium) break;  // else Newton goes on from where it was
    }
    if (it == s.max_iterations) break;
    if (!hessian.factorize(K)) {
      out.status =
          "the modified Hessian could not be factorised: the problem may have a "
          "rigid-body mode";
      break;
    }
    d = hessian.solve(R);
    if (!d.allFinite()) {
      out.status = "non-finite Newton step";
      break;
    }
    d *= p.stepBound(d);
    const double slope = -R.dot(d);  // dE/dalpha at alpha = 0, < 0 for a positive definite H
    double alpha = 1.0;
    bool accepted = false;
    for (; alpha >= kMinStep; alpha *= 0.5) {
      p.increment(alpha * d);
      const double Et = p.energy(lambda);
      // Armijo; failing that, a fall of the residual norm (the penalty's potential is
      // integrated by quadrature, so near the solution, and where the energy's round-off hides
      // the decrease, its gradient and R agree only to the quadrature error).
      if (std::isfinite(Et) && Et <= E + kArmijo * alpha * slope) {
        E = Et;
        accepted = true;
        break;
      }
      if (std::isfinite(Et)) {
        p.linearize(lambda, Rt, F0, nullptr);
        if (Rt.norm() <= (1.0 - kArmijo * alpha) * R.norm()) {
          E = Et;
          accepted = true;
          break;
        }
      }
      p.restore();
    }
    if (!accepted && out.residual <= 100.0 * s.tolerance) {
      floor = true;
      continue;
    }
    if (!accepted) {
      out.status = "the line search found no lower energy along the Newton direction";
      break;
    }
    p.save();
    p.linearize(lambda, R, F0, &K);
  }
  out.iterations = it;
  if (!out.status.empty() || out.cancelled) return out;
  std::ostringstream msg;
  if (out.converged) {
    msg << "converged to a stable equilibrium in " << it << " Newton iterations";
    if (out.saddle_escapes > 0)
      msg << " (" << out.saddle_escapes << " saddles left along their lowest mode)";
  } else if (out.residual <= 100.0 * s.tolerance && !out.stability.computed) {
    msg << "equilibrium found in " << it << " iterations, but its stability could not be computed";
  } else if (out.residual <= 100.0 * s.tolerance) {
    msg << "unstable equilibrium (saddle, lowest eigenvalue " << out.stability.lowest_eigenvalue
        << ") after " << out.saddle_escapes << " attempts to leave it";
  } else {
    msg << "no convergence in " << it << " Newton iterations (residual " << out.residual << ")";
  }
  out.status = msg.str();
  return out;
}

}  // namespace chs
