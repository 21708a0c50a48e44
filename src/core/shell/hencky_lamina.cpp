#include "cloth_hair_sim/core/shell/hencky_lamina.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

// QR of F in the reference frame, Han (A.3): F e_j = r_ij q_i, r upper triangular. q_3 = q_1 x q_2
// is the deformed lamina normal; for Kirchhoff-Love F, r_13 = r_23 = 0 and r_33 = 1.
struct LaminaQR {
  Eigen::Matrix3d q;  // columns q_1, q_2, q_3
  Eigen::Matrix3d r;
};

LaminaQR laminaQR(const Eigen::Matrix3d& F, const Eigen::Matrix3d& frame) {
  const Eigen::Matrix3d c = F * frame;
  LaminaQR qr;
  qr.r.setZero();
  qr.r(0, 0) = c.col(0).norm();
  qr.q.col(0) = c.col(0) / qr.r(0, 0);
  qr.r(0, 1) = qr.q.col(0).dot(c.col(1));
  const Eigen::Vector3d w = c.col(1) - qr.r(0, 1) * qr.q.col(0);
  qr.r(1, 1) = w.norm();
  qr.q.col(1) = w / qr.r(1, 1);
  qr.q.col(2) = qr.q.col(0).cross(qr.q.col(1));
  for (int i = 0; i < 3; ++i) qr.r(i, 2) = qr.q.col(i).dot(c.col(2));
  return qr;
}

// Closed-form spectral calculus of a symmetric positive definite 2x2 tensor B (C_hat or r r^T):
// eigenvalues l1 >= l2 and functions f(B) = mean(f) I + f[l1, l2] (B - m I) with m = tr B / 2 and
// the divided difference f[l1, l2] = (f(l1) - f(l2)) / (l1 - l2), which has the eigenvalues and
// eigenvectors of f applied to B. The divided differences are written through
// r = (l1 - l2) / l2 so that they stay exact as B becomes isotropic (r -> 0), where an unstretched
// cloth lives; no eigenvectors (no angle, no iterative solver) are needed.
struct Spectrum2 {
  double l1, l2;      // eigenvalues, l1 >= l2
  double d, b;        // B - m I = [[d, b], [b, -d]]
  double half_gap;    // (l1 - l2) / 2
  double log1, log2;  // log l1, log l2
  double log_ratio;   // log(1 + r) / r, the divided difference log[l1, l2] times l2
};

Spectrum2 spectrum(const Eigen::Matrix2d& B) {
  Spectrum2 s;
  const double m = 0.5 * (B(0, 0) + B(1, 1));
  s.d = 0.5 * (B(0, 0) - B(1, 1));
  s.b = 0.5 * (B(0, 1) + B(1, 0));
  s.half_gap = std::hypot(s.d, s.b);
  s.l1 = m + s.half_gap;
  s.l2 = (B(0, 0) * B(1, 1) - s.b * s.b) / s.l1;  // det / l1: no cancellation in m - half_gap
  s.log1 = std::log(s.l1);
  s.log2 = std::log(s.l2);
  const double r = 2.0 * s.half_gap / s.l2;
  // Taylor series of log(1 + r) / r below 1e-4: its truncation error r^4 / 5 is below 2e-17.
  s.log_ratio = r < 1e-4 ? 1.0 - r * (0.5 - r * (1.0 / 3.0 - 0.25 * r)) : std::log1p(r) / r;
  return s;
}

// mean I + slope (B - m I) as a matrix.
Eigen::Matrix2d spectralFunction(const Spectrum2& s, double mean, double slope) {
  Eigen::Matrix2d f;
  f << mean + slope * s.d, slope * s.b, slope * s.b, mean - slope * s.d;
  return f;
}

// psi of Han (5.11) in the principal Hencky strains eps_i = 1/2 log l_i.
double henckyEnergy(const Spectrum2& s, double mu, double lambda) {
  const double e1 = 0.5 * s.log1, e2 = 0.5 * s.log2, trace = e1 + e2;
  return mu * (e1 * e1 + e2 * e2) + 0.5 * lambda * trace * trace;
}

