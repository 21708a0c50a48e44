#include "cloth_hair_sim/core/solver/symmetric_band_matrix.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace chs {

void SymmetricBandMatrix::reset(int n, int kd) {
  if (n < 0 || kd < 0 || (n > 0 && kd > n - 1))
    throw std::logic_error("SymmetricBandMatrix: size " + std::to_string(n) + " with bandwidth " +
                           std::to_string(kd));
  n_ = n;
  kd_ = kd;
  band_.assign(static_cast<std::size_t>(kd + 1) * n, 0.0);
}

void SymmetricBandMatrix::outsideBand(int r, int c) const {
  throw std::logic_error("SymmetricBandMatrix: entry (" + std::to_string(r) + ", " +
                         std::to_string(c) + ") outside the lower band of half-width " +
                         std::to_string(kd_) + " of a matrix of size " + std::to_string(n_));
}

void SymmetricBandMatrix::addBlock(int r, int c, const Eigen::Matrix3d& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) add(r + i, c + j, b(i, j));
}

void SymmetricBandMatrix::hold(int k) {
  for (int r = k; r <= std::min(n_ - 1, k + kd_); ++r) lower(r, k) = 0.0;
  for (int c = std::max(0, k - kd_); c < k; ++c) lower(k, c) = 0.0;
  lower(k, k) = 1.0;
}

double SymmetricBandMatrix::maxDiagonal() const {
  double m = 0.0;
  for (int j = 0; j < n_; ++j) m = std::max(m, band_[static_cast<std::size_t>(j) * (kd_ + 1)]);
  return m;
}

Eigen::MatrixXd SymmetricBandMatrix::dense() const {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n_, n_);
  for (int c = 0; c < n_; ++c)
    for (int r = c; r <= std::min(n_ - 1, c + kd_); ++r) a(r, c) = a(c, r) = lower(r, c);
  return a;
}

}  // namespace chs
