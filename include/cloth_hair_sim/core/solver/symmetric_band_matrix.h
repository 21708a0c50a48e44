#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace chs {

// A symmetric n x n matrix whose entries vanish beyond kd of the diagonal, its lower band kept
// column by column as LAPACK keeps it (entry (r, c), c <= r <= c + kd, at c (kd + 1) + r - c):
// a strand's Newton matrix (discrete_elastic_rod.h), assembled in place where a list of
// triplets cost more than the factorisation (solver/banded_cholesky.h).
class SymmetricBandMatrix {
 public:
  SymmetricBandMatrix() = default;
  SymmetricBandMatrix(int n, int kd) { reset(n, kd); }

  // Zero, of size n and half-bandwidth kd (at most n - 1).
  void reset(int n, int kd);
  int size() const { return n_; }
  int bandwidth() const { return kd_; }

  // Adds v to entry (r, c) when r >= c and so to its mirror (c, r); skips entries above the
  // diagonal, so that a caller adding both triangles of a symmetric matrix adds each pair once.
  // An entry beyond the band is a caller's error (std::logic_error).
  void add(int r, int c, double v) {
    if (r >= c) lower(r, c) += v;
  }
  // Adds the symmetric m x m matrix b at rows and columns first .. first + m - 1 (its lower
  // half, column by column along the band's storage).
  template <typename Derived>
  void addDiagonalBlock(int first, const Eigen::MatrixBase<Derived>& b) {
    const int m = static_cast<int>(b.rows());
    if (first < 0 || first + m > n_ || m - 1 > kd_) outsideBand(first + m - 1, first);
    for (int c = 0; c < m; ++c) {
      double* column = &band_[static_cast<std::size_t>(first + c) * (kd_ + 1)];
      for (int r = c; r < m; ++r) column[r - c] += b(r, c);
    }
  }
  // Sums the 3 x 3 block of rows r.. and columns c.. (its part on or below the diagonal).
  void addBlock(int r, int c, const Eigen::Matrix3d& b);
  // Entry (r, c) with r >= c.
  double& lower(int r, int c) {
    if (c < 0 || r < c || r - c > kd_ || r >= n_) outsideBand(r, c);
    return band_[static_cast<std::size_t>(c) * (kd_ + 1) + (r - c)];
  }
  double lower(int r, int c) const { return const_cast<SymmetricBandMatrix*>(this)->lower(r, c); }
  // Row and column k zero, its diagonal 1: unknown k held (its increment solves to zero).
  void hold(int k);
  double maxDiagonal() const;
  Eigen::MatrixXd dense() const;
  const std::vector<double>& band() const { return band_; }

 private:
  [[noreturn]] void outsideBand(int r, int c) const;

  int n_ = 0, kd_ = 0;
  std::vector<double> band_;
};

}  // namespace chs
