#include "cloth_hair_sim/core/solver/banded_cholesky.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace chs {

bool BandedCholesky::factorize(const SymmetricBandMatrix& a, double shift) {
  n_ = a.size();
  kd_ = a.bandwidth();
  band_ = a.band();
  const std::size_t ld = static_cast<std::size_t>(kd_) + 1;
  for (int j = 0; j < n_; ++j) band_[j * ld] += shift;
  // Column by column (right-looking): L_jj = sqrt(a_jj), the column below it divided by L_jj,
  // then the trailing band less the column's outer product.
  for (int j = 0; j < n_; ++j) {
    double* col = &band_[j * ld];
    if (!(col[0] > 0.0) || !std::isfinite(col[0])) return factorized_ = false;
    const double d = std::sqrt(col[0]);
    col[0] = d;
    const int m = std::min(kd_, n_ - 1 - j);
    for (int i = 1; i <= m; ++i) col[i] /= d;
    for (int k = 1; k <= m; ++k) {
      double* next = &band_[(j + k) * ld];  // column j + k, from its diagonal
      const double lk = col[k];
      for (int i = k; i <= m; ++i) next[i - k] -= col[i] * lk;
    }
  }
  return factorized_ = true;
}

Eigen::VectorXd BandedCholesky::solve(const Eigen::VectorXd& b) const {
  if (!factorized_ || b.size() != n_)
    throw std::logic_error("BandedCholesky::solve without a factorisation of that size");
  const std::size_t ld = static_cast<std::size_t>(kd_) + 1;
  Eigen::VectorXd x = b;
  for (int j = 0; j < n_; ++j) {  // L y = b
    const double* col = &band_[j * ld];
    x[j] /= col[0];
    const int m = std::min(kd_, n_ - 1 - j);
    for (int i = 1; i <= m; ++i) x[j + i] -= col[i] * x[j];
  }
  for (int j = n_ - 1; j >= 0; --j) {  // L^T x = y
    const double* col = &band_[j * ld];
    const int m = std::min(kd_, n_ - 1 - j);
    double s = x[j];
    for (int i = 1; i <= m; ++i) s -= col[i] * x[j + i];
    x[j] = s / col[0];
  }
  return x;
}

}  // namespace chs
