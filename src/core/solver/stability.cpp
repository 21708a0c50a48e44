#include "cloth_hair_sim/core/solver/stability.h"

#include <algorithm>
#include <cmath>

#include <Spectra/SymEigsShiftSolver.h>
#include <Eigen/SparseCholesky>

namespace chs {

namespace {

// (S - sigma I)^-1 for Spectra's shift-invert mode, by a sparse LDL^T (S may be indefinite).
class ShiftInvertLdlt {
 public:
  using Scalar = double;
  explicit ShiftInvertLdlt(const Eigen::SparseMatrix<double>& S) : S_(S) {}
  Eigen::Index rows() const { return S_.rows(); }
  Eigen::Index cols() const { return S_.cols(); }
  void set_shift(double sigma) {
    Eigen::SparseMatrix<double> I(S_.rows(), S_.cols());
    I.setIdentity();
    ldlt_.compute(S_ - sigma * I);
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<Eigen::VectorXd>(y_out, S_.rows()) =
        ldlt_.solve(Eigen::Map<const Eigen::VectorXd>(x_in, S_.rows()));
  }
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt() const { return ldlt_; }

 private:
  const Eigen::SparseMatrix<double>& S_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
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

  ShiftInvertLdlt op(S);
  op.set_shift(0.0);
  if (op.ldlt().info() != Eigen::Success) return out;  // exactly singular: neither verdict
  out.negative_eigenvalues = static_cast<int>((op.ldlt().vectorD().array() < 0.0).count());
  if (n == 1) {
    out.lowest_eigenvalue = S.coeff(0, 0);
    out.mode = Eigen::VectorXd::Ones(1);
  } else {
    const Eigen::Index nev = std::min<Eigen::Index>(n - 1, out.negative_eigenvalues + 2);
    const Eigen::Index ncv = std::min<Eigen::Index>(n, std::max<Eigen::Index>(2 * nev + 1, 20));
    Spectra::SymEigsShiftSolver<ShiftInvertLdlt> eigs(op, nev, ncv, 0.0);
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
        ShiftInvertLdlt below(S);
        below.set_shift(sigma);
        if (below.ldlt().info() != Eigen::Success || (below.ldlt().vectorD().array() < 0.0).any())
          continue;
        Spectra::SymEigsShiftSolver<ShiftInvertLdlt> lowest(below, 1, std::min<Eigen::Index>(n, 20),
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