// 2 dpsi/dC_hat = C_hat^{-1} (2 mu eps + lambda tr eps I) = g(C_hat) with
// g(l) = mu log(l) / l + K / l, K = lambda tr eps. (log l / l)[l1, l2] = (log[l1, l2] - log l2 /
// l2) / l1 and (1 / l)[l1, l2] = -1 / (l1 l2).
Eigen::Matrix2d henckySecondPiola(const Spectrum2& s, double mu, double lambda) {
  const double K = 0.5 * lambda * (s.log1 + s.log2);
  const double g1 = (mu * s.log1 + K) / s.l1, g2 = (mu * s.log2 + K) / s.l2;
  const double slope = (mu * (s.log_ratio - s.log2) - K) / (s.l1 * s.l2);
  return spectralFunction(s, 0.5 * (g1 + g2), slope);
}

// d^2 psi / dc^2 of Han (5.11) in c = (C_11, C_22, C_12) of C = C_hat, given S = henckySecondPiola.
// S = C^{-1} T with T = mu log C + K I commuting with C, so dS = C^{-1} (dT - dC S) with
// dT = mu dlog C + lambda dA I. log C = A I + B D with A = log(det C) / 2, B = log[l1, l2],
// D = C - m I (D^2 = h^2 I, h = half_gap); through dm = tr dC / 2, dD = dC - dm I and
// dh = D : dC / (2 h):
//   dlog C = dA I + dB D + B dD,  dA = tr(C^{-1} dC) / 2,  dB = -dm / (l1 l2) + kappa D : dC,
// kappa = (m / (l1 l2) - B) / (2 h^2) (the h-derivative of B over 2h). Its two terms cancel to
// O(t^2), t = h / m, as C becomes isotropic (the cloth at rest): there kappa takes the series
// m^-3 sum_{k >= 1} k / (2k + 1) t^(2k - 2) (from log[l1, l2] = atanh(t) / h), whose first 8
// terms are exact to 1e-16 for t < 0.1, where the cancelling form has lost at most ~2e-14.
Eigen::Matrix3d henckyHessian(const Spectrum2& s, const Eigen::Matrix2d& C,
                              const Eigen::Matrix2d& S, double mu, double lambda) {
  const double m = 0.5 * (s.l1 + s.l2), det = s.l1 * s.l2, t = s.half_gap / m;
  const double B = s.log_ratio / s.l2;
  double kappa;
  if (t < 0.1) {
    double series = 0.0;
    for (int k = 8; k >= 1; --k) series = k / (2.0 * k + 1.0) + t * t * series;
    kappa = series / (m * m * m);
  } else {
    kappa = (m / det - B) / (2.0 * s.half_gap * s.half_gap);
  }
  Eigen::Matrix2d C_inv, D;
  C_inv << C(1, 1), -s.b, -s.b, C(0, 0);
  C_inv /= det;
  D << s.d, s.b, s.b, -s.d;
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  Eigen::Matrix3d H;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix2d dC = Eigen::Matrix2d::Zero();  // the derivative of C in c_k
    if (k < 2) {
      dC(k, k) = 1.0;
    } else {
      dC(0, 1) = dC(1, 0) = 1.0;
    }
    const double dm = 0.5 * dC.trace(), dA = 0.5 * C_inv.cwiseProduct(dC).sum();
    const double dB = -dm / det + kappa * D.cwiseProduct(dC).sum();
    const Eigen::Matrix2d dlog = (dA - B * dm) * I + dB * D + B * dC;
    const Eigen::Matrix2d dS = C_inv * (mu * dlog + lambda * dA * I - dC * S);
    H.col(k) << 0.5 * dS(0, 0), 0.5 * dS(1, 1), 0.5 * (dS(0, 1) + dS(1, 0));  // of dpsi/dc
  }
  return 0.5 * (H + H.transpose());
}

// Hencky stress tau = 2 mu eps + lambda tr(eps) I = mu log B + K I of a stretch tensor B.
Eigen::Matrix2d henckyKirchhoff(const Spectrum2& s, double mu, double lambda) {
  const double K = 0.5 * lambda * (s.log1 + s.log2);
  return spectralFunction(s, 0.5 * mu * (s.log1 + s.log2) + K, mu * s.log_ratio / s.l2);
}

// Closed-form SVD of a 2x2 matrix, M = U diag(sigma) V^T with U, V rotations (Blinn, "Consider
// the lowly 2x2 matrix"); sigma_2 < 0 only if det M < 0, which the QR factor r_hat never has.
struct Svd2 {
  Eigen::Matrix2d U, V;
  Eigen::Vector2d sigma;
};

