#include "cloth_hair_sim/core/shell/stencil_hessian.h"

#include <algorithm>

namespace chs {
namespace {

constexpr int kPairI[6] = {0, 0, 0, 1, 1, 2};
constexpr int kPairJ[6] = {0, 1, 2, 1, 2, 2};

int pairIndex(int i, int j) {  // i <= j
  return i == 0 ? j : (i == 1 ? 2 + j : 5);
}

// pairs[p][k][l] += sum_f sum_b U_f[p][b][k] C_f[b][l], U_f[p][b][k] = sum_a C_f[a][k] H_f(3a+i,
// 3b+j) for pair p = (i, j). S > 0: the stencil size known at compile time, so that a row
// stays in registers; S = 0: any size s.
template <int S>
__attribute__((target_clones("arch=x86-64-v3", "default"))) void sumFibres(
    int s_runtime, int fibres, const double* weights, const double* hessians, double* pairs,
    double* u) {
  const int s = S > 0 ? S : s_runtime;
  for (int f = 0; f < fibres; ++f) {
    const double* c = weights + 5 * s * f;
    const double* H = hessians + 225 * f;
    for (int p = 0; p < 6; ++p)
      for (int b = 0; b < 5; ++b) {
        const double* column = H + 15 * (3 * b + kPairJ[p]) + kPairI[p];
        const double h0 = column[0], h1 = column[3], h2 = column[6], h3 = column[9],
                     h4 = column[12];
        double* out = u + ((f * 6 + p) * 5 + b) * s;
        for (int k = 0; k < s; ++k)
          out[k] =
              h0 * c[k] + h1 * c[s + k] + h2 * c[2 * s + k] + h3 * c[3 * s + k] + h4 * c[4 * s + k];
      }
  }
  for (int p = 0; p < 6; ++p)
    for (int k = 0; k < s; ++k) {
      double* out = pairs + (p * s + k) * s;
      double row[S > 0 ? S : 1];
      double* acc = S > 0 ? row : out;
      if (S > 0) std::copy(out, out + s, acc);
      for (int f = 0; f < fibres; ++f) {
        const double* c = weights + 5 * s * f;
        for (int b = 0; b < 5; ++b) {
          const double ub = u[((f * 6 + p) * 5 + b) * s + k];
          const double* cb = c + b * s;
          for (int l = 0; l < s; ++l) acc[l] += ub * cb[l];
        }
      }
      if (S > 0) std::copy(acc, acc + s, out);
    }
}

}  // namespace

void StencilHessian::reset(int s) {
  s_ = s;
  fibres_ = 0;
  weights_.clear();
  hessians_.clear();
  pairs_.assign(6 * static_cast<std::size_t>(s) * s, 0.0);
}

void StencilHessian::add(const SurfaceStencil& st, const FibreHessian& H) {
  for (const std::vector<double>* c : {&st.du, &st.dv, &st.duu, &st.duv, &st.dvv})
    weights_.insert(weights_.end(), c->begin(), c->end());
  hessians_.insert(hessians_.end(), H.data(), H.data() + 225);
  ++fibres_;
}

void StencilHessian::addAtPosition(const SurfaceStencil& st, const Eigen::Matrix3d& A) {
  for (int p = 0; p < 6; ++p) {
    const double a = A(kPairI[p], kPairJ[p]);
    for (int k = 0; k < s_; ++k)
      for (int l = 0; l < s_; ++l) pairs_[(p * s_ + k) * s_ + l] += a * st.w[k] * st.w[l];
  }
}

void StencilHessian::finish() {
  if (fibres_ == 0) return;
  scratch_.resize(30 * static_cast<std::size_t>(fibres_) * s_);
  // A regular face's stencil, a boundary face's and a corner face's (ghost points elsewhere).
  auto sum = s_ == 16   ? sumFibres<16>
             : s_ == 12 ? sumFibres<12>
             : s_ == 9  ? sumFibres<9>
                        : sumFibres<0>;
  sum(s_, fibres_, weights_.data(), hessians_.data(), pairs_.data(), scratch_.data());
  fibres_ = 0;
  weights_.clear();
  hessians_.clear();
}

Eigen::Matrix3d StencilHessian::block(int k, int l) const {
  Eigen::Matrix3d B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      B(i, j) = i <= j ? pairs_[(pairIndex(i, j) * s_ + k) * s_ + l]
                       : pairs_[(pairIndex(j, i) * s_ + l) * s_ + k];
  return B;
}

}  // namespace chs
