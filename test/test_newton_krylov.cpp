// The Jacobian-free Newton-GMRES solver against systems with known roots: a non-symmetric
// nonlinear system (the case Han section 5.7 warns about), a residual that turns non-finite,
// and bad settings.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/solver/newton_krylov.h"

namespace chs {
namespace {

// r(x) = A x + c x^3 (componentwise) - b with A non-symmetric (an upwind difference operator
// plus a diagonal), built so that x* = (1, 2, ..., n) / n is the root.
struct CubicSystem {
  int n = 40;
  Eigen::MatrixXd A;
  Eigen::VectorXd x_star, b;
  double c = 2.0;
  CubicSystem() {
    A = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      A(i, i) = 3.0 + 0.1 * i;
      if (i > 0) A(i, i - 1) = -1.5;  // upwind: no matching (i - 1, i) entry
      if (i + 2 < n) A(i, i + 2) = 0.4;
    }
    x_star = Eigen::VectorXd::LinSpaced(n, 1.0, n) / n;
    b = A * x_star + c * x_star.array().cube().matrix();
  }
  void operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    r = A * x + c * x.array().cube().matrix() - b;
  }
};

TEST(NewtonKrylov, SolvesNonSymmetricNonlinearSystem) {
  const CubicSystem sys;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.n);
  NewtonKrylovSettings s;
  s.tolerance = 1e-10;
  s.krylov_tolerance = 1e-4;
  s.max_krylov_iterations = sys.n;
  const NewtonKrylovResult r =
      solveNewtonKrylov(std::cref(sys), Eigen::VectorXd(sys.A.diagonal()), x, s);
  const double error = (x - sys.x_star).norm() / sys.x_star.norm();
  std::printf("[figure] non-symmetric cubic system, n = %d: %s; relative error of x %.2e\n", sys.n,
              r.describe().c_str(), error);
  EXPECT_TRUE(r.converged());
  EXPECT_LE(r.newton_iterations, 8);  // Newton converges fast from x = 0 on this system
  EXPECT_LT(error, 1e-9);
}

TEST(NewtonKrylov, NonFiniteResidualKeepsTheLastGoodIterate) {
  const CubicSystem sys;
  // The residual is NaN where some |x_k| > 2 (a state the model cannot evaluate); starting
  // there, the solver reports it and leaves x untouched.
  auto residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    sys(x, r);
    if (x.cwiseAbs().maxCoeff() > 2.0) r(0) = std::numeric_limits<double>::quiet_NaN();
  };
  Eigen::VectorXd x = Eigen::VectorXd::Constant(sys.n, 3.0);
  const NewtonKrylovResult r =
      solveNewtonKrylov(residual, Eigen::VectorXd::Ones(sys.n), x, NewtonKrylovSettings{});
  EXPECT_EQ(r.status, NewtonKrylovStatus::kNonFinite);
  EXPECT_EQ(x, Eigen::VectorXd::Constant(sys.n, 3.0));
  std::printf("[figure] non-finite start: %s\n", r.describe().c_str());
}

TEST(NewtonKrylov, RejectsNonsense) {
  const CubicSystem sys;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.n);
  EXPECT_THROW(solveNewtonKrylov(std::cref(sys), Eigen::VectorXd::Zero(sys.n), x, {}), InputError);
  EXPECT_THROW(solveNewtonKrylov(std::cref(sys), Eigen::VectorXd::Ones(3), x, {}), InputError);
  NewtonKrylovSettings s;
  s.krylov_tolerance = 1.0;
  EXPECT_THROW(solveNewtonKrylov(std::cref(sys), Eigen::VectorXd::Ones(sys.n), x, s), InputError);
}

}  // namespace
}  // namespace chs
