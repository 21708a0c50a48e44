#pragma once
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace chs {

// Cholesky factorisation of a symmetric positive definite band matrix by LAPACK's dpbtrf /
// dpbtrs: a strand's Newton matrix (discrete_elastic_rod.h: each vertex's bending couples the
// unknowns of two edges around it, half-bandwidth 10) costs O(n kd^2) and no symbolic analysis,
// where a general sparse LDL^T spent most of its time on ordering and copying.
class BandedCholesky {
 public:
  // The n x n matrix summed from `entries` (both triangles given, or the lower one: entries
  // above the diagonal are ignored), plus `shift` on the diagonal. False, and nothing to solve
  // with, when it is not positive definite (LAPACK's leading minor test).
  bool factorize(int n, const std::vector<Eigen::Triplet<double>>& entries, double shift = 0.0);
  // A^-1 b with the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  // The largest diagonal entry of the last matrix given (before the shift).
  double maxDiagonal() const { return max_diagonal_; }

 private:
  int n_ = 0, kd_ = 0;
  std::vector<double> band_;  // LAPACK's lower band storage, (kd + 1) x n, column-major
  double max_diagonal_ = 0.0;
  bool factorized_ = false;
};

}  // namespace chs
