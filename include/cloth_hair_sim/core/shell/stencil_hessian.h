#pragma once
#include <vector>

#include "cloth_hair_sim/core/shell/kirchhoff_love_hessian.h"
#include "cloth_hair_sim/core/subdiv/surface_stencil.h"

namespace chs {

// The Newton matrix's share of one face: its fibres' Hessians in the five stencil sums
// (kirchhoff_love_hessian.h) taken to the S control points that all of them share,
//   K = sum_f (C_f (x) I_3)^T H_f (C_f (x) I_3),
// C_f the 5 x S weights (du, dv, duu, duv, dvv) of fibre f's stencil. K is symmetric, so only its
// six component pairs (i, j), i <= j, are formed, each S x S over (k, l): block (k, l) of K is
//   K_kl(i, j) = pair(i, j)[k][l] for i <= j,   K_kl(i, j) = pair(j, i)[l][k] for i > j.
// The fibres' sums run inside the product (over f and the sum index), which keeps each output
// row in registers: the form of a small matrix product, not of 3 x 3 blocks. On processors
// with AVX2 and FMA a build of the kernel for them is chosen at run time (GCC's
// target_clones); the default build runs anywhere. With it the towel's Newton matrix took 0.75-0.8
// of the assembly time of the 3 x 3 block sums it replaced (docs/BENCHMARKS.md, 2026-12-07).
class StencilHessian {
 public:
  // Clears the sum for a face of s stencil points.
  void reset(int s);
  // Adds fibre f's Hessian H in its sums over the stencil's weights.
  void add(const SurfaceStencil& stencil, const FibreHessian& H);
  // Adds w w^T (x) A: a 3 x 3 Hessian A at the stencil's position x = sum_k w_k x_k.
  void addAtPosition(const SurfaceStencil& stencil, const Eigen::Matrix3d& A);
  // Forms the sum of the fibres added since reset().
  void finish();
  // Block (k, l) of K, after finish().
  Eigen::Matrix3d block(int k, int l) const;
  int size() const { return s_; }

 private:
  int s_ = 0, fibres_ = 0;
  std::vector<double> weights_;   // per fibre added: 5 rows of s (du, dv, duu, duv, dvv)
  std::vector<double> hessians_;  // per fibre added: H, 225 entries column-major
  std::vector<double> pairs_;  // six s x s matrices, pair (0,0), (0,1), (0,2), (1,1), (1,2), (2,2)
  std::vector<double> scratch_;
};

}  // namespace chs
