#include "cloth_hair_sim/core/solver/stability.h"

#include <algorithm>
#include <cmath>

#include <Spectra/SymEigsShiftSolver.h>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include "cloth_hair_sim/core/common/blas_threads.h"

namespace chs {

namespace {

// (S - sigma I)^-1 for Spectra's shift-invert mode. A positive definite S - sigma I (a stable
// drape at sigma = 0) is factorised by CHOLMOD's supernodal LL^T, whose dense kernels make it
// several times faster than the simplicial LDL^T on a drape's tangent (the check was 6 % of the
// 48 x 48 pedestal's drape, the LDL^T nearly all of it); its success is the inertia (no negative
// eigenvalue). Where it fails, the simplicial LDL^T, which takes an indefinite S, gives the
// solves and counts the negative pivots.
class ShiftInvert {
 public:
  using Scalar = double;
  explicit ShiftInvert(const Eigen::SparseMatrix<double>& S) : S_(S) {
    llt_.cholmod().print = 0;  // a failure is an answer here (not positive definite)
  }
  Eigen::Index rows() const { return S_.rows(); }
  Eigen::Index cols() const { return S_.cols(); }
  void set_shift(double sigma) {
    Eigen::SparseMatrix<double> I(S_.rows(), S_.cols());
    I.setIdentity();
    const Eigen::SparseMatrix<double> A = S_ - sigma * I;
    {
      const InlineOpenMpRegions serial;
      llt_.compute(A);
    }
    definite_ = llt_.info() == Eigen::Success;
    if (definite_) {
      negative_ = 0;
      factored_ = true;
      return;
    }
    ldlt_.compute(A);
    factored_ = ldlt_.info() == Eigen::Success;
    negative_ = factored_ ? static_cast<int>((ldlt_.vectorD().array() < 0.0).count()) : 0;
  }
  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Map<const Eigen::VectorXd> x(x_in, S_.rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, S_.rows());
    if (definite_)
      y = llt_.solve(x);
    else
      y = ldlt_.solve(x);
  }
  bool factored() const { return factored_; }
  int negativeEigenvalues() const { return negative_; }

 private:
  const Eigen::SparseMatrix<double>& S_;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool definite_ = false, factored_ = false;
  int negative_ = 0;
};

}  // namespace

StabilityCheck checkStability(const Eigen::SparseMatrix<double>& K) {
  StabilityCheck out;
  const Eigen::Index n = K.rows();
  if (n == 0) {
    out.computed = out.stable = true;
    out.lowest_eigenvalue = HUGE_VAL;
    return out;
  }
  Eigen::SparseMatrix<double> S = 0.5 * (K + Eigen::SparseMatrix<double>(K.transpose()));
  Eigen::VectorXd scale = S.diagonal().cwiseAbs();
  for (Eigen::Index i = 0; i < n; ++i) scale[i] = scale[i] > 0.0 ? 1.0 / std::sqrt(scale[i]) : 1.0;
  S = scale.asDiagonal() * S * scale.asDiagonal();

  ShiftInvert op(S);
  op.set_shift(0.0);
  if (!op.factored()) return out;  // exactly singular: neither verdict
  out.negative_eigenvalues = op.negativeEigenvalues();
  if (n == 1) {
    out.lowest_eigenvalue = S.coeff(0, 0);
    out.mode = Eigen::VectorXd::Ones(1);
  } else {
    const Eigen::Index nev = std::min<Eigen::Index>(n - 1, out.negative_eigenvalues + 2);
    const Eigen::Index ncv = std::min<Eigen::Index>(n, std::max<Eigen::Index>(2 * nev + 1, 20));
    Spectra::SymEigsShiftSolver<ShiftInvert> eigs(op, nev, ncv, 0.0);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
    if (eigs.info() != Spectra::CompInfo::Successful) return out;
    // Sorted ascending: the first is the lowest found.
    out.lowest_eigenvalue = eigs.eigenvalues()[0];
    out.mode = scale.asDiagonal() * eigs.eigenvectors().col(0);
    if (out.negative_eigenvalues > 0 && out.lowest_eigenvalue >= 0.0) {
      // The inertia counts a negative eigenvalue that the eigenvalues nearest zero do not hold
      // (a cluster of tiny positive ones around a folding sheet's mode). Bracket the lowest by
      // inertia, S - sigma I without a negative pivot for the first sigma = -1e-10, -1e-9, ...,
      // so that it lies in [sigma, sigma / 10): the eigenvalue nearest sigma is the lowest.
      for (double sigma = -1e-10; sigma >= -10.0; sigma *= 10.0) {
        ShiftInvert below(S);
        below.set_shift(sigma);
        if (!below.factored() || below.negativeEigenvalues() > 0) continue;
        Spectra::SymEigsShiftSolver<ShiftInvert> lowest(below, 1, std::min<Eigen::Index>(n, 20),
                                                        sigma);
        lowest.init();
        lowest.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10,
                       Spectra::SortRule::SmallestAlge);
        if (lowest.info() == Spectra::CompInfo::Successful) {
          out.lowest_eigenvalue = lowest.eigenvalues()[0];
          out.mode = scale.asDiagonal() * lowest.eigenvectors().col(0);
        }
        break;
      }
    }
  }
  out.computed = true;
  out.stable = out.negative_eigenvalues == 0 && out.lowest_eigenvalue > 0.0;
  return out;
}

}  // namespace chs
