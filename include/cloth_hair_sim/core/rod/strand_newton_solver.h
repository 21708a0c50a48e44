#pragma once
#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/rod/discrete_elastic_rod.h"
#include "cloth_hair_sim/core/rod/obstacle_contact.h"

namespace chs::rod {

// What acts on a strand besides its elasticity, as terms of one potential in its generalised
// coordinates q (discrete_elastic_rod.h):
//   Phi(q) = E(q) + 1 / (2 dt^2) (q - q~)^T M (q - q~) - sum_i m_i g . x_i - sum_i F_i . x_i
//            - M_tip phi_tip(q) + C(q),
// the incremental potential of backward Euler (Gast et al., IEEE TVCG 2015; its minimiser is the
// implicit step x^{n+1} with q~ = q^n + dt qdot^n) when dt > 0, the total potential energy of a
// static equilibrium when dt <= 0. phi_tip is the angle of the last edge about
// tip_moment_axis, so that M_tip is a dead end moment (a rod closed into a circle by
// M = 2 pi EI / L), and C the obstacles' normal penalty and lagged friction potential
// (obstacle_contact.h), if any. Held unknowns (a clamped root) keep the values they have in the
// rod.
struct StrandLoads {
  double dt = 0.0;                  // [s]; <= 0: static
  Eigen::VectorXd inertial_target;  // q~ (numDofs()), dynamic only
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> vertex_forces;  // F_i [N], one per vertex, or empty
  double tip_moment = 0.0;                     // M_tip [N m]
  Eigen::Vector3d tip_moment_axis = Eigen::Vector3d::UnitZ();
  std::vector<char> held;  // per unknown: 1 = held where the rod has it; empty: none held
  const ObstacleContact* obstacles = nullptr;  // C, or none
};

struct StrandNewtonSettings {
  // Converged when a full Newton step moves no vertex by more than tolerance times the mean
  // segment length and no angle by more than tolerance [rad], or when a full step of the true
  // Newton iteration stays within 0.1 sqrt(tolerance) so measured (quadratic convergence leaves
  // an error of the order of its square: the confirming iteration is skipped).
  double tolerance = 1e-9;
  int max_iterations = 30;
};

struct StrandNewtonResult {
  bool converged = false;
  int iterations = 0;
  double step = 0.0;  // the last Newton step's size, relative as in the tolerance
  // dPhi/dq at the end on the held unknowns (zero elsewhere; empty when none is held): the
  // generalised force the holding applies to the strand there (N on a position, N m about the
  // edge on an angle), the held vertices' own weight and acceleration included.
  Eigen::VectorXd held_reaction;
};

// Newton's method with the banded Hessian of Phi, assembled in place (the true one, or its
// Gauss-Newton form where the true one is not positive definite and on the first iteration:
// DiscreteElasticRod::addElasticDerivatives), factored by a band Cholesky (shifted when
// singular: solver/banded_cholesky.h), and a backtracking (Armijo)
// line search on Phi that also refuses configurations where the energy is not defined. The rod
// ends at the last accepted iterate, committed: its reference frames are transported from
// iterate to iterate, so that each Newton step's gradient (taken at a committed configuration)
// is the derivative of the potential its line search measures. tip_angle: the tip angle phi_tip of
// the rod's configuration on entry (for a tip moment), updated to the end configuration's. Throws
// InputError for loads whose sizes do not match the rod.
StrandNewtonResult solveStrand(DiscreteElasticRod& rod, const StrandLoads& loads,
                               const StrandNewtonSettings& settings = {},
                               double* tip_angle = nullptr);

}  // namespace chs::rod
