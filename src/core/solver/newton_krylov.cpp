#include "cloth_hair_sim/core/solver/newton_krylov.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/SparseCore>
#include <unsupported/Eigen/IterativeSolvers>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs::detail {
class JacobianOperator;
}  // namespace chs::detail

namespace Eigen::internal {
template <>
struct traits<chs::detail::JacobianOperator> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace chs::detail {

// The Jacobian of a residual function as a matrix-free operator for Eigen's iterative solvers
// (the "matrix-free solvers" pattern of Eigen's documentation): products are forward
// differences J d = (r(x + h d) - r(x)) / h.
class JacobianOperator : public Eigen::EigenBase<JacobianOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };

  JacobianOperator(const ResidualFunction& residual, const Eigen::VectorXd& x,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& diagonal, int& evaluations)
      : residual_(residual), x_(x), r_(r), diagonal_(diagonal), evaluations_(evaluations) {}

  Eigen::Index rows() const { return x_.size(); }
  Eigen::Index cols() const { return x_.size(); }
  const Eigen::VectorXd& diagonal() const { return diagonal_; }

  template <typename Rhs>
  Eigen::Product<JacobianOperator, Rhs, Eigen::AliasFreeProduct> operator*(
      const Eigen::MatrixBase<Rhs>& d) const {
    return Eigen::Product<JacobianOperator, Rhs, Eigen::AliasFreeProduct>(*this, d.derived());
  }

  void apply(const Eigen::VectorXd& d, Eigen::VectorXd& out) const {
    const double dn = d.norm();
    if (dn == 0.0) {
      out.setZero(d.size());
      return;
    }
    // The usual JFNK increment: sqrt(machine epsilon) relative to the size of x.
    const double h = std::sqrt(std::numeric_limits<double>::epsilon()) * (1.0 + x_.norm()) / dn;
    Eigen::VectorXd r;
    residual_(x_ + h * d, r);
    ++evaluations_;
    out = (r - r_) / h;
  }

 private:
  const ResidualFunction& residual_;
  const Eigen::VectorXd& x_;
  const Eigen::VectorXd& r_;
  const Eigen::VectorXd& diagonal_;
  int& evaluations_;
};

// Jacobi preconditioner from the diagonal the caller supplies (the operator has no entries).
class InverseDiagonal {
 public:
  InverseDiagonal() = default;
  template <typename M>
  InverseDiagonal& analyzePattern(const M&) {
    return *this;
  }
  template <typename M>
  InverseDiagonal& factorize(const M& m) {
    return compute(m);
  }
  template <typename M>
  InverseDiagonal& compute(const M& m) {
    inverse_ = m.diagonal().cwiseInverse();
    return *this;
  }
  template <typename Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    return inverse_.cwiseProduct(b);
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  Eigen::VectorXd inverse_;
};

}  // namespace chs::detail

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<chs::detail::JacobianOperator, Rhs, SparseShape, DenseShape,
                            GemvProduct>
    : generic_product_impl_base<chs::detail::JacobianOperator, Rhs,
                                generic_product_impl<chs::detail::JacobianOperator, Rhs>> {
  using Scalar = typename Product<chs::detail::JacobianOperator, Rhs>::Scalar;
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const chs::detail::JacobianOperator& lhs, const Rhs& rhs,
                            const Scalar& alpha) {
    Eigen::VectorXd y;
    lhs.apply(rhs, y);
    dst += alpha * y;
  }
};
}  // namespace Eigen::internal

