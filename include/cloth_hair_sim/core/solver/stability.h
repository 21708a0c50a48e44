#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace chs {

// Stability of an equilibrium from its constrained tangent stiffness K (free unknowns only):
// stable when the symmetric part K_s = (K + K^T) / 2 is positive definite, i.e. when the second
// variation of the potential energy is positive for every admissible perturbation (Koiter's
// energy criterion). K_s is first scaled to unit diagonal, S = D^-1/2 K_s D^-1/2, a congruence:
// by Sylvester's law of inertia S has as many negative eigenvalues as K_s, and its eigenvalues
// are dimensionless although the unknowns mix translations and director rotations.
struct StabilityCheck {
  double lowest_eigenvalue = 0.0;  // of S; eigenvalues are counted, see negative_eigenvalues
  int negative_eigenvalues = 0;    // inertia of S (= of K_s) from its LDL^T factorisation
  bool stable = false;             // negative_eigenvalues == 0 and lowest_eigenvalue > 0
  bool computed = false;           // false: the eigenvalue solver failed (status says why)
  Eigen::VectorXd mode;            // eigenvector of lowest_eigenvalue in the unknowns of K
};

// Lowest eigenvalue by shift-invert Lanczos (Spectra's SymEigsShiftSolver, shift 0, solves with
// the LDL^T factorisation that also gives the inertia). The eigenvalues nearest zero are the
// ones that decide stability; with negative eigenvalues, the lowest of those found is reported.
StabilityCheck checkStability(const Eigen::SparseMatrix<double>& K);

}  // namespace chs
