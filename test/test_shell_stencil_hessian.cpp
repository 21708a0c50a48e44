// The face sum of the fibres' Hessians (shell/stencil_hessian.h) against the product it stands
// for, (C (x) I_3)^T H (C (x) I_3) summed over the fibres, formed densely: on a regular face's
// stencil (16 points), a boundary face's (12), a corner face's (9) and another size (the
// general path), with an obstacle's Hessian at the stencil's position.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/shell/stencil_hessian.h"

namespace chs {
namespace {

SurfaceStencil randomStencil(int s, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SurfaceStencil st;
  for (int k = 0; k < s; ++k) {
    st.points.push_back(k);
    for (std::vector<double>* c : {&st.w, &st.du, &st.dv, &st.duu, &st.duv, &st.dvv})
      c->push_back(u(rng));
  }
  return st;
}

// The 5 x s weights of a stencil taken to the 15 x 3s map of control positions to sums.
Eigen::MatrixXd sumMap(const SurfaceStencil& st) {
  const int s = st.size();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(15, 3 * s);
  const std::vector<double>* c[5] = {&st.du, &st.dv, &st.duu, &st.duv, &st.dvv};
  for (int a = 0; a < 5; ++a)
    for (int k = 0; k < s; ++k)
      for (int i = 0; i < 3; ++i) J(3 * a + i, 3 * k + i) = (*c[a])[k];
  return J;
}

class StencilHessianSizes : public ::testing::TestWithParam<int> {};

TEST_P(StencilHessianSizes, EqualsTheDenseSumOfTheFibresProducts) {
  const int s = GetParam();
  std::mt19937 rng(s);
  std::normal_distribution<double> normal;
  StencilHessian K;
  K.reset(s);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * s, 3 * s);
  for (int f = 0; f < 4; ++f) {
    SurfaceStencil st = randomStencil(s, rng);
    FibreHessian H = FibreHessian::NullaryExpr([&] { return normal(rng); });
    H = (H + H.transpose()).eval();  // a fibre's Hessian is symmetric, not definite
    const Eigen::MatrixXd J = sumMap(st);
    dense += J.transpose() * H * J;
    K.add(st, H);
    if (f == 2) {
      Eigen::Matrix3d A = Eigen::Matrix3d::NullaryExpr([&] { return normal(rng); });
      A = (A + A.transpose()).eval();
      K.addAtPosition(st, A);
      for (int k = 0; k < s; ++k)
        for (int l = 0; l < s; ++l) dense.block<3, 3>(3 * k, 3 * l) += st.w[k] * st.w[l] * A;
    }
  }
  K.finish();
  double error = 0.0;
  for (int k = 0; k < s; ++k)
    for (int l = 0; l < s; ++l)
      error =
          std::max(error, (K.block(k, l) - dense.block<3, 3>(3 * k, 3 * l)).cwiseAbs().maxCoeff());
  const double scale = dense.cwiseAbs().maxCoeff();
  std::printf("stencil of %d points: largest block error %.3g of entries up to %.3g\n", s, error,
              scale);
  EXPECT_LT(error, 1e-13 * scale);
}

INSTANTIATE_TEST_SUITE_P(RegularBoundaryCornerAndOther, StencilHessianSizes,
                         ::testing::Values(16, 12, 9, 7));

TEST(StencilHessian, ResetClearsTheLastFace) {
  std::mt19937 rng(1);
  StencilHessian K;
  K.reset(9);
  K.add(randomStencil(9, rng), FibreHessian::Identity());
  K.finish();
  K.reset(9);
  K.finish();
  for (int k = 0; k < 9; ++k)
    for (int l = 0; l < 9; ++l) EXPECT_EQ(K.block(k, l), Eigen::Matrix3d::Zero());
}

}  // namespace
}  // namespace chs
