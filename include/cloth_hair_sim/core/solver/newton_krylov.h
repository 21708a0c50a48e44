#pragma once
#include <functional>
#include <string>

#include <Eigen/Core>

namespace chs {

struct NewtonKrylovSettings {
  // Converged when the weighted residual norm sqrt(sum_k r_k^2 / d_k) (d: the diagonal handed
  // to the solver, e.g. the masses, which makes it a kinetic-energy norm) is <= tolerance.
  double tolerance = 1e-8;
  int max_newton_iterations = 10;
  int max_krylov_iterations = 60;  // GMRES iterations per Newton iteration
  int krylov_restart = 30;
  // GMRES stops at eta times its right-hand side: the forcing term of an inexact Newton method
  // (an exact linear solve is wasted far from the root). Adaptive: Eisenstat and Walker's choice
  // 2, eta from 0.5 down to krylov_tolerance as Newton converges, and no tighter than the
  // tolerance needs; otherwise eta = krylov_tolerance throughout.
  double krylov_tolerance = 1e-2;
  bool adaptive_forcing = true;
  double min_line_search_step = 1.0 / 64.0;
};

enum class NewtonKrylovStatus { kConverged, kMaxIterations, kLineSearchFailed, kNonFinite };

struct NewtonKrylovResult {
  NewtonKrylovStatus status = NewtonKrylovStatus::kMaxIterations;
  int newton_iterations = 0;
  int krylov_iterations = 0;      // summed over the Newton iterations
  int residual_evaluations = 0;   // each Jacobian product is one
  double initial_residual = 0.0;  // weighted norms, as for the tolerance
  double residual = 0.0;
  bool converged() const { return status == NewtonKrylovStatus::kConverged; }
  std::string describe() const;
};

// r(x) into r (sized by the callee). Evaluations at trial points may be non-finite; the solver
// then backtracks or stops with kNonFinite.
using ResidualFunction = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& r)>;

// Solves r(x) = 0 from the guess in x by Jacobian-free Newton-Krylov (Knoll and Keyes, J. Comput.
// Phys. 193, 2004): each Newton system J dx = -r is solved by Eigen's restarted GMRES, with the
// Jacobian products J d taken as forward differences of r. GMRES and not conjugate gradients
// because the Jacobian of an elastoplastic or frictional force is not symmetric when its return
// mapping stays inside the solve (Han section 5.7). `diagonal` (positive) preconditions GMRES and
// weights the norm. A backtracking line search keeps the weighted norm of r decreasing. x is left
// at the last accepted iterate: the guess itself if no step was accepted.
NewtonKrylovResult solveNewtonKrylov(const ResidualFunction& residual,
                                     const Eigen::VectorXd& diagonal, Eigen::VectorXd& x,
                                     const NewtonKrylovSettings& settings);

}  // namespace chs
