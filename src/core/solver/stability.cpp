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
// solves and counts the negative pivots. Every shift has the pattern of S: both factorisations
// analyse it once (the analysis cost as much as a factorisation of the tablecloth's tangent).
class ShiftInvert {
 public:
  using Scalar = double;
  explicit ShiftInvert(const Eigen::SparseMatrix<double>& S) : S_(S), A_(S) {
    llt_.cholmod().print = 0;  // a failure is an answer here (not positive definite)
  }
  Eigen::Index rows() const { return S_.rows(); }
  Eigen::Index cols() const { return S_.cols(); }
  // Spectra's solvers set their shift themselves: a shift already factorised is kept.
  void set_shift(double sigma) {
    if (!(factored_ && sigma == sigma_)) factorize(sigma, true);
  }
  // Factorises S - sigma I; with `inertia` false an indefinite S - sigma I is only reported
  // (factored() false), not factorised again by the LDL^T to count its negative eigenvalues.
  void factorize(double sigma, bool inertia) {
    sigma_ = sigma;
    A_.diagonal() = S_.diagonal().array() - sigma;
    {
      const InlineOpenMpRegions serial;
      if (!llt_analyzed_) llt_.analyzePattern(A_);
      llt_analyzed_ = true;
      llt_.factorize(A_);
    }
    definite_ = llt_.info() == Eigen::Success;
    factored_ = definite_;
    negative_ = 0;
    if (definite_ || !inertia) return;
    if (!ldlt_analyzed_) ldlt_.analyzePattern(A_);
    ldlt_analyzed_ = true;
    ldlt_.factorize(A_);
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
  bool definite() const { return definite_; }
  int negativeEigenvalues() const { return negative_; }

 private:
  const Eigen::SparseMatrix<double>& S_;
  Eigen::SparseMatrix<double> A_;  // S - sigma I
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool llt_analyzed_ = false, ldlt_analyzed_ = false;
  bool definite_ = false, factored_ = false;
  double sigma_ = 0.0;
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
  // S = D^-1/2 K_s D^-1/2, scaled in place; the explicit zero diagonal keeps every diagonal
  // entry in the pattern, which the shifts write.
  Eigen::SparseMatrix<double> I(n, n);
  I.setIdentity();
  Eigen::SparseMatrix<double> S = 0.5 * (K + Eigen::SparseMatrix<double>(K.transpose())) + 0.0 * I;
  Eigen::VectorXd scale = S.diagonal().cwiseAbs();
  for (Eigen::Index i = 0; i < n; ++i) scale[i] = scale[i] > 0.0 ? 1.0 / std::sqrt(scale[i]) : 1.0;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(S, j); it; ++it)
      it.valueRef() *= scale[it.row()] * scale[j];

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
      // inertia, S - sigma I positive definite for the first sigma = -1e-10, -1e-9, ..., so
      // that it lies in [sigma, sigma / 10): the eigenvalue nearest sigma is the lowest. The
      // LL^T's success alone is that inertia: no LDL^T is needed on the way down.
      for (double sigma = -1e-10; sigma >= -10.0; sigma *= 10.0) {
        op.factorize(sigma, false);
        if (!op.definite()) continue;
        Spectra::SymEigsShiftSolver<ShiftInvert> lowest(op, 1, std::min<Eigen::Index>(n, 20),
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
