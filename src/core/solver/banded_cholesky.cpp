#include "cloth_hair_sim/core/solver/banded_cholesky.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

// LAPACK (Fortran): the trailing arguments are the hidden lengths of the character arguments.
extern "C" {
void dpbtrf_(const char* uplo, const int* n, const int* kd, double* ab, const int* ldab, int* info,
             std::size_t uplo_length);
void dpbtrs_(const char* uplo, const int* n, const int* kd, const int* nrhs, const double* ab,
             const int* ldab, double* b, const int* ldb, int* info, std::size_t uplo_length);
}

namespace chs {

bool BandedCholesky::factorize(int n, const std::vector<Eigen::Triplet<double>>& entries,
                               double shift) {
  factorized_ = false;
  n_ = n;
  kd_ = 0;
  for (const auto& t : entries)
    if (t.row() >= t.col()) kd_ = std::max(kd_, t.row() - t.col());
  const int ld = kd_ + 1;
  band_.assign(static_cast<std::size_t>(ld) * n, 0.0);
  for (const auto& t : entries)
    if (t.row() >= t.col())
      band_[static_cast<std::size_t>(t.col()) * ld + (t.row() - t.col())] += t.value();
  max_diagonal_ = 0.0;
  for (int j = 0; j < n; ++j) {
    double& d = band_[static_cast<std::size_t>(j) * ld];
    max_diagonal_ = std::max(max_diagonal_, d);
    d += shift;
  }
  if (n == 0) return factorized_ = true;
  int info = 0;
  dpbtrf_("L", &n_, &kd_, band_.data(), &ld, &info, 1);
  factorized_ = info == 0;
  return factorized_;
}

Eigen::VectorXd BandedCholesky::solve(const Eigen::VectorXd& b) const {
  if (!factorized_ || b.size() != n_)
    throw std::logic_error("BandedCholesky::solve without a factorisation of that size");
  Eigen::VectorXd x = b;
  if (n_ == 0) return x;
  const int ld = kd_ + 1, nrhs = 1;
  int info = 0;
  dpbtrs_("L", &n_, &kd_, &nrhs, band_.data(), &ld, x.data(), &n_, &info, 1);
  if (info != 0) throw std::logic_error("BandedCholesky::solve: dpbtrs failed");
  return x;
}

}  // namespace chs
