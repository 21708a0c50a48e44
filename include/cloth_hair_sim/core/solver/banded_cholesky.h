#pragma once

#include <vector>

#include <Eigen/Core>

#include "cloth_hair_sim/core/solver/symmetric_band_matrix.h"

namespace chs {

// Cholesky factorisation L L^T of a symmetric positive definite band matrix: a strand's Newton
// matrix (discrete_elastic_rod.h: each vertex's bending couples the unknowns of two edges
// around it, half-bandwidth 10) costs O(n kd^2) and no symbolic analysis, where a general
// sparse LDL^T spent most of its time on ordering and copying.
//
// Written out rather than LAPACK's dpbtrf / dpbtrs, which this replaced: at kd = 10 and a
// hundred unknowns their unblocked path makes a BLAS call per column (dsyr, dscal, daxpy), and
// those calls, not the arithmetic, were a fifth of a strand's Newton iteration.
class BandedCholesky {
 public:
  // Factorises a + shift I. False, and nothing to solve with, when it is not positive definite
  // (a pivot that is not positive).
  bool factorize(const SymmetricBandMatrix& a, double shift = 0.0);
  // A^-1 b with the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  int n_ = 0, kd_ = 0;
  std::vector<double> band_;  // L's lower band, laid out as SymmetricBandMatrix's
  bool factorized_ = false;
};

}  // namespace chs