Svd2 svd2(const Eigen::Matrix2d& M) {
  const double e = 0.5 * (M(0, 0) + M(1, 1)), f = 0.5 * (M(0, 0) - M(1, 1));
  const double g = 0.5 * (M(1, 0) + M(0, 1)), h = 0.5 * (M(1, 0) - M(0, 1));
  const double q = std::hypot(e, h), r = std::hypot(f, g);
  const double a1 = std::atan2(g, f), a2 = std::atan2(h, e);
  const double phi = 0.5 * (a2 + a1), theta = 0.5 * (a2 - a1);
  Svd2 s;
  s.sigma = Eigen::Vector2d(q + r, q - r);
  s.U << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
  s.V << std::cos(theta), std::sin(theta), -std::sin(theta), std::cos(theta);  // Rot(theta)^T
  return s;
}

}  // namespace

HenckyLamina::HenckyLamina(double youngs_modulus, double poisson_ratio, double yield_stress)
    : E_(youngs_modulus), nu_(poisson_ratio), c_vm_(yield_stress) {
  if (!std::isfinite(E_) || E_ <= 0.0)
    throw InputError("HenckyLamina: Young's modulus must be positive and finite, got " +
                     std::to_string(E_));
  // Plane-stress stability needs mu > 0 and mu + lambda = E / (2 (1 - nu)) > 0, i.e. -1 < nu < 1;
  // an isotropic solid further has nu <= 1/2.
  if (!std::isfinite(nu_) || nu_ <= -1.0 || nu_ > 0.5)
    throw InputError("HenckyLamina: Poisson ratio must lie in (-1, 0.5], got " +
                     std::to_string(nu_));
  if (std::isnan(c_vm_) || c_vm_ <= 0.0)
    throw InputError(
        "HenckyLamina: von Mises yield stress must be positive (infinity = purely elastic), got " +
        std::to_string(c_vm_));
  mu_ = E_ / (2.0 * (1.0 + nu_));
  lambda_ = E_ * nu_ / (1.0 - nu_ * nu_);
}

double HenckyLamina::bendingStiffness(double thickness) const {
  return E_ * thickness * thickness * thickness / (12.0 * (1.0 - nu_ * nu_));
}

double HenckyLamina::energyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& frame) const {
  const Eigen::Matrix<double, 3, 2> lamina = F * frame.leftCols<2>();
  return henckyEnergy(spectrum(lamina.transpose() * lamina), mu_, lambda_);  // Han (5.11)
}

HenckyLamina::LaminaResponse HenckyLamina::laminaResponse(const Eigen::Matrix2d& C_hat,
                                                          Eigen::Matrix3d* hessian) const {
  const Spectrum2 s = spectrum(C_hat);
  const LaminaResponse r{henckyEnergy(s, mu_, lambda_), henckySecondPiola(s, mu_, lambda_)};
  if (hessian) *hessian = henckyHessian(s, C_hat, r.second_piola, mu_, lambda_);
  return r;
}

Eigen::Matrix3d HenckyLamina::firstPiolaStress(const Eigen::Matrix3d& F,
                                               const Eigen::Matrix3d& frame) const {
  const Eigen::Matrix<double, 3, 2> E_hat = frame.leftCols<2>();
  const Eigen::Matrix<double, 3, 2> lamina = F * E_hat;
  // psi depends on F only through C_hat = E^T F^T F E, so P = F E (2 dpsi/dC_hat) E^T.
  const Eigen::Matrix2d S = henckySecondPiola(spectrum(lamina.transpose() * lamina), mu_, lambda_);
  return lamina * S * E_hat.transpose();
}

Eigen::Matrix3d HenckyLamina::kirchhoffStress(const Eigen::Matrix3d& F,
                                              const Eigen::Matrix3d& frame) const {
  const LaminaQR qr = laminaQR(F, frame);
  const Eigen::Matrix2d r_hat = qr.r.topLeftCorner<2, 2>();
  const Eigen::Matrix2d tau_hat =
      henckyKirchhoff(spectrum(r_hat * r_hat.transpose()), mu_, lambda_);  // (5.12), eps^L
  const Eigen::Matrix<double, 3, 2> q_hat = qr.q.leftCols<2>();
  return q_hat * tau_hat * q_hat.transpose();
}

