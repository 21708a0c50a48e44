#include "cloth_hair_sim/core/solver/permuted_cholesky.h"

#include <limits>
#include <utility>

#include <Eigen/CholmodSupport>

#include "cloth_hair_sim/core/common/blas_threads.h"

namespace chs {

using Lower = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;

namespace {

// Analyses a pattern with one ordering at a time and reads the factor's permutation, which
// Eigen's wrapper keeps protected.
struct OrderingProbe : Lower {
  std::vector<int> fewestFlops(const Eigen::SparseMatrix<double>& pattern) {
    cholmod().print = 0;
    cholmod().nmethods = 1;
    std::vector<int> best;
    double best_flops = std::numeric_limits<double>::infinity();
    const auto perm = [this] {
      const int* p = static_cast<const int*>(m_cholmodFactor->Perm);
      return std::vector<int>(p, p + m_cholmodFactor->n);
    };
    for (int ordering : {CHOLMOD_AMD, CHOLMOD_METIS, CHOLMOD_NESDIS}) {
      cholmod().method[0].ordering = ordering;
      analyzePattern(pattern);
      // (A CHOLMOD built without METIS refuses the last two.)
      if (!m_cholmodFactor || cholmod().status != CHOLMOD_OK || !(cholmod().fl < best_flops))
        continue;
      best_flops = cholmod().fl;
      best = perm();
    }
    if (best.empty()) {  // CHOLMOD's own choice
      cholmod().nmethods = 0;
      analyzePattern(pattern);
      best = perm();
    }
    return best;
  }
};

}  // namespace

std::vector<int> fewestFlopsOrder(const Eigen::SparseMatrix<double>& symmetric) {
  return OrderingProbe().fewestFlops(symmetric);
}

struct PermutedCholesky::Llt : Lower {
  // A failed factorisation can be expected (a Hessian that is not positive definite): no
  // CHOLMOD warning on stderr.
  Llt() {
    cholmod().print = 0;
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = CHOLMOD_NATURAL;
    cholmod().postorder = 0;  // the order given is postordered already
  }
};

PermutedCholesky::PermutedCholesky(std::vector<int> order)
    : order_(std::move(order)), llt_(std::make_unique<Llt>()) {
  holdBlasToOneThread();
}

PermutedCholesky::~PermutedCholesky() = default;

Eigen::SparseMatrix<double> PermutedCholesky::permutedLower(const Eigen::SparseMatrix<double>& A,
                                                            std::vector<int>& slot) const {
  const int n = static_cast<int>(order_.size());
  std::vector<int> position(n);  // of each row of A in the factorised order
  for (int k = 0; k < n; ++k) position[order_[k]] = k;
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<int> entry;  // A's value index of each triplet
  for (int c = 0; c < A.outerSize(); ++c)
    for (int i = A.outerIndexPtr()[c]; i < A.outerIndexPtr()[c + 1]; ++i) {
      const int r = A.innerIndexPtr()[i];
      if (r > c) continue;
      const int pr = position[r], pc = position[c];
      triplets.emplace_back(std::max(pr, pc), std::min(pr, pc), 0.0);
      entry.push_back(i);
    }
  Eigen::SparseMatrix<double> M(n, n);
  M.setFromTriplets(triplets.begin(), triplets.end());
  slot.assign(A.nonZeros(), -1);
  for (std::size_t t = 0; t < triplets.size(); ++t)
    slot[entry[t]] =
        static_cast<int>(&M.coeffRef(triplets[t].row(), triplets[t].col()) - M.valuePtr());
  return M;
}

bool PermutedCholesky::factorize(const Eigen::SparseMatrix<double>& M) {
  const InlineOpenMpRegions serial;
  if (!analyzed_) {
    llt_->analyzePattern(M);
    analyzed_ = true;
  }
  llt_->factorize(M);
  return llt_->info() == Eigen::Success;
}

Eigen::VectorXd PermutedCholesky::solve(const Eigen::VectorXd& b) const {
  const int n = static_cast<int>(order_.size());
  Eigen::VectorXd bp(n), x(n);
  for (int k = 0; k < n; ++k) bp(k) = b(order_[k]);
  const Eigen::VectorXd y = llt_->solve(bp);
  for (int k = 0; k < n; ++k) x(order_[k]) = y(k);
  return x;
}

}  // namespace chs
