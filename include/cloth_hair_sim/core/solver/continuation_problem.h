#pragma once
#include <limits>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace chs {

// A discrete nonlinear static problem R(q, lambda) = 0 for the path-following solvers: the
// out-of-balance force R = lambda F(q) + F_c(q) - P(q) of seed 000 eqs. (17), (33).
class ContinuationProblem {
 public:
  virtual ~ContinuationProblem() = default;
  virtual int size() const = 0;
  // R at the current state, F0 = dR/dlambda (eq. (26)) and the tangent K = -dR/dq (eq. (25)
  // plus the penalty contact part (34)); K has a fixed sparsity pattern.
  virtual void linearize(double lambda, Eigen::VectorXd& R, Eigen::VectorXd& F0,
                         Eigen::SparseMatrix<double>* K) = 0;
  // q <- q (+) dq: translations add, directors follow the exponential map.
  virtual void increment(const Eigen::VectorXd& dq) = 0;
  // Keep / return to the last converged state.
  virtual void save() = 0;
  virtual void restore() = 0;
  // Norm of the full load (lambda = 1): the scale of relative residuals.
  virtual double loadNorm() const = 0;
  // Length scale of the model, to recognise a runaway increment.
  virtual double lengthScale() const = 0;
  virtual int activeContacts() const { return 0; }
  // Total potential energy at the current state and load factor, whose gradient is -R; NaN
  // when the forces have no potential (then only the path-following solver applies).
  virtual double energy(double /*lambda*/) { return std::numeric_limits<double>::quiet_NaN(); }
  // Factor in (0, 1] that brings an increment within the model's trust bounds (the energy
  // minimiser's far-field Newton step can be the huge linear response); 1 = no bound.
  virtual double stepBound(const Eigen::VectorXd& /*dq*/) const { return 1.0; }
  // Viscous stabilisation (see ArcLengthSettings::stabilization): adds -c m (x - x_anchor) to
  // R. save() also anchors; anchorHere() moves only the anchor. Without it the calls do nothing.
  virtual void setStabilization(double /*factor*/) {}
  virtual void anchorHere() {}
};

}  // namespace chs
