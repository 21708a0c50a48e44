// CHOLMOD's OpenMP regions run inline on the calling thread while an InlineOpenMpRegions lives
// (common/blas_threads.h): the interposition must take in a program that links the core, and
// the factor must be the one libgomp's teams give.
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include "cloth_hair_sim/core/common/blas_threads.h"

namespace chs {
namespace {

// The 5-point Laplacian of an n x n grid plus the identity: SPD, with supernodes large enough
// for CHOLMOD's dense kernels.
Eigen::SparseMatrix<double> gridLaplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j) { return i * n + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      t.emplace_back(id(i, j), id(i, j), 5.0);
      if (i + 1 < n) {
        t.emplace_back(id(i, j), id(i + 1, j), -1.0);
        t.emplace_back(id(i + 1, j), id(i, j), -1.0);
      }
      if (j + 1 < n) {
        t.emplace_back(id(i, j), id(i, j + 1), -1.0);
        t.emplace_back(id(i, j + 1), id(i, j), -1.0);
      }
    }
  Eigen::SparseMatrix<double> A(n * n, n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::VectorXd solveWithCholmod(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b) {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt;
  llt.compute(A);
  EXPECT_EQ(llt.info(), Eigen::Success);
  return llt.solve(b);
}

TEST(InlineOpenMp, CholmodRegionsRunInlineWithTheSameFactor) {
  const Eigen::SparseMatrix<double> A = gridLaplacian(60);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const long before = inlinedOpenMpRegions();
  const Eigen::VectorXd teams = solveWithCholmod(A, b);
  EXPECT_EQ(inlinedOpenMpRegions(), before) << "regions ran inline without the guard";

  Eigen::VectorXd inline_x;
  {
    const InlineOpenMpRegions serial;
    inline_x = solveWithCholmod(A, b);
  }
  const long regions = inlinedOpenMpRegions() - before;
  const double residual = (A * inline_x - b).norm() / b.norm();
  const double difference = (inline_x - teams).cwiseAbs().maxCoeff();
  std::printf(
      "InlineOpenMp: %ld of CHOLMOD's parallel regions ran inline in one factorisation of "
      "%ld unknowns; relative residual %.2e, largest difference from libgomp's teams "
      "%.2e\n",
      regions, static_cast<long>(A.rows()), residual, difference);
  EXPECT_GT(regions, 0) << "libgomp's GOMP_parallel came first in the lookup order: the "
                           "interposition did not take";
  EXPECT_LT(residual, 1e-12);
  EXPECT_EQ(difference, 0.0);  // the regions clear and scatter maps: the same arithmetic

  const long after = inlinedOpenMpRegions();
  solveWithCholmod(A, b);
  EXPECT_EQ(inlinedOpenMpRegions(), after) << "the guard outlived its scope";
}

}  // namespace
}  // namespace chs