Eigen::Vector2d HenckyLamina::principalStress(const Eigen::Vector2d& log_stretch) const {
  return 2.0 * mu_ * log_stretch + Eigen::Vector2d::Constant(lambda_ * log_stretch.sum());
}

Eigen::Vector2d HenckyLamina::principalLogStretch(const Eigen::Vector2d& principal_stress) const {
  // Inverse of A = 2 mu I + lambda 1 1^T on the axes (1,1) (eigenvalue 2 (mu + lambda)) and
  // (1,-1) (eigenvalue 2 mu).
  const double mean = 0.5 * principal_stress.sum() / (2.0 * (mu_ + lambda_));
  const double half_diff = 0.5 * (principal_stress(0) - principal_stress(1)) / (2.0 * mu_);
  return Eigen::Vector2d(mean + half_diff, mean - half_diff);
}

double HenckyLamina::vonMises(const Eigen::Vector2d& t) {
  return std::sqrt(2.0 / 3.0 * (t(0) * t(0) + t(1) * t(1) - t(0) * t(1)));  // (5.14), tau_3 = 0
}

Eigen::Vector2d HenckyLamina::projectPrincipalStress(const Eigen::Vector2d& trial) const {
  const double f_trial = vonMises(trial);
  if (isElastic() || f_trial <= c_vm_) return trial;
  // On the axes s = (t1 + t2)/sqrt2, d = (t1 - t2)/sqrt2: f^2 = s^2/3 + d^2 and A = diag(2 (mu +
  // lambda), 2 mu), so tau = tau_tr - kappa A grad(f^2) gives s = s0 / (1 + a kappa), d = d0 /
  // (1 + b kappa). Solve f(kappa) = c_vM through 1/f, which is nearly linear in kappa, by
  // bracketed Newton.
  const double s0 = (trial(0) + trial(1)) / std::sqrt(2.0);
  const double d0 = (trial(0) - trial(1)) / std::sqrt(2.0);
  const double a = 4.0 * (mu_ + lambda_) / 3.0, b = 4.0 * mu_;
  auto state = [&](double kappa, double& inv_f, double& dinv_f) {
    const double s = s0 / (1.0 + a * kappa), d = d0 / (1.0 + b * kappa);
    const double f2 = s * s / 3.0 + d * d;
    const double df2 =
        -2.0 * a * s * s / (3.0 * (1.0 + a * kappa)) - 2.0 * b * d * d / (1.0 + b * kappa);
    inv_f = 1.0 / std::sqrt(f2);
    dinv_f = -0.5 * inv_f / f2 * df2;
  };
  const double target = 1.0 / c_vm_;
  double lo = 0.0, hi = (f_trial / c_vm_ - 1.0) / std::min(a, b);  // f <= f_trial/(1+min(a,b)k)
  double kappa = 0.0;
  for (int it = 0; it < 200; ++it) {
    double g, dg;
    state(kappa, g, dg);
    const double residual = g - target;
    if (std::abs(residual) <= 1e-15 * target) break;
    (residual < 0.0 ? lo : hi) = kappa;
    double next = kappa - residual / dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == kappa) break;
    kappa = next;
  }
  const double s = s0 / (1.0 + a * kappa), d = d0 / (1.0 + b * kappa);
  return Eigen::Vector2d(s + d, s - d) / std::sqrt(2.0);
}

HenckyLamina::DentingReturn HenckyLamina::returnMapping(const Eigen::Matrix3d& F_elastic_trial,
                                                        const Eigen::Matrix3d& frame) const {
  DentingReturn result;
  const LaminaQR qr = laminaQR(F_elastic_trial, frame);
  const Eigen::Matrix2d r_hat = qr.r.topLeftCorner<2, 2>();
  const Svd2 svd = svd2(r_hat);  // (5.18)
  result.trial_stress = principalStress(svd.sigma.array().log().matrix());
  result.stress = projectPrincipalStress(result.trial_stress);
  result.yielded = result.stress != result.trial_stress;
  if (!result.yielded) {
    result.elastic_deformation = F_elastic_trial;
    return result;
  }
  const Eigen::Vector2d sigma = principalLogStretch(result.stress).array().exp();  // (5.19)
  Eigen::Matrix3d r = qr.r;
  r.topLeftCorner<2, 2>() = svd.U * sigma.asDiagonal() * svd.V.transpose();  // (5.20)
  result.elastic_deformation = qr.q * r * frame.transpose();
  return result;
}

}  // namespace chs
