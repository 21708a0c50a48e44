#pragma once
#include <memory>
#include <vector>

#include <Eigen/SparseCore>

namespace chs {

// The fill-reducing order of a symmetric pattern (its lower triangle is read) with the fewest
// flops of the factorisation, of the three CHOLMOD offers: AMD, METIS and NESDIS. Row k of the
// permuted matrix is row order[k] of the given one. CHOLMOD's own choice tries METIS only where
// AMD fills in much and then keeps the smaller factor: it kept AMD on the cloth dropped on the
// sphere (289 MFlop per factorisation, nested dissection 234) and on the drape's tablecloth
// (17.5 MFlop, NESDIS 13.0; docs/BENCHMARKS.md, 2026-12-08).
std::vector<int> fewestFlopsOrder(const Eigen::SparseMatrix<double>& symmetric);

// CHOLMOD's supernodal Cholesky of P A P^T, given as its lower triangle M in a fixed order (for
// instance fewestFlopsOrder's) and factorised in the natural order. Given any other triangle or
// order, CHOLMOD's supernodal factorisation first transposes the matrix once or twice
// (cholmod_transpose_sym: 4 % of the 48 x 48 pedestal's drape).
class PermutedCholesky {
 public:
  explicit PermutedCholesky(std::vector<int> order = {});
  ~PermutedCholesky();
  PermutedCholesky(const PermutedCholesky&) = delete;
  PermutedCholesky& operator=(const PermutedCholesky&) = delete;

  const std::vector<int>& order() const { return order_; }
  // The lower triangle of P A P^T with the pattern of A (row <= column entries are read; the
  // rest of A's pattern must mirror them). slot[i] is where A's stored value i goes in M, -1 for
  // an entry below the diagonal.
  Eigen::SparseMatrix<double> permutedLower(const Eigen::SparseMatrix<double>& A,
                                            std::vector<int>& slot) const;
  // Factorises M (its pattern analysed at the first call, and fixed from then on); false where
  // M is not positive definite. On one BLAS thread with CHOLMOD's OpenMP regions inline
  // (common/blas_threads.h).
  bool factorize(const Eigen::SparseMatrix<double>& M);
  // A^-1 b, in A's order.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  struct Llt;
  std::vector<int> order_;
  std::unique_ptr<Llt> llt_;
  bool analyzed_ = false;
};

}  // namespace chs