namespace chs {
namespace {
constexpr double kLoosestForcing = 0.5;
}  // namespace

std::string NewtonKrylovResult::describe() const {
  static const char* names[] = {"converged", "iteration limit reached", "line search failed",
                                "non-finite residual"};
  char text[160];
  std::snprintf(text, sizeof text,
                "%s after %d Newton and %d GMRES iterations, residual %.3g (from %.3g)",
                names[static_cast<int>(status)], newton_iterations, krylov_iterations, residual,
                initial_residual);
  return text;
}

NewtonKrylovResult solveNewtonKrylov(const ResidualFunction& residual,
                                     const Eigen::VectorXd& diagonal, Eigen::VectorXd& x,
                                     const NewtonKrylovSettings& s) {
  if (diagonal.size() != x.size() || !(diagonal.array() > 0.0).all())
    throw InputError("Newton-Krylov: the diagonal must be positive and sized like the unknowns");
  if (!(s.tolerance >= 0.0) || s.max_newton_iterations < 0 || s.max_krylov_iterations < 1 ||
      s.krylov_restart < 1 || !(s.krylov_tolerance > 0.0 && s.krylov_tolerance < 1.0) ||
      !(s.min_line_search_step > 0.0 && s.min_line_search_step <= 1.0))
    throw InputError("Newton-Krylov: nonsensical settings");
  const Eigen::VectorXd weight = diagonal.cwiseInverse();
  auto norm = [&](const Eigen::VectorXd& r) { return std::sqrt(r.cwiseAbs2().dot(weight)); };

  NewtonKrylovResult result;
  Eigen::VectorXd r;
  residual(x, r);
  result.residual_evaluations = 1;
  result.initial_residual = result.residual = norm(r);
  if (!std::isfinite(result.residual)) {
    result.status = NewtonKrylovStatus::kNonFinite;
    return result;
  }
  Eigen::VectorXd dx, x_trial, r_trial;
  // The forcing term: fixed, or adaptive starting from its loosest value.
  double eta = s.adaptive_forcing ? kLoosestForcing : s.krylov_tolerance;
  double previous_residual = result.residual;
  while (true) {
    if (result.residual <= s.tolerance) {
      result.status = NewtonKrylovStatus::kConverged;
      return result;
    }
    if (result.newton_iterations == s.max_newton_iterations) {
      result.status = NewtonKrylovStatus::kMaxIterations;
      return result;
    }
    ++result.newton_iterations;
    int evaluations = 0;
    detail::JacobianOperator jacobian(residual, x, r, diagonal, evaluations);
    Eigen::GMRES<detail::JacobianOperator, detail::InverseDiagonal> gmres;
    gmres.set_restart(s.krylov_restart);
    gmres.setMaxIterations(s.max_krylov_iterations);
    if (s.adaptive_forcing) {
      // Eisenstat and Walker's choice 2 (SIAM J. Sci. Comput. 17, 1996): solve loosely while
      // Newton is far from the root, tighter as it converges, and never beyond what the
      // tolerance needs.
      if (result.newton_iterations > 1) {
        const double ratio = result.residual / previous_residual;
        const double safeguard = 0.9 * eta * eta;
        eta = 0.9 * ratio * ratio;
        if (safeguard > 0.1) eta = std::max(eta, safeguard);
      }
      eta = std::clamp(std::max(eta, 0.5 * s.tolerance / result.residual), s.krylov_tolerance,
                       kLoosestForcing);
    }
    previous_residual = result.residual;
    gmres.setTolerance(eta);
    gmres.compute(jacobian);
    dx = gmres.solve(-r);
    result.krylov_iterations += static_cast<int>(gmres.iterations());
    result.residual_evaluations += evaluations;
    // Backtracking on the weighted residual norm (Armijo with a small slope fraction).
    double step = 1.0;
    while (true) {
      x_trial = x + step * dx;
      residual(x_trial, r_trial);
      ++result.residual_evaluations;
      const double n = norm(r_trial);
      if (std::isfinite(n) && n <= (1.0 - 1e-4 * step) * result.residual) {
        x.swap(x_trial);
        r.swap(r_trial);
        result.residual = n;
        break;
      }
      step *= 0.5;
      if (step < s.min_line_search_step) {
        result.status = std::isfinite(n) ? NewtonKrylovStatus::kLineSearchFailed
                                         : NewtonKrylovStatus::kNonFinite;
        return result;
      }
    }
  }
}

}  // namespace chs
