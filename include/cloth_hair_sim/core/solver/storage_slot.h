#pragma once
#include <algorithm>

#include <Eigen/SparseCore>

namespace chs {

// Position of entry (r, c) in a compressed column-major matrix's value array, for assembling
// into a fixed sparsity pattern; -1 for a held row or column (r or c < 0). The entry must be in
// the pattern.
inline int storageSlot(const Eigen::SparseMatrix<double>& m, int r, int c) {
  if (r < 0 || c < 0) return -1;
  const int* rows = m.innerIndexPtr();
  const int begin = m.outerIndexPtr()[c], end = m.outerIndexPtr()[c + 1];
  return static_cast<int>(std::lower_bound(rows + begin, rows + end, r) - rows);
}

}  // namespace chs
