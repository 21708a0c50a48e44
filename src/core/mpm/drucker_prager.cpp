#include "cloth_hair_sim/core/mpm/drucker_prager.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mpm/rotation_svd.h"

namespace chs::mpm {

DruckerPrager::DruckerPrager(const HenckySolid& material, double friction_coefficient)
    : material_(material), c_f_(friction_coefficient) {
  if (!(c_f_ >= 0.0 && std::isfinite(c_f_)))
    throw InputError("Drucker-Prager: friction coefficient must be >= 0 and finite, got " +
                     std::to_string(c_f_));
  const double s = std::sin(std::atan(c_f_));
  alpha_ = std::sqrt(2.0 / 3.0) * 2.0 * s / (3.0 - s);
}

Eigen::Matrix3d DruckerPrager::project(const Eigen::Matrix3d& F, Case* which) const {
  const double J = F.determinant();
  if (!F.allFinite() || !(J > 0.0))
    throw InputError("Drucker-Prager: deformation gradient with det F = " + std::to_string(J) +
                     " (inverted, flattened or not finite)");
  const RotationSvd svd = rotationSvd(F);
  const Eigen::Vector3d eps = svd.sigma.array().log();
  const double tr = eps.sum();
  auto done = [&](Case c, const Eigen::Vector3d& e) {
    if (which) *which = c;
    return Eigen::Matrix3d(svd.U * e.array().exp().matrix().asDiagonal() * svd.V.transpose());
  };
  if (tr >= 0.0) return done(Case::kSeparated, Eigen::Vector3d::Zero());
  const Eigen::Vector3d dev = eps.array() - tr / 3.0;
  const double dev_norm = dev.norm();
  const double mu = material_.mu(), lambda = material_.lambda();
  // Klar et al. (2016) eq. 27: the distance outside the cone in strain, tau = 2 mu eps +
  // lambda tr(eps) I having ||dev tau|| = 2 mu ||dev eps|| and tr tau = (3 lambda + 2 mu) tr eps.
  const double delta_gamma = dev_norm + (3.0 * lambda + 2.0 * mu) / (2.0 * mu) * tr * alpha_;
  if (delta_gamma <= 0.0) {
    if (which) *which = Case::kElastic;
    return F;
  }
  return done(Case::kSlid, eps - (delta_gamma / dev_norm) * dev);
}

double DruckerPrager::yield(const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d tau = material_.kirchhoffStress(F);
  const double tr = tau.trace();
  return (tau - tr / 3.0 * Eigen::Matrix3d::Identity()).norm() + alpha_ * tr;
}

}  // namespace chs::mpm
